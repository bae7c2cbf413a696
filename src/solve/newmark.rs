//! Newmark-family time integration of `M·q̈ + C·q̇ + K·q + f_nl(q, q̇) = F(t)`.
//!
//! One implementation covers Newmark (average and linear acceleration), HHT-α and
//! generalised-α: all are the generalised-α balance
//!
//! M·a_{n+1−α_m} + C·v_{n+1−α_f} + K·u_{n+1−α_f} + f_nl,{n+1−α_f} = F_{n+1−α_f},
//!
//! with x_{n+1−α} = (1−α)·x_{n+1} + α·x_n and the Newmark updates
//! u_{n+1} = u_n + Δt·v_n + Δt²·((½−β)·a_n + β·a_{n+1}),
//! v_{n+1} = v_n + Δt·((1−γ)·a_n + γ·a_{n+1}).
//!
//! For a linear system the effective stiffness
//! K_eff = (1−α_f)·K + (1−α_f)·γ/(βΔt)·C + (1−α_m)/(βΔt²)·M is factorised once and each
//! step is three sparse products and one profile back-substitution, in buffers sized once.
//! Nonlinear discrete elements follow the trial/commit protocol: Newton iterations with the
//! consistent tangent, and only a converged step commits the elements' state.

use crate::error::{Error, Result};
use crate::linalg::{Csr, Skyline, SkylineLdlt};

/// Integration parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scheme {
    pub gamma: f64,
    pub beta: f64,
    pub alpha_m: f64,
    pub alpha_f: f64,
}

impl Scheme {
    /// The weights of K, C and M in the effective stiffness each step factors at step Δt
    /// (s): K_eff = (1 − α_f)·K + (1 − α_f)·γ/(β·Δt)·C + (1 − α_m)/(β·Δt²)·M.
    pub fn effective_weights(&self, dt: f64) -> [f64; 3] {
        [
            1.0 - self.alpha_f,
            (1.0 - self.alpha_f) * self.gamma / (self.beta * dt),
            (1.0 - self.alpha_m) / (self.beta * dt * dt),
        ]
    }

    /// Trapezoidal rule (γ = ½, β = ¼): unconditionally stable, no numerical damping,
    /// second order.
    pub fn average_acceleration() -> Self {
        Scheme { gamma: 0.5, beta: 0.25, alpha_m: 0.0, alpha_f: 0.0 }
    }

    /// γ = ½, β = 1/6: second order, stable for ωΔt < 2√3.
    pub fn linear_acceleration() -> Self {
        Scheme { gamma: 0.5, beta: 1.0 / 6.0, alpha_m: 0.0, alpha_f: 0.0 }
    }

    /// Hilber–Hughes–Taylor with α ∈ [0, 1/3]: damps the poorly resolved high modes.
    pub fn hht(alpha: f64) -> Self {
        Scheme { gamma: 0.5 + alpha, beta: 0.25 * (1.0 + alpha).powi(2), alpha_m: 0.0, alpha_f: alpha }
    }

    /// Chung–Hulbert generalised-α with high-frequency spectral radius ρ∞ ∈ [0, 1].
    pub fn generalized_alpha(rho_inf: f64) -> Self {
        let alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
        let alpha_f = rho_inf / (rho_inf + 1.0);
        let gamma = 0.5 - alpha_m + alpha_f;
        Scheme { gamma, beta: 0.25 * (1.0 - alpha_m + alpha_f).powi(2), alpha_m, alpha_f }
    }

    /// Largest stable step for an undamped mode of circular frequency ω, if the scheme is
    /// only conditionally stable.
    pub fn critical_step(&self, omega_max: f64) -> Option<f64> {
        if 2.0 * self.beta >= self.gamma && self.gamma >= 0.5 && self.alpha_m == 0.0 {
            None
        } else if self.alpha_m == 0.0 && self.alpha_f == 0.0 {
            Some(1.0 / (omega_max * (0.5 * self.gamma - self.beta).sqrt()))
        } else {
            None
        }
    }
}

