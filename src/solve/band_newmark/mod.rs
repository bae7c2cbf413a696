//! The fast path of the Newmark family for linear systems.
//!
//! [`Newmark`](super::newmark::Newmark) does a step as the textbook writes it, through the
//! general CSR and profile kernels: every product walks column indices and every triangular
//! sweep runs loops of data-dependent length. Per degree of freedom a step is only about 60
//! flops, so index arithmetic, bounds checks and loop overhead, not the flops, set its cost.
//! This integrator does the same arithmetic on storage shaped for the beam:
//!
//! * The step solves for the **increment** Δu = u_{n+1} − u_n, not for u_{n+1}: the same
//!   arithmetic in exact terms, but the solver's relative round-off then falls on Δu, which
//!   the acceleration (Δu − Δt·v)/(βΔt²) amplifies ≈ 1/(βΔtω) rather than 1/(βΔt²ω²) times
//!   (≈ 30× more accurate on the paper beam, `tests/precision.rs`). Its right-hand side is
//!   M·w₁ + C·w₂ − K·u with w₁, w₂ the v and a terms of the history.
//! * M, C and K are stored by **diagonals** of a band of half-width B (3 for Hermite beam
//!   elements): the right-hand side is then one loop over rows whose body reads
//!   3·(2B+1) contiguous streams, which the compiler vectorises.
//! * The factor L·D·Lᵀ of the effective stiffness is stored **by rows of width B** with
//!   1/D; the forward and backward sweeps, which are recurrences and cannot be vectorised,
//!   are fully unrolled for B known at compile time, ordered so the newest unknown enters
//!   last (the critical path per row is one multiply–add), and use fused multiply–add where
//!   the processor has it. For B = 3 (every beam) they carry the last three unknowns in
//!   registers and finish four rows at a time, the Newmark update of those rows as vectors
//!   (`groups.rs`).
//! * The few rows that reach beyond the band (an actuator's body rows reach back to its
//!   feet) keep their extra entries in short side lists.
//! * Loads are sparse (actuators load a handful of DOFs), the dissipation v̄ᵀ·C·v̄ of the
//!   step is optional (and counted in the next step's right-hand side pass, which reads C
//!   anyway), and nothing in a step allocates.
//!
//! On x86-64 the step is compiled twice, for the baseline target and for AVX2 + FMA, and the
//! faster one is chosen at run time when the processor supports it (with AVX-512F, the band
//! right-hand side then takes eight rows at a time). The FMA version rounds
//! differently (a fused multiply–add rounds once), so the two agree to round-off, as does
//! this integrator with `Newmark` (`tests/newmark.rs`).
//!
//! The module holds the integrator's state and the order of a step; the storage is
//! [`crate::linalg::band`], the vector kernels with their scalar twins are in
//! [`crate::simd`], and the files here are the step's parts: coefficients and the
//! proportional form (`coeffs.rs`), the row-by-row sweeps (`sweeps.rs`), the grouped sweeps
//! (`groups.rs`) and the factor runs they read (`factor_runs.rs`), the dense step of small
//! systems (`dense.rs`) and the read-outs (`observe.rs`).

// The step indexes several arrays with one row index on purpose: that is the form the
// vectoriser and the reader both follow.
#![allow(clippy::needless_range_loop)]

use super::newmark::Scheme;
use crate::error::{Error, Result};
use crate::linalg::band::{BandFactor, BandMatrices};
use crate::linalg::{Csr, Skyline};
use crate::simd::band::PeriodicRun;
use crate::simd::update::StepCoeffs;
use crate::simd::{dispatch, has_avx512, has_fma, Builds};
use std::sync::Arc;

mod accurate;
mod coeffs;
mod dense;
mod factor_runs;
mod groups;
mod observe;
mod sweeps;

use coeffs::{step_coeffs, Proportional};
use dense::{DenseLoads, DenseStep, DENSE_LIMIT};
use factor_runs::FactorRun;
use observe::Observations;

