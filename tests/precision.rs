//! The transient against an independent reference in double-double arithmetic (≈ 32
//! digits): the bare paper beam's Newmark response, the OpenSees anchor problem.
//!
//! The reference builds its own element matrices from the beam's data (not beamflow's
//! element code), factorises the band of K_eff = K + γ/(βΔt)·C + M/(βΔt²) and steps the
//! textbook average-acceleration rule, all in double-double, so its own round-off is far
//! below what it checks. On this problem OpenSeesPy agrees with it to 5.3e-10 of the peak
//! and beamflow to 3.9e-9 (1.1e-7 before it solved for the increment; docs/performance.md,
//! "Against OpenSees and an extended-precision reference").

use beamflow::analysis::plan::calibrated_model;
use beamflow::assembly::System;
use beamflow::solve::band_newmark::{BandNewmark, StepOptions};
use beamflow::solve::newmark::{Newmark, Scheme};

mod common;

/// A double-double number hi + lo, |lo| ≤ ½ ulp(hi).
#[derive(Clone, Copy, Debug, Default)]
struct Dd {
    hi: f64,
    lo: f64,
}

fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

fn quick_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

impl Dd {
    fn from(x: f64) -> Self {
        Dd { hi: x, lo: 0.0 }
    }
    fn norm((hi, lo): (f64, f64)) -> Self {
        let (hi, lo) = quick_two_sum(hi, lo);
        Dd { hi, lo }
    }
    fn add(self, y: Dd) -> Dd {
        let (s, e) = two_sum(self.hi, y.hi);
        let (t, f) = two_sum(self.lo, y.lo);
        let (s, e) = quick_two_sum(s, e + t);
        Dd::norm((s, e + f))
    }
    fn neg(self) -> Dd {
        Dd { hi: -self.hi, lo: -self.lo }
    }
    fn sub(self, y: Dd) -> Dd {
        self.add(y.neg())
    }
    fn mul(self, y: Dd) -> Dd {
        let p = self.hi * y.hi;
        let e = self.hi.mul_add(y.hi, -p);
        Dd::norm((p, e + (self.hi * y.lo + self.lo * y.hi)))
    }
    fn div(self, y: Dd) -> Dd {
        let q1 = self.hi / y.hi;
        let r = self.sub(y.mul(Dd::from(q1)));
        let q2 = r.hi / y.hi;
        let r = r.sub(y.mul(Dd::from(q2)));
        let q3 = r.hi / y.hi;
        Dd::norm(quick_two_sum(q1, q2)).add(Dd::from(q3))
    }
}