/// A discrete element with a nonlinear force law, e.g. a hardening spring.
///
/// The integrator asks for the force at trial states during Newton iterations and calls
/// `commit` once a step has converged; an element with internal state (plasticity,
/// hysteresis) keeps a committed copy and evaluates trials from it, so a rejected trial
/// leaves no trace.
pub trait NonlinearElement {
    /// The global DOFs the element acts on.
    fn dofs(&self) -> &[usize];
    /// Internal force (on the element's DOFs, same order), its tangent ∂f/∂u and ∂f/∂v
    /// (row-major, n×n), at trial displacements u and velocities v.
    fn trial(&mut self, u: &[f64], v: &[f64], force: &mut [f64], k_t: &mut [f64], c_t: &mut [f64]);
    /// Accepts the last trial state.
    fn commit(&mut self);
}

/// Newton settings for nonlinear steps.
#[derive(Clone, Copy, Debug)]
pub struct NewtonSettings {
    /// Converged when the residual norm falls below `tol`·(norm of the step's load).
    pub tol: f64,
    pub max_iter: usize,
}

impl Default for NewtonSettings {
    fn default() -> Self {
        NewtonSettings { tol: 1e-10, max_iter: 30 }
    }
}

/// Statistics of the Newton iterations of a run.
#[derive(Clone, Copy, Debug, Default)]
pub struct NewtonStats {
    pub steps: usize,
    pub iterations: usize,
    pub max_iterations_in_a_step: usize,
}

/// The consistent initial acceleration a₀ = M⁻¹·(F₀ − C·v₀ − K·u₀), F₀ as sparse pairs;
/// zero without a solve when the right-hand side is zero.
pub fn consistent_acceleration(
    m: &Csr,
    c: &Csr,
    k: &Csr,
    envelope: &[usize],
    u0: &[f64],
    v0: &[f64],
    f0: &[(usize, f64)],
) -> Result<Vec<f64>> {
    let mut r = vec![0.0; m.dim()];
    for &(d, f) in f0 {
        r[d] += f;
    }
    c.mul_vec_add(-1.0, v0, &mut r);
    k.mul_vec_add(-1.0, u0, &mut r);
    solve_mass(m, envelope, r)
}

/// M⁻¹·r for the initial acceleration (zero without a solve when r is zero).
fn solve_mass(m: &Csr, envelope: &[usize], mut r: Vec<f64>) -> Result<Vec<f64>> {
    if r.iter().all(|&x| x == 0.0) {
        return Ok(r);
    }
    let mut ms = Skyline::zeros(envelope.to_vec());
    m.add_into_skyline(1.0, &mut ms);
    let mf = ms.factorize().map_err(|e| Error::Numerical(format!("initial acceleration: {e}")))?;
    mf.solve_in_place(&mut r);
    Ok(r)
}

/// The integrator state and its workspace.
pub struct Newmark<'a> {
    m: &'a Csr,
    c: &'a Csr,
    k: &'a Csr,
    scheme: Scheme,
    dt: f64,
    k_eff: Skyline<f64>,
    factor: SkylineLdlt<f64>,
    /// Displacement, velocity, acceleration at the current time.
    pub u: Vec<f64>,
    pub v: Vec<f64>,
    pub a: Vec<f64>,
    f_prev: Vec<f64>,
    rhs: Vec<f64>,
    w1: Vec<f64>,
    w2: Vec<f64>,
    pub newton: NewtonStats,
}