/// How the integrator runs. The default is the fastest build the processor has, the
/// three-product right-hand side and no dissipation ledger; the switches that turn a fast
/// path off exist to test and measure it against the simpler one.
#[derive(Clone, Copy, Debug)]
pub struct StepOptions {
    /// The Rayleigh coefficients (a₀ in 1/s, a₁ in s) C was assembled with: the right-hand
    /// side then takes the proportional form where it pays (see
    /// [`BandNewmark::uses_proportional_damping`]).
    pub rayleigh: Option<(f64, f64)>,
    /// Accumulate the energy dissipated by C ([`BandNewmark::dissipated`]).
    pub track_dissipation: bool,
    /// Use the AVX2 + FMA build where the processor has it.
    pub fma: bool,
    /// Use 512-bit vectors for the band right-hand side where the processor has them (and
    /// the system has at most `WIDE_RHS_MAX_DOFS` rows).
    pub avx512: bool,
    /// Read repeating stretches of the matrices and the factor from their pattern.
    pub periodic_runs: bool,
    /// Sweep in groups of four rows where the band allows.
    pub grouped_sweeps: bool,
}

impl Default for StepOptions {
    fn default() -> Self {
        StepOptions {
            rayleigh: None,
            track_dissipation: false,
            fma: true,
            avx512: true,
            periodic_runs: true,
            grouped_sweeps: true,
        }
    }
}

/// K·x formed without the assembled K, for the step's −K·u on fine meshes.
///
/// The assembled stiffness's entries are ~EI/h³ and a smooth displacement cancels them by
/// ~elements⁴, so −K·u from the band loses ε·elements⁴ of the force that drives the smooth
/// modes: on 5,000 beam elements the periodic state the run converges to is then ≈ 6e-3
/// off the exact one. A product through the elements' own rows (Gᵀ(G·u)) cancels only by
/// ~elements² (`crate::assembly::rows`).
pub trait StiffnessProduct: Send + Sync {
    /// z ← z − K·x (x and z of the system's n DOFs).
    fn subtract(&self, x: &[f64], z: &mut [f64]);
    /// xᵀ·K·x.
    fn quadratic(&self, x: &[f64]) -> f64;
}

/// Largest system whose band right-hand side runs on 512-bit vectors. Above it the state
/// streams from main memory, where on an AMD EPYC (Zen 5) VM the 512-bit kernel took
/// twice the 256-bit one's time (the whole step 5 % slower at 4·10⁵ DOFs, 18 % at 2·10⁶,
/// in alternating pairs; 5 % faster at 2·10⁵ and 4 % at 3·10⁵), and on an Intel Xeon VM
/// the two were equal there. Software prefetching and 64-byte-aligned vectors did not
/// change it.
const WIDE_RHS_MAX_DOFS: usize = 300_000;