/// w(t) at node `load_node` of a clamped–clamped beam of `ne` equal Euler–Bernoulli elements
/// (consistent mass, C = a₀·M + a₁·K) under a unit force sin(2π·f·t), stepped from rest.
#[allow(clippy::too_many_arguments)]
fn reference(
    [length, width, thickness, young, density]: [f64; 5],
    ne: usize,
    [a0, a1]: [f64; 2],
    load_node: usize,
    f_hz: f64,
    dt: f64,
    steps: usize,
) -> Vec<f64> {
    let d = Dd::from;
    let h = d(length).div(d(ne as f64));
    let t3 = d(thickness).mul(d(thickness)).mul(d(thickness));
    let ei = d(young).mul(d(width)).mul(t3).div(d(12.0));
    let rho_a = d(density).mul(d(width)).mul(d(thickness));
    let h2 = h.mul(h);
    let kf = ei.div(h2.mul(h));
    let mf = rho_a.mul(h).div(d(420.0));
    // Element matrices in (w₁, θ₁, w₂, θ₂); entries c·h^p.
    let pw = |c: f64, p: usize| -> Dd { [d(c), d(c).mul(h), d(c).mul(h2)][p] };
    let ke: [[Dd; 4]; 4] = [
        [pw(12.0, 0), pw(6.0, 1), pw(-12.0, 0), pw(6.0, 1)],
        [pw(6.0, 1), pw(4.0, 2), pw(-6.0, 1), pw(2.0, 2)],
        [pw(-12.0, 0), pw(-6.0, 1), pw(12.0, 0), pw(-6.0, 1)],
        [pw(6.0, 1), pw(2.0, 2), pw(-6.0, 1), pw(4.0, 2)],
    ]
    .map(|r| r.map(|x| x.mul(kf)));
    let me: [[Dd; 4]; 4] = [
        [pw(156.0, 0), pw(22.0, 1), pw(54.0, 0), pw(-13.0, 1)],
        [pw(22.0, 1), pw(4.0, 2), pw(13.0, 1), pw(-3.0, 2)],
        [pw(54.0, 0), pw(13.0, 1), pw(156.0, 0), pw(-22.0, 1)],
        [pw(-13.0, 1), pw(-3.0, 2), pw(-22.0, 1), pw(4.0, 2)],
    ]
    .map(|r| r.map(|x| x.mul(mf)));
    // Free DOFs: w and θ of nodes 1..ne−1, DOF 2(node − 1) + {0, 1}; band storage of the
    // lower triangle, entry (i, i − t) at [i][t], t ≤ 3.
    let n = 2 * (ne - 1);
    let mut kb = vec![[Dd::default(); 4]; n];
    let mut mb = vec![[Dd::default(); 4]; n];
    for e in 0..ne {
        let dofs: Vec<Option<usize>> = (0..4)
            .map(|l| {
                let node = e + l / 2;
                (node > 0 && node < ne).then(|| 2 * (node - 1) + l % 2)
            })
            .collect();
        for (p, &gp) in dofs.iter().enumerate() {
            for (q, &gq) in dofs.iter().enumerate() {
                if let (Some(i), Some(j)) = (gp, gq) {
                    if j <= i {
                        kb[i][i - j] = kb[i][i - j].add(ke[p][q]);
                        mb[i][i - j] = mb[i][i - j].add(me[p][q]);
                    }
                }
            }
        }
    }
    let cb: Vec<[Dd; 4]> =
        kb.iter().zip(&mb).map(|(k, m)| std::array::from_fn(|t| d(a0).mul(m[t]).add(d(a1).mul(k[t])))).collect();
    let (beta, gamma) = (d(0.25), d(0.5));
    let dtd = d(dt);
    let c0 = d(1.0).div(beta.mul(dtd).mul(dtd));
    let c1 = gamma.div(beta.mul(dtd));
    // LDLᵀ of the band of K_eff.
    let mut l = vec![[Dd::default(); 4]; n];
    let mut dg = vec![Dd::default(); n];
    for i in 0..n {
        let a = |t: usize| kb[i][t].add(c1.mul(cb[i][t])).add(c0.mul(mb[i][t]));
        for t in (1..=3.min(i)).rev() {
            let j = i - t;
            // L(i, j) = (A(i, j) − Σ_k L(i, k)·d_k·L(j, k)) / d_j over k < j within both bands.
            let mut s = a(t);
            for k in j.saturating_sub(3)..j {
                if i - k <= 3 {
                    s = s.sub(l[i][i - k].mul(dg[k]).mul(l[j][j - k]));
                }
            }
            l[i][t] = s.div(dg[j]);
        }
        let mut s = a(0);
        for k in i.saturating_sub(3)..i {
            s = s.sub(l[i][i - k].mul(l[i][i - k]).mul(dg[k]));
        }
        dg[i] = s;
    }
    let band_mul = |b: &[[Dd; 4]], x: &[Dd], y: &mut [Dd]| {
        for i in 0..n {
            let mut s = b[i][0].mul(x[i]);
            for t in 1..=3 {
                if i >= t {
                    s = s.add(b[i][t].mul(x[i - t]));
                }
                if i + t < n {
                    s = s.add(b[i + t][t].mul(x[i + t]));
                }
            }
            y[i] = y[i].add(s);
        }
    };
    let (mut u, mut v, mut a) = (vec![Dd::default(); n], vec![Dd::default(); n], vec![Dd::default(); n]);
    let (mut w1, mut w2, mut x) = (vec![Dd::default(); n], vec![Dd::default(); n], vec![Dd::default(); n]);
    let probe = 2 * (load_node - 1);
    let mut out = Vec::with_capacity(steps);
    for k in 1..=steps {
        // The same f64 load as beamflow's run, converted exactly.
        let f = (2.0 * std::f64::consts::PI * f_hz * (k as f64 * dt)).sin();
        for i in 0..n {
            w1[i] = c0.mul(u[i].add(dtd.mul(v[i]))).add(a[i]);
            w2[i] = c1.mul(u[i]).add(v[i]);
            x[i] = Dd::default();
        }
        x[probe] = d(f);
        band_mul(&mb, &w1, &mut x);
        band_mul(&cb, &w2, &mut x);
        for i in 0..n {
            for t in 1..=3.min(i) {
                x[i] = x[i].sub(l[i][t].mul(x[i - t]));
            }
        }
        for i in 0..n {
            x[i] = x[i].div(dg[i]);
        }
        for i in (0..n).rev() {
            for t in 1..=3 {
                if i + t < n {
                    x[i] = x[i].sub(l[i + t][t].mul(x[i + t]));
                }
            }
        }
        for i in 0..n {
            let a_new = c0.mul(x[i].sub(u[i]).sub(dtd.mul(v[i]))).sub(a[i]);
            v[i] = v[i].add(dtd.mul(d(0.5)).mul(a[i].add(a_new)));
            a[i] = a_new;
            u[i] = x[i];
        }
        out.push(u[probe].hi + u[probe].lo);
    }
    out
}