impl<'a> Newmark<'a> {
    /// Sets up the integrator and factorises the effective stiffness. `envelope` must cover
    /// the pattern of M, C, K and of any nonlinear element's DOFs.
    pub fn new(m: &'a Csr, c: &'a Csr, k: &'a Csr, envelope: &[usize], scheme: Scheme, dt: f64) -> Result<Self> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(Error::Numerical(format!("time step must be positive, got {dt}")));
        }
        let n = m.dim();
        let s = scheme;
        let mut k_eff = Skyline::zeros(envelope.to_vec());
        let [wk, wc, wm] = s.effective_weights(dt);
        k.add_into_skyline(wk, &mut k_eff);
        c.add_into_skyline(wc, &mut k_eff);
        m.add_into_skyline(wm, &mut k_eff);
        let factor = k_eff.factorize()?;
        Ok(Newmark {
            m,
            c,
            k,
            scheme,
            dt,
            k_eff,
            factor,
            u: vec![0.0; n],
            v: vec![0.0; n],
            a: vec![0.0; n],
            f_prev: vec![0.0; n],
            rhs: vec![0.0; n],
            w1: vec![0.0; n],
            w2: vec![0.0; n],
            newton: NewtonStats::default(),
        })
    }

    pub fn dt(&self) -> f64 {
        self.dt
    }

    pub fn scheme(&self) -> Scheme {
        self.scheme
    }

    /// Sets the initial state and the consistent initial acceleration
    /// a₀ = M⁻¹·(F₀ − C·v₀ − K·u₀ − f_nl(u₀, v₀)).
    pub fn initialize(
        &mut self,
        u0: &[f64],
        v0: &[f64],
        f0: &[f64],
        elements: &mut [&mut dyn NonlinearElement],
    ) -> Result<()> {
        self.u.copy_from_slice(u0);
        self.v.copy_from_slice(v0);
        self.f_prev.copy_from_slice(f0);
        let mut r = f0.to_vec();
        self.c.mul_vec_add(-1.0, v0, &mut r);
        self.k.mul_vec_add(-1.0, u0, &mut r);
        for el in elements.iter_mut() {
            let ue: Vec<f64> = el.dofs().iter().map(|&d| u0[d]).collect();
            let ve: Vec<f64> = el.dofs().iter().map(|&d| v0[d]).collect();
            let (f, _, _) = eval_element(&mut **el, &ue, &ve);
            for (i, &d) in el.dofs().iter().enumerate() {
                r[d] -= f[i];
            }
            el.commit();
        }
        let a0 = solve_mass(self.m, self.k_eff.first(), r)?;
        self.a.copy_from_slice(&a0);
        Ok(())
    }

    /// Builds the known part of the balance at t_{n+1−α_f} for the increment Δu = u_{n+1} − u_n
    /// into `self.rhs` (everything but K_eff·Δu), for load F_{n+1} = `f_next`: the right-hand
    /// side of the whole displacement less K_eff·u_n, so M and C act on the v and a terms
    /// only and −K·u_n stands in their u terms' place. The same step in exact arithmetic;
    /// in floating point the solver's relative error then falls on Δu rather than on u,
    /// which a_{n+1} = (Δu − Δt·v_n)/(βΔt²) − … amplifies ≈ 1/(βΔtω) rather than
    /// 1/(βΔt²ω²) times (`tests/precision.rs`).
    // Eight arrays advance in lockstep: one row index reads as the textbook formula does.
    #[allow(clippy::needless_range_loop)]
    fn build_rhs(&mut self, f_next: &[f64]) {
        let s = self.scheme;
        let dt = self.dt;
        let (am, af, g, b) = (s.alpha_m, s.alpha_f, s.gamma, s.beta);
        let c0 = (1.0 - am) / (b * dt * dt);
        let ca = (1.0 - am) * (0.5 / b - 1.0) - am;
        for i in 0..self.u.len() {
            self.rhs[i] = (1.0 - af) * f_next[i] + af * self.f_prev[i];
            // M-part: (1−α_m)·[Δt·v_n/(βΔt²) + (1/(2β) − 1)·a_n] − α_m·a_n
            self.w1[i] = c0 * (dt * self.v[i]) + ca * self.a[i];
            // C-part: (1−α_f)·[−(1 − γ/β)·v_n − Δt(1 − γ/(2β))·a_n] − α_f·v_n
            self.w2[i] =
                (1.0 - af) * (-(1.0 - g / b) * self.v[i] - dt * (1.0 - 0.5 * g / b) * self.a[i]) - af * self.v[i];
        }
        self.m.mul_vec_add(1.0, &self.w1, &mut self.rhs);
        self.c.mul_vec_add(1.0, &self.w2, &mut self.rhs);
        // −α_f·K·u_n of the balance and −(1−α_f)·K·u_n of K_eff·u_n.
        self.k.mul_vec_add(-1.0, &self.u, &mut self.rhs);
    }

    /// Updates u, v and a from the increment Δu held in `w1` and commits them.
    fn update(&mut self, f_next: &[f64]) {
        let s = self.scheme;
        let dt = self.dt;
        for i in 0..self.u.len() {
            let du = self.w1[i];
            let a_new = (du - dt * self.v[i]) / (s.beta * dt * dt) - (0.5 / s.beta - 1.0) * self.a[i];
            self.v[i] += dt * ((1.0 - s.gamma) * self.a[i] + s.gamma * a_new);
            self.a[i] = a_new;
            self.u[i] += du;
        }
        self.f_prev.copy_from_slice(f_next);
    }

    /// Advances one step of a linear system to the load `f_next` = F(t_{n+1}).
    pub fn step(&mut self, f_next: &[f64]) {
        self.build_rhs(f_next);
        self.factor.solve_in_place(&mut self.rhs);
        std::mem::swap(&mut self.w1, &mut self.rhs);
        self.update(f_next);
    }

    /// Advances one step with nonlinear elements, by Newton iterations on Δu with the
    /// consistent tangent K_eff + (1−α_f)·(K_t + γ/(βΔt)·C_t).
    pub fn step_nonlinear(
        &mut self,
        f_next: &[f64],
        elements: &mut [&mut dyn NonlinearElement],
        settings: NewtonSettings,
    ) -> Result<()> {
        let s = self.scheme;
        let dt = self.dt;
        let n = self.u.len();
        // Element forces at the committed state (the α_f-weighted old part).
        let mut f_old = vec![0.0; n];
        for el in elements.iter_mut() {
            let ue: Vec<f64> = el.dofs().iter().map(|&d| self.u[d]).collect();
            let ve: Vec<f64> = el.dofs().iter().map(|&d| self.v[d]).collect();
            let (f, _, _) = eval_element(&mut **el, &ue, &ve);
            for (i, &d) in el.dofs().iter().enumerate() {
                f_old[d] += f[i];
            }
        }
        self.build_rhs(f_next);
        let rhs = self.rhs.clone();
        let scale = rhs.iter().map(|x| x * x).sum::<f64>().sqrt().max(f64::MIN_POSITIVE);
        // Predictor: the linear step's increment.
        let mut du = rhs.clone();
        self.factor.solve_in_place(&mut du);
        let mut iters = 0;
        loop {
            let u_new: Vec<f64> = (0..n).map(|i| self.u[i] + du[i]).collect();
            // v_{n+1}(Δu) from the Newmark relations.
            let v_new: Vec<f64> = (0..n)
                .map(|i| {
                    let a_new = (du[i] - dt * self.v[i]) / (s.beta * dt * dt) - (0.5 / s.beta - 1.0) * self.a[i];
                    self.v[i] + dt * ((1.0 - s.gamma) * self.a[i] + s.gamma * a_new)
                })
                .collect();
            let mut res = vec![0.0; n];
            self.k_eff.mul_vec(&du, &mut res);
            for i in 0..n {
                res[i] += s.alpha_f * f_old[i] - rhs[i];
            }
            let mut jac = self.k_eff.clone();
            for el in elements.iter_mut() {
                let dofs = el.dofs().to_vec();
                let ue: Vec<f64> = dofs.iter().map(|&d| u_new[d]).collect();
                let ve: Vec<f64> = dofs.iter().map(|&d| v_new[d]).collect();
                let (f, kt, ct) = eval_element(&mut **el, &ue, &ve);
                let ne = dofs.len();
                for a in 0..ne {
                    res[dofs[a]] += (1.0 - s.alpha_f) * f[a];
                    for b in 0..=a {
                        let t = (1.0 - s.alpha_f) * (kt[a * ne + b] + s.gamma / (s.beta * dt) * ct[a * ne + b]);
                        // Symmetric tangents only (LDLᵀ): each pair once.
                        jac.add(dofs[a], dofs[b], t);
                    }
                }
            }
            let rnorm = res.iter().map(|x| x * x).sum::<f64>().sqrt();
            if rnorm <= settings.tol * scale {
                break;
            }
            if iters >= settings.max_iter {
                return Err(Error::Numerical(format!(
                    "Newton did not converge in {} iterations at t step {} (residual {:.3e} of load {:.3e})",
                    settings.max_iter,
                    self.newton.steps + 1,
                    rnorm,
                    scale
                )));
            }
            let jf = jac.factorize()?;
            jf.solve_in_place(&mut res);
            for i in 0..n {
                du[i] -= res[i];
            }
            iters += 1;
        }
        self.w1.copy_from_slice(&du);
        self.update(f_next);
        for el in elements.iter_mut() {
            el.commit();
        }
        self.newton.steps += 1;
        self.newton.iterations += iters;
        self.newton.max_iterations_in_a_step = self.newton.max_iterations_in_a_step.max(iters);
        Ok(())
    }
}

fn eval_element(el: &mut dyn NonlinearElement, u: &[f64], v: &[f64]) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let ne = el.dofs().len();
    let mut f = vec![0.0; ne];
    let mut kt = vec![0.0; ne * ne];
    let mut ct = vec![0.0; ne * ne];
    el.trial(u, v, &mut f, &mut kt, &mut ct);
    (f, kt, ct)
}