/// A linear system's Newmark integrator on band storage.
#[derive(Clone)]
pub struct BandNewmark {
    scheme: Scheme,
    dt: f64,
    n: usize,
    b: usize,
    /// M, C, K by diagonals (K for the increment's −K·u_n, C for the dissipation).
    band: BandMatrices,
    /// The factor of the effective stiffness by rows.
    factor: BandFactor,
    /// u_i at B + i, with B zeros before and padding after (see `new`).
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    /// w₁, w₂, padded with B zeros at both ends.
    w1: Vec<f64>,
    w2: Vec<f64>,
    /// Right-hand side then y (forward sweep), padded with B leading zeros.
    z: Vec<f64>,
    /// y/d, then Δu as the backward sweep finishes each row, then, once a row is updated,
    /// the step's mean velocity v̄ (u takes u + Δu); padded with B zeros before and B + 4
    /// after, so that the sweep's and the dense step's dissipation's reads past n are zeros.
    x: Vec<f64>,
    /// Dense load of the step in progress, zero except at the DOFs just loaded.
    load: Vec<f64>,
    touched: Vec<usize>,
    /// F_n, kept for α_f ≠ 0.
    f_prev: Vec<(usize, f64)>,
    fma: bool,
    /// 512-bit vectors for the band right-hand side (within the AVX2 build).
    avx512: bool,
    /// Periodic runs of the band right-hand side for groups of four and of eight rows, of
    /// the factor's rows, and whether the step uses them.
    runs4: Vec<PeriodicRun>,
    runs8: Vec<PeriodicRun>,
    factor_runs: Vec<FactorRun>,
    /// The grouped sweeps' row pairs (`groups.rs`).
    pairs: groups::PairRows,
    use_runs: bool,
    /// Whether the sweeps run in groups of four rows (`groups.rs`) where the band allows.
    use_groups: bool,
    /// For small dense systems (modal-reduced models), the step as dense products.
    dense: Option<DenseStep>,
    /// Registered load patterns b_a (see `set_load_patterns`), K_eff⁻¹·b_a for the dense
    /// step, and the pattern weights of the step in progress (α_f-blended) and of F_n.
    patterns: Vec<Vec<(usize, f64)>>,
    patterns_solved: Vec<Vec<f64>>,
    weights: Vec<f64>,
    weights_prev: Vec<f64>,
    use_weights: bool,
    /// w₁, w₂ already hold the next step's history terms (the update writes them while it
    /// has u, v, a in registers); false after `set_state`.
    w_ready: bool,
    /// Accumulate the dissipated energy Σ Δt·v̄ᵀ·C·v̄ (v̄ each step's mean velocity).
    track_dissipation: bool,
    /// Σ v̄ᵀ·C·v̄ over the steps counted so far (without the factor Δt).
    diss_sum: f64,
    /// `x` holds the v̄ of a step not yet in `diss_sum`: the band step counts it in the next
    /// step's right-hand side pass, which reads C's diagonals anyway, or in `dissipated`.
    diss_pending: bool,
    /// Registered read-outs (see `set_observations`) and their latest values.
    observations: Observations,
    /// The step's coefficients, fixed by the scheme and Δt (and the proportional form).
    coeffs: StepCoeffs,
    /// The proportional form of the right-hand side, when in use.
    proportional: Option<Proportional>,
    /// The right-hand side's −K·(u − a₁·w₂) from a product rather than the band (whose K
    /// is then zero) and the increment refined, when set
    /// ([`BandNewmark::use_stiffness_product`]).
    accurate: Option<accurate::Accurate>,
}

/// The band half-width as a type, so that fixed widths unroll.
trait Width: Copy {
    fn b(self) -> usize;
}
#[derive(Clone, Copy)]
struct Fixed<const B: usize>;
impl<const B: usize> Width for Fixed<B> {
    #[inline(always)]
    fn b(self) -> usize {
        B
    }
}
#[derive(Clone, Copy)]
struct Dynamic(usize);
impl Width for Dynamic {
    #[inline(always)]
    fn b(self) -> usize {
        self.0
    }
}