#[test]
fn transient_agrees_with_a_double_double_reference() {
    let (ne, load_node, f_hz, dt, steps) = (200, 41, 60.0, 1e-4, 4_000);
    let (a0, a1) = (5.29, 9.96e-6);
    let lc = common::bare_beam(ne, [a0, a1]);
    let model = calibrated_model(&lc).unwrap();
    let sys = System::assemble(&model).unwrap();
    let beam = model.beam().unwrap();
    let x_load = beam.mesh.x[load_node];
    let probe = sys.w_at(&model, &beamflow::structure::Location::Beam { x: x_load }, "load").unwrap();
    assert_eq!(probe.len(), 1);
    let probe = probe[0].0;
    // The beam's data as beamflow read them (defaults: 730 × 50 × 5 mm steel).
    let spec = &lc.case.beam;
    let data = [spec.length, spec.width, spec.thickness, spec.youngs_modulus, spec.density];
    let w_ref = reference(data, ne, [a0, a1], load_node, f_hz, dt, steps);

    // The fused step as transient::run takes it (the proportional form of the right-hand
    // side) and with its three band products.
    let fused = |rayleigh| {
        let options = StepOptions { rayleigh, ..StepOptions::default() };
        BandNewmark::new(&sys.m, &sys.c, &sys.k, &sys.envelope, Scheme::average_acceleration(), dt, options).unwrap()
    };
    let (mut fast, mut three) = (fused(Some((a0, a1))), fused(None));
    assert!(fast.uses_proportional_damping());
    let mut textbook = Newmark::new(&sys.m, &sys.c, &sys.k, &sys.envelope, Scheme::average_acceleration(), dt).unwrap();
    let zeros = vec![0.0; sys.n()];
    textbook.initialize(&zeros, &zeros, &zeros, &mut []).unwrap();
    let mut f = zeros.clone();
    let peak = w_ref.iter().fold(0.0f64, |m, w| m.max(w.abs()));
    let (mut err_fast, mut err_three, mut err_textbook) = (0.0f64, 0.0f64, 0.0f64);
    for (k, &w) in w_ref.iter().enumerate() {
        let load = (2.0 * std::f64::consts::PI * f_hz * ((k + 1) as f64 * dt)).sin();
        fast.step(&[(probe, load)]);
        three.step(&[(probe, load)]);
        f[probe] = load;
        textbook.step(&f);
        err_fast = err_fast.max((fast.u()[probe] - w).abs() / peak);
        err_three = err_three.max((three.u()[probe] - w).abs() / peak);
        err_textbook = err_textbook.max((textbook.u[probe] - w).abs() / peak);
        if k == 0 {
            // One step is one solve: the same problem to the solver's round-off.
            assert!((fast.u()[probe] - w).abs() <= 1e-11 * w.abs(), "step 1: {} against {w}", fast.u()[probe]);
        }
    }
    // Measured 3.5e-9 (3.4e-9 with three band products) and 3.8e-9: both steps solve for the increment Δu, so the solver's
    // relative round-off (≈ 1e-13) reaches the acceleration multiplied by ≈ 1/(βΔtω). Had
    // they solved for the whole displacement, it would be multiplied
    // by 1/(βΔt²ω²): 1.14e-7 here.
    assert!(err_fast < 1e-8, "fused step: {err_fast:.3e} of the peak");
    assert!(err_three < 1e-8, "fused step, three products: {err_three:.3e} of the peak");
    assert!(err_textbook < 1e-8, "textbook step: {err_textbook:.3e} of the peak");
}