impl BandNewmark {
    /// Sets up the integrator of M·a + C·v + K·u = F with `scheme` at step Δt (s) and
    /// factorises the effective stiffness. `envelope` must cover the patterns of M, C and K.
    pub fn new(
        m: &Csr,
        c: &Csr,
        k: &Csr,
        envelope: &[usize],
        scheme: Scheme,
        dt: f64,
        options: StepOptions,
    ) -> Result<Self> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(Error::Numerical(format!("time step must be positive, got {dt}")));
        }
        let n = m.dim();
        let s = scheme;
        let mut k_eff = Skyline::<f64>::zeros(envelope.to_vec());
        let [wk, wc, wm] = s.effective_weights(dt);
        k.add_into_skyline(wk, &mut k_eff);
        c.add_into_skyline(wc, &mut k_eff);
        m.add_into_skyline(wm, &mut k_eff);
        let ldlt = k_eff.factorize()?;
        let factor = BandFactor::new(ldlt.clone());
        let b = factor.b;
        let band = BandMatrices::new(m, c, k, b);
        let runs = |lanes| PeriodicRun::find(n, b, [&band.m, &band.c, &band.k], lanes);
        let (runs4, runs8) = (runs(4), runs(8));
        let factor_runs = FactorRun::find(n, b, &factor.l, &factor.d_inv, &factor.long);
        let pairs = groups::PairRows::new(n, b, &factor.l);
        let dense = (n <= DENSE_LIMIT && 2 * b >= n).then(|| DenseStep::new(m, c, k, &ldlt));
        let fma = options.fma && has_fma();
        let plain = step_coeffs(scheme, dt);
        let form = match options.rayleigh {
            Some((a0, a1)) if dense.is_none() => Proportional::detect(&band, n, b, a0, a1, plain),
            _ => None,
        };
        let (proportional, coeffs) = match form {
            Some((p, k)) => (Some(p), k),
            None => (None, plain),
        };
        Ok(BandNewmark {
            scheme,
            dt,
            n,
            b,
            band,
            factor,
            // u_i at index B + i: B zeros before, where the right-hand side's −K·u reads
            // them as the band's shifted copies, and after it zero padding to B past n and to
            // a multiple of four, so dense read-outs run over whole lanes.
            u: vec![0.0; b + (n + b).next_multiple_of(4)],
            v: vec![0.0; n.next_multiple_of(4)],
            a: vec![0.0; n.next_multiple_of(4)],
            w1: vec![0.0; n + 2 * b],
            w2: vec![0.0; n + 2 * b],
            z: vec![0.0; n + b],
            x: vec![0.0; n + 2 * b + 4],
            load: vec![0.0; n],
            touched: Vec::new(),
            f_prev: Vec::new(),
            fma,
            avx512: fma && options.avx512 && has_avx512() && n <= WIDE_RHS_MAX_DOFS,
            runs4,
            runs8,
            factor_runs,
            pairs,
            use_runs: options.periodic_runs,
            use_groups: options.grouped_sweeps,
            dense,
            patterns: Vec::new(),
            patterns_solved: Vec::new(),
            weights: Vec::new(),
            weights_prev: Vec::new(),
            use_weights: false,
            w_ready: false,
            track_dissipation: options.track_dissipation,
            diss_sum: 0.0,
            diss_pending: false,
            observations: Observations::default(),
            coeffs,
            proportional,
            accurate: None,
        })
    }

    /// Takes the right-hand side's stiffness term from `product` instead of the band's
    /// assembled K: −K·(u − a₁·w₂) in the proportional form, where it is the only product
    /// with K (C's a₁·K is folded into it). Declines, changing nothing, where the step does
    /// not run in that form (the three-product form's C·w₂ would keep a₁·K's cancellation)
    /// or runs dense (a reduced system, whose coordinates are not the elements' DOFs).
    pub fn use_stiffness_product(&mut self, product: Arc<dyn StiffnessProduct>) -> bool {
        let Some(p) = &self.proportional else { return false };
        if self.dense.is_some() {
            return false;
        }
        let weights = self.scheme.effective_weights(self.dt);
        let acc = accurate::Accurate::new(product, self.n, weights, p.a0, p.a1);
        let (a0, residual) = (p.a0, p.residual.clone());
        self.band.k.iter_mut().for_each(|k| *k = 0.0);
        self.band.extra.iter_mut().for_each(|e| e.k = 0.0);
        // C's band is read only for the dissipation: it keeps a₀·M + R, and the product
        // gives a₁·v̄ᵀ·K·v̄ (`band_dissipation_from`).
        let stride = self.n + self.b;
        for (c, m) in self.band.c.iter_mut().zip(&self.band.m) {
            *c = a0 * m;
        }
        for e in &mut self.band.extra {
            e.c = a0 * e.m;
        }
        for (i, j, r) in residual {
            if i - j <= self.b {
                self.band.c[(i - j) * stride + i] += r;
            } else if let Some(e) = self.band.extra.iter_mut().find(|e| e.i == i && e.j == j) {
                e.c += r;
            }
        }
        let band = &self.band;
        let runs = |lanes| PeriodicRun::find(self.n, self.b, [&band.m, &band.c, &band.k], lanes);
        (self.runs4, self.runs8) = (runs(4), runs(8));
        self.accurate = Some(acc);
        true
    }

    /// Whether the stiffness term comes from a [`StiffnessProduct`].
    pub fn uses_stiffness_product(&self) -> bool {
        self.accurate.is_some()
    }

    pub fn dt(&self) -> f64 {
        self.dt
    }

    pub fn dim(&self) -> usize {
        self.n
    }

    /// Half-width of the band part of the storage (rows reaching further have side lists).
    pub fn band_width(&self) -> usize {
        self.b
    }

    /// Bytes held by the integrator (matrices, factor, state and work vectors): linear in
    /// the number of DOFs, since everything is stored by band.
    pub fn memory_bytes(&self) -> usize {
        let f = std::mem::size_of::<f64>();
        let (band, factor) = (&self.band, &self.factor);
        let vecs = [&band.m, &band.c, &band.k, &factor.l, &factor.l_tail, &factor.d_inv, &self.u, &self.v, &self.a]
            .iter()
            .chain([&self.w1, &self.w2, &self.z, &self.x, &self.load].iter())
            .map(|v| v.len())
            .sum::<usize>();
        (vecs + self.pairs.len()) * f
            + band.extra.len() * std::mem::size_of::<crate::linalg::band::Extra>()
            + factor.long.len() * std::mem::size_of::<crate::linalg::band::LongRow>()
    }

    /// Whether the step runs as dense products (small dense systems).
    pub fn is_dense(&self) -> bool {
        self.dense.is_some()
    }

    /// Whether the AVX2 + FMA build of the step is in use.
    pub fn uses_fma(&self) -> bool {
        self.fma
    }

    /// Whether the band right-hand side uses 512-bit vectors.
    pub fn uses_avx512(&self) -> bool {
        self.avx512
    }

    /// Whether the right-hand side runs in the proportional form: asked for with
    /// [`StepOptions::rayleigh`], and declined for the dense step (small reduced models) and
    /// where R = C − a₀·M − a₁·K would be more than a few entries a row.
    pub fn uses_proportional_damping(&self) -> bool {
        self.proportional.is_some()
    }

    /// Rows whose right-hand side reads M and C from a periodic run rather than the band
    /// (for the widest kernel this processor runs); zero in the baseline build.
    pub fn periodic_rows(&self) -> usize {
        let runs = if self.avx512 { &self.runs8 } else { &self.runs4 };
        if self.use_runs && self.fma && self.dense.is_none() {
            runs.iter().map(|r| r.end - r.start).sum()
        } else {
            0
        }
    }

    /// Rows whose forward sweep reads the factor from a periodic run rather than the band
    /// (every build, in the grouped sweeps; the backward sweep, which also needs the B rows
    /// below, a few fewer).
    pub fn periodic_factor_rows(&self) -> usize {
        if self.use_runs && self.use_groups && self.dense.is_none() {
            self.factor_runs.iter().map(|r| r.end - r.start).sum()
        } else {
            0
        }
    }

    /// Displacement, velocity and acceleration at the current time.
    pub fn u(&self) -> &[f64] {
        &self.u[self.b..self.b + self.n]
    }
    pub fn v(&self) -> &[f64] {
        &self.v[..self.n]
    }
    pub fn a(&self) -> &[f64] {
        &self.a[..self.n]
    }

    /// Starts from displacement u₀, velocity v₀ and acceleration a₀ (which should be the
    /// consistent one, M⁻¹·(F₀ − C·v₀ − K·u₀)), with load F₀ as sparse pairs.
    pub fn set_state(&mut self, u0: &[f64], v0: &[f64], a0: &[f64], f0: &[(usize, f64)]) {
        self.u[self.b..self.b + self.n].copy_from_slice(u0);
        self.v[..self.n].copy_from_slice(v0);
        self.a[..self.n].copy_from_slice(a0);
        self.w_ready = false;
        self.diss_sum = 0.0;
        self.diss_pending = false;
        self.f_prev.clear();
        self.f_prev.extend_from_slice(f0);
        self.observe_dispatch();
    }

    /// Registers read-outs: row r is gᵣ as sparse pairs (duplicates summed). After
    /// `set_observations`, `set_state` and every step, `observed()[r]` holds
    /// (gᵣᵀu, gᵣᵀv, gᵣᵀa).
    pub fn set_observations(&mut self, rows: &[Vec<(usize, f64)>]) {
        self.observations = Observations::new(self.n, rows);
        self.observe_dispatch();
    }

    /// (gᵣᵀu, gᵣᵀv, gᵣᵀa) of each registered read-out at the current state.
    pub fn observed(&self) -> &[[f64; 3]] {
        self.observations.values()
    }

    /// Registers load patterns b_a (sparse, on the system's DOFs) for `step_weighted`, whose
    /// load is Σ_a b_a·weight_a: the actuators' drives. For a dense system K_eff⁻¹·b_a is
    /// computed once, so a step's load costs n multiply–adds per pattern.
    pub fn set_load_patterns(&mut self, patterns: Vec<Vec<(usize, f64)>>) {
        self.patterns_solved = match &self.dense {
            Some(ops) => patterns.iter().map(|b| ops.solve_pattern(b)).collect(),
            None => Vec::new(),
        };
        self.weights = vec![0.0; patterns.len()];
        self.weights_prev = vec![0.0; patterns.len()];
        self.patterns = patterns;
    }

    /// Sets the weights of F_n (the current load) for α_f schemes; see `set_load_patterns`.
    pub fn set_previous_weights(&mut self, w: &[f64]) {
        self.weights_prev.copy_from_slice(w);
    }

    /// Advances one step to the load F_{n+1} = Σ_a b_a·wₐ of the registered patterns.
    pub fn step_weighted(&mut self, w: &[f64]) {
        assert_eq!(w.len(), self.patterns.len(), "one weight per registered load pattern");
        let af = self.scheme.alpha_f;
        for a in 0..w.len() {
            self.weights[a] = (1.0 - af) * w[a] + af * self.weights_prev[a];
            self.weights_prev[a] = w[a];
        }
        if self.dense.is_none() {
            for (b, &wa) in self.patterns.iter().zip(&self.weights) {
                for &(d, c) in b {
                    self.load[d] += c * wa;
                    self.touched.push(d);
                }
            }
        }
        // F_n of the pattern weights is kept in `weights_prev`; `step` leaves `f_prev` alone.
        self.use_weights = true;
        self.step(&[]);
        self.use_weights = false;
    }

    /// Advances one step to the load F_{n+1} (sparse pairs, duplicates summed).
    pub fn step(&mut self, f_next: &[(usize, f64)]) {
        let af = self.scheme.alpha_f;
        for &(d, f) in f_next {
            self.load[d] += (1.0 - af) * f;
            self.touched.push(d);
        }
        if af != 0.0 && !self.use_weights {
            for &(d, f) in &self.f_prev {
                self.load[d] += af * f;
                self.touched.push(d);
            }
        }
        let k = self.coeffs;
        // The right-hand side consumed (and zeroed) the touched load entries.
        self.dispatch(k);
        self.touched.clear();
        if af != 0.0 && !self.use_weights {
            self.f_prev.clear();
            self.f_prev.extend_from_slice(f_next);
        }
    }

    /// Energy dissipated by C since the start (`set_state` or construction):
    /// Σ Δt·v̄ᵀ·C·v̄ over the steps, v̄ each step's mean velocity (J). Zero unless
    /// [`StepOptions::track_dissipation`] was set.
    pub fn dissipated(&self) -> f64 {
        let mut sum = self.diss_sum;
        if self.diss_pending {
            sum += if self.fma { self.band_dissipation::<true>() } else { self.band_dissipation::<false>() };
        }
        self.dt * sum
    }

    fn observe_dispatch(&mut self) {
        dispatch(self.fma, self, ());
    }

    #[inline(always)]
    fn observe<const FMA: bool>(&mut self) {
        // u, v, a carry zero padding up to a multiple of four.
        self.observations.observe::<FMA>(self.n, [&self.u[self.b..], &self.v, &self.a]);
    }

    fn dispatch(&mut self, k: StepCoeffs) {
        dispatch(self.fma, self, k);
    }

    #[inline(always)]
    fn by_width<const FMA: bool>(&mut self, k: StepCoeffs) {
        self.advance::<FMA>(k);
        self.observe::<FMA>();
    }

    #[inline(always)]
    fn advance<const FMA: bool>(&mut self, k: StepCoeffs) {
        if self.dense.is_some() {
            self.dense_step::<FMA>(k);
            return;
        }
        match self.b {
            0 => self.step_impl::<_, FMA>(Fixed::<0>, k),
            1 => self.step_impl::<_, FMA>(Fixed::<1>, k),
            2 => self.step_impl::<_, FMA>(Fixed::<2>, k),
            3 => self.step_impl::<_, FMA>(Fixed::<3>, k),
            4 => self.step_impl::<_, FMA>(Fixed::<4>, k),
            w => self.step_impl::<_, FMA>(Dynamic(w), k),
        }
    }

    /// A band step: right-hand side, forward and backward sweep with each row's update.
    #[inline(always)]
    fn step_impl<W: Width, const FMA: bool>(&mut self, w: W, k: StepCoeffs) {
        if self.accurate.is_some() {
            self.accurate_step::<W, FMA>(w, k);
            return;
        }
        self.rhs::<W, FMA>(w, k);
        if Self::groups_apply(w.b()) && self.use_groups {
            self.forward_groups::<W, FMA>(w);
            if self.track_dissipation {
                self.backward_groups::<W, FMA, true>(w, k);
            } else {
                self.backward_groups::<W, FMA, false>(w, k);
            }
        } else {
            self.forward::<W, FMA>(w);
            if self.track_dissipation {
                self.backward::<W, FMA, true>(w, k);
            } else {
                self.backward::<W, FMA, false>(w, k);
            }
        }
        self.w_ready = true;
        self.diss_pending = self.track_dissipation;
    }

    /// A dense step: the solve, the update and the step's dissipation.
    #[inline(always)]
    fn dense_step<const FMA: bool>(&mut self, k: StepCoeffs) {
        let (n, b) = (self.n, self.b);
        let ops = self.dense.as_mut().expect("dense step");
        let loads = DenseLoads {
            solved: self.use_weights.then_some((&self.patterns_solved[..], &self.weights[..])),
            touched: &self.touched,
            load: &mut self.load,
        };
        let x = &mut self.x[b..b + n];
        ops.solve::<FMA>(k, self.w_ready, [&self.u[b..b + n], &self.v[..n], &self.a[..n]], x, loads);
        ops.update::<FMA>(k, x, [&mut self.u[b..b + n], &mut self.v[..n], &mut self.a[..n]]);
        self.w_ready = true;
        if self.track_dissipation {
            self.diss_sum += ops.dissipation::<FMA>(&self.x[b..], &mut self.z[..n]);
        }
    }
}

/// A step (`by_width`) in one build, for [`dispatch`].
impl Builds<StepCoeffs> for BandNewmark {
    type Out = ();
    #[inline(always)]
    fn run<const FMA: bool>(&mut self, k: StepCoeffs) {
        self.by_width::<FMA>(k)
    }
}

/// The read-outs (`observe`) in one build, for [`dispatch`].
impl Builds<()> for BandNewmark {
    type Out = ();
    #[inline(always)]
    fn run<const FMA: bool>(&mut self, _: ()) {
        self.observe::<FMA>()
    }
}
