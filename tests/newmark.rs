//! The time integrator against exact single-DOF solutions, energy conservation and
//! measured convergence order.

use beamflow::linalg::Csr;
use beamflow::solve::newmark::{Newmark, NewtonSettings, NonlinearElement, Scheme};

mod common;

fn scalar(v: f64) -> Csr {
    Csr::from_triplets(1, &[(0, 0, v)])
}

/// max |xᵢ|.
fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

/// max |xᵢ − yᵢ|.
fn max_diff(x: &[f64], y: &[f64]) -> f64 {
    x.iter().zip(y).fold(0.0f64, |m, (p, q)| m.max((p - q).abs()))
}

/// Exact response of m·ẍ + c·ẋ + k·x = F₀·sin(Ωt) from rest.
fn sdof_exact(m: f64, c: f64, k: f64, f0: f64, om: f64, t: f64) -> f64 {
    let wn = (k / m).sqrt();
    let zeta = c / (2.0 * m * wn);
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let x = f0 / ((k - m * om * om).powi(2) + (c * om).powi(2)).sqrt();
    let phi = (c * om).atan2(k - m * om * om);
    let a = x * phi.sin();
    let b = (zeta * wn * a - x * om * phi.cos()) / wd;
    x * (om * t - phi).sin() + (-zeta * wn * t).exp() * (a * (wd * t).cos() + b * (wd * t).sin())
}

/// Max error over [0, t_end] of a scheme at step dt.
fn sdof_error(scheme: Scheme, dt: f64) -> f64 {
    let (m, c, k, f0, om) = (0.315, 200.0 * 0.05, 3.0e5, 2.0, 2.0 * std::f64::consts::PI * 60.0);
    let (mm, cm, km) = (scalar(m), scalar(c), scalar(k));
    let mut nm = Newmark::new(&mm, &cm, &km, &[0], scheme, dt).unwrap();
    nm.initialize(&[0.0], &[0.0], &[0.0], &mut []).unwrap();
    let steps = (0.1 / dt).round() as usize;
    let mut err = 0.0f64;
    let mut amp = 0.0f64;
    for s in 1..=steps {
        let t = s as f64 * dt;
        nm.step(&[f0 * (om * t).sin()]);
        let x = sdof_exact(m, c, k, f0, om, t);
        err = err.max((nm.u[0] - x).abs());
        amp = amp.max(x.abs());
    }
    err / amp
}

#[test]
fn forced_damped_oscillator_matches_exact_solution_at_second_order() {
    for scheme in [
        Scheme::average_acceleration(),
        Scheme::linear_acceleration(),
        Scheme::hht(0.1),
        Scheme::generalized_alpha(0.8),
    ] {
        let errs: Vec<f64> = [2e-4, 1e-4, 5e-5, 2.5e-5].iter().map(|&dt| sdof_error(scheme, dt)).collect();
        assert!(errs[3] < 2e-3, "{scheme:?}: error {:e} at the finest step", errs[3]);
        for w in errs.windows(2) {
            let order = (w[0] / w[1]).log2();
            assert!((1.85..2.2).contains(&order), "{scheme:?}: observed order {order:.3}, errors {errs:?}");
        }
    }
}

#[test]
fn steady_amplitude_and_phase_match_the_exact_response() {
    // Late in the run the homogeneous part has died out; compare amplitude and phase of the
    // last period by projection on sin and cos.
    let (m, c, k, f0, om) = (1.0, 4.0, 1.0e4, 1.0, 70.0);
    let (mm, cm, km) = (scalar(m), scalar(c), scalar(k));
    let period = 2.0 * std::f64::consts::PI / om;
    let n = 2000;
    let dt = period / n as f64;
    let mut nm = Newmark::new(&mm, &cm, &km, &[0], Scheme::average_acceleration(), dt).unwrap();
    nm.initialize(&[0.0], &[0.0], &[0.0], &mut []).unwrap();
    let periods = 150;
    let (mut s, mut co) = (0.0, 0.0);
    for step in 1..=periods * n {
        let t = step as f64 * dt;
        nm.step(&[f0 * (om * t).sin()]);
        if step > (periods - 1) * n {
            s += nm.u[0] * (om * t).sin() * 2.0 / n as f64;
            co += nm.u[0] * (om * t).cos() * 2.0 / n as f64;
        }
    }
    let amp = (s * s + co * co).sqrt();
    let phase = (-co).atan2(s);
    let x = f0 / ((k - m * om * om).powi(2) + (c * om).powi(2)).sqrt();
    let phi = (c * om).atan2(k - m * om * om);
    assert!((amp - x).abs() < 1e-5 * x, "amplitude {amp} vs {x}");
    assert!((phase - phi).abs() < 1e-5, "phase {phase} vs {phi}");
}

#[test]
fn average_acceleration_conserves_energy_of_free_vibration_to_round_off() {
    // A 3-DOF undamped chain released from a displaced state.
    let k = Csr::from_triplets(
        3,
        &[(0, 0, 2e4), (0, 1, -1e4), (1, 0, -1e4), (1, 1, 2e4), (1, 2, -1e4), (2, 1, -1e4), (2, 2, 1e4)],
    );
    let m = Csr::from_triplets(3, &[(0, 0, 1.0), (1, 1, 2.0), (2, 2, 0.5)]);
    let c = Csr::zeros(3);
    let env = [0, 0, 1];
    let mut nm = Newmark::new(&m, &c, &k, &env, Scheme::average_acceleration(), 1e-3).unwrap();
    nm.initialize(&[0.01, -0.02, 0.03], &[0.0, 0.5, 0.0], &[0.0; 3], &mut []).unwrap();
    let energy = |nm: &Newmark| 0.5 * m.bilinear(&nm.v, &nm.v) + 0.5 * k.bilinear(&nm.u, &nm.u);
    let e0 = energy(&nm);
    let mut worst = 0.0f64;
    for _ in 0..20000 {
        nm.step(&[0.0; 3]);
        worst = worst.max((energy(&nm) - e0).abs() / e0);
    }
    assert!(worst < 1e-12, "energy drift {worst:e}");
    // HHT damps it, as it should.
    let mut hht = Newmark::new(&m, &c, &k, &env, Scheme::hht(0.3), 1e-3).unwrap();
    hht.initialize(&[0.01, -0.02, 0.03], &[0.0, 0.5, 0.0], &[0.0; 3], &mut []).unwrap();
    for _ in 0..20000 {
        hht.step(&[0.0; 3]);
    }
    assert!(energy(&hht) < 0.9 * e0);
}

/// A hardening spring f = k₁u + k₃u³ from DOF 0 to the ground.
struct CubicSpring {
    dofs: [usize; 1],
    k1: f64,
    k3: f64,
    commits: usize,
}

impl NonlinearElement for CubicSpring {
    fn dofs(&self) -> &[usize] {
        &self.dofs
    }
    fn trial(&mut self, u: &[f64], _v: &[f64], force: &mut [f64], k_t: &mut [f64], _c_t: &mut [f64]) {
        force[0] = self.k1 * u[0] + self.k3 * u[0].powi(3);
        k_t[0] = self.k1 + 3.0 * self.k3 * u[0] * u[0];
    }
    fn commit(&mut self) {
        self.commits += 1;
    }
}

fn cubic_run(dt: f64) -> (f64, usize, usize) {
    let m = scalar(0.5);
    let c = Csr::zeros(1);
    let k = Csr::zeros(1);
    let mut spring = CubicSpring { dofs: [0], k1: 1.0e3, k3: 4.0e7, commits: 0 };
    let mut nm = Newmark::new(&m, &c, &k, &[0], Scheme::average_acceleration(), dt).unwrap();
    let u0 = 0.01;
    nm.initialize(&[u0], &[0.0], &[0.0], &mut [&mut spring]).unwrap();
    let energy = |u: f64, v: f64| 0.25 * v * v + 0.5 * 1.0e3 * u * u + 0.25 * 4.0e7 * u.powi(4);
    let e0 = energy(u0, 0.0);
    let mut worst = 0.0f64;
    let steps = (0.5 / dt).round() as usize;
    for _ in 0..steps {
        nm.step_nonlinear(&[0.0], &mut [&mut spring], NewtonSettings::default()).unwrap();
        worst = worst.max((energy(nm.u[0], nm.v[0]) - e0).abs() / e0);
    }
    (worst, nm.newton.max_iterations_in_a_step, spring.commits)
}

#[test]
fn newton_converges_and_cubic_spring_energy_is_conserved() {
    let (e1, it1, commits) = cubic_run(2e-4);
    let (e2, _, _) = cubic_run(1e-4);
    assert!((1..=8).contains(&it1), "Newton took {it1} iterations in a step");
    assert_eq!(commits, (0.5f64 / 2e-4).round() as usize + 1, "one commit per converged step (+ the initial state)");
    assert!(e1 < 1e-3, "energy error {e1:e}");
    // The trapezoidal rule's energy error for a nonlinear spring is O(Δt²) and does not drift.
    let order = (e1 / e2).log2();
    assert!(order > 1.7, "energy error order {order:.2} ({e1:e} → {e2:e})");
}

#[test]
fn newton_reports_failure_instead_of_returning_garbage() {
    let m = scalar(1.0);
    let z = Csr::zeros(1);
    let mut spring = CubicSpring { dofs: [0], k1: 1.0, k3: 1.0e9, commits: 0 };
    let mut nm = Newmark::new(&m, &z, &z, &[0], Scheme::average_acceleration(), 1e-2).unwrap();
    nm.initialize(&[0.0], &[0.0], &[0.0], &mut [&mut spring]).unwrap();
    let r = nm.step_nonlinear(&[1.0e6], &mut [&mut spring], NewtonSettings { tol: 1e-14, max_iter: 2 });
    assert!(r.unwrap_err().to_string().contains("Newton"));
}

/// The fast integrator against the textbook step, on the coupled paper beam with a frame
/// actuator (band storage; the frame's body rows reach back over the leg span, so the long
/// rows are exercised) and on its modal-reduced model (15 dense DOFs: the dense path), for
/// schemes with and without α_f, with each build. A 204-element mesh (406 DOFs, not a
/// multiple of eight or four) also takes the vector kernels' partial groups; a sensor near
/// the far end ends the factor's periodic run inside the matrix; an inertial actuator ahead
/// of the frame moves the frame's long rows off the bounds of the sweeps' groups of four.
#[test]
fn fast_integrator_matches_textbook_step_to_round_off() {
    use beamflow::analysis::plan::calibrated_model;
    use beamflow::analysis::reduction::{self, Cutoff, ReductionSettings};
    use beamflow::assembly::System;
    use beamflow::case::LoadedCase;
    use beamflow::solve::band_newmark::{BandNewmark, StepOptions};
    let text =
        "[[actuator]]\ntype = \"frame\"\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n";
    let lc = LoadedCase::from_str(text, "fused.toml", std::env::temp_dir()).unwrap();
    let model = calibrated_model(&lc).unwrap();
    let full = System::assemble(&model).unwrap();
    let rs = ReductionSettings {
        cutoff: Cutoff::HarmonicFactor(5.0),
        static_correction: true,
        error_estimate: false,
        modal_damping: None,
    };
    let hz = reduction::cutoff_hz(&model, &rs, 9).unwrap();
    let (red, _) = reduction::reduce(&model, &full, &rs, hz).unwrap();
    // The frame case with more in its file, assembled.
    // With the Rayleigh coefficients the case chose for its own mesh (from that mesh's modes).
    let system = |before: &str, after: &str| {
        let lc = LoadedCase::from_str(&format!("{before}{text}{after}"), "case.toml", std::env::temp_dir()).unwrap();
        let model = calibrated_model(&lc).unwrap();
        (System::assemble(&model).unwrap(), (model.rayleigh().a0, model.rayleigh().a1))
    };
    let (odd, odd_rayleigh) = system("[beam.mesh]\nelements = 203\n", "");
    assert_eq!(odd.n() % 8, 6, "{}", odd.n());
    // A sensor near the far end makes a node there, so the elements past it are shorter and
    // the factor's periodic run ends inside the matrix rather than at its last row.
    let (ends, ends_rayleigh) = system("", "[[sensor]]\nname = \"tip\"\nx = 0.68\n");
    // An inertial actuator's one body DOF ahead of the frame shifts the frame's long rows
    // by one: they then start and end inside groups of four rows, not on their bounds.
    let inertial = "[[actuator]]\ntype = \"inertial\"\nx_e = 0.05\n[actuator.voltage]\nkind = \"sine\"\n\
                    amplitude = 12.0\nfrequency = 60.0\n";
    let (two, two_rayleigh) = system("", inertial);
    let leg_rows = |sys: &System| (0..sys.n()).filter(|&i| i - sys.envelope[i] > 10).collect::<Vec<_>>();
    assert_eq!(leg_rows(&full), [104, 105]);
    assert_eq!(leg_rows(&two), [105, 106]);
    let full_rayleigh = (model.rayleigh().a0, model.rayleigh().a1);
    for (sys, dense, (a0, a1)) in [
        (&full, false, full_rayleigh),
        (&odd, false, odd_rayleigh),
        (&ends, false, ends_rayleigh),
        (&two, false, two_rayleigh),
        (&red, true, full_rayleigh),
    ] {
        let n = sys.n();
        let drive = sys.drives[0].clone();
        // (Linear acceleration is only conditionally stable: this mesh's top modes need
        // Δt < 1e-7 s.)
        for scheme in [Scheme::average_acceleration(), Scheme::hht(0.1), Scheme::generalized_alpha(0.8)] {
            // 0: the best build this processor has (AVX-512 right-hand side where present),
            // 1: AVX2 + FMA only, 2: the baseline build.
            for build in 0..3 {
                let fma = build < 2;
                let dt = 1.0 / 60.0 / 200.0;
                let mut slow = Newmark::new(&sys.m, &sys.c, &sys.k, &sys.envelope, scheme, dt).unwrap();
                // An integrator of this build: 0 the best the processor has, 1 AVX2 + FMA
                // only, 2 the baseline.
                // All of them in the proportional form of the right-hand side (the beam's
                // Rayleigh damping; the frame's dashpots, masses and springs as R), which
                // the band step takes and the dense step declines.
                let build_options =
                    StepOptions { rayleigh: Some((a0, a1)), fma, avx512: build == 0, ..StepOptions::default() };
                let with = |options: StepOptions| {
                    let nm = BandNewmark::new(&sys.m, &sys.c, &sys.k, &sys.envelope, scheme, dt, options).unwrap();
                    assert_eq!(nm.uses_proportional_damping(), !dense && options.rayleigh.is_some(), "{n} DOFs");
                    nm
                };
                let integrator = || with(build_options);
                let tracked = StepOptions { track_dissipation: true, ..build_options };
                let mut fast = with(tracked);
                assert_eq!(fast.is_dense(), dense, "{n} DOFs");
                // The same build without the dissipation (which then skips v̄): the state must
                // come out bit for bit the same.
                let mut plain = integrator();
                // The same build with its fast paths switched off: streaming M, C, K and the
                // factor from the band in every row instead of a uniform mesh's periodic
                // runs, which must give the same bits, dissipation included; and sweeping row
                // by row instead of in grouped pairs of rows, with and without the runs,
                // which must agree with each other to the bit and with the grouped sweeps to
                // round-off (the pairs substitute one row into the other).
                let reference = |periodic_runs: bool, grouped_sweeps: bool| {
                    with(StepOptions { periodic_runs, grouped_sweeps, ..tracked })
                };
                let mut no_runs = reference(false, true);
                let mut by_rows = [reference(true, false), reference(false, false)];
                // And the three-product right-hand side, to round-off.
                let three_options = StepOptions { rayleigh: None, ..tracked };
                let mut three = with(three_options);
                if fma && !dense {
                    assert!(fast.periodic_rows() > n / 2, "{n} DOFs: only {} periodic rows", fast.periodic_rows());
                }
                if !dense {
                    // The factor converges to its periodic rows only far from the ends and the
                    // actuator (≈ 50 of 400 rows here), but the runs must be exercised.
                    assert!(fast.periodic_factor_rows() >= 32, "{n} DOFs: {}", fast.periodic_factor_rows());
                }
                // Read-outs: every link's stretch and foot (dense rows in the reduced model),
                // the drive, and one long row over every third DOF (dense in both).
                let mut rows: Vec<Vec<(usize, f64)>> =
                    sys.links.iter().flat_map(|l| [l.stretch.clone(), l.foot.clone()]).collect();
                rows.push(drive.clone());
                rows.push((0..n).step_by(3).map(|d| (d, 1.0 + 0.1 * d as f64)).collect());
                fast.set_observations(&rows);
                let zeros = vec![0.0; n];
                slow.initialize(&zeros, &zeros, &zeros, &mut []).unwrap();
                fast.set_state(&zeros, &zeros, &zeros, &[]);
                plain.set_state(&zeros, &zeros, &zeros, &[]);
                for other in [&mut no_runs, &mut three].into_iter().chain(&mut by_rows) {
                    other.set_state(&zeros, &zeros, &zeros, &[]);
                }
                let mut f = vec![0.0; n];
                // Worst relative difference of u, v and a over the run.
                let (mut worst, mut worst_diss, mut d_slow) = ([0.0f64; 3], 0.0f64, 0.0);
                // The same for the grouped sweeps against the row-by-row ones, and for the
                // proportional form against the three-product one.
                let (mut worst_rows, mut worst_three) = ([0.0f64; 3], [0.0f64; 3]);
                for step in 1..=600 {
                    let fp = 46.8 * (2.0 * std::f64::consts::PI * 60.0 * step as f64 * dt).sin();
                    let sparse: Vec<(usize, f64)> = drive.iter().map(|&(d, c)| (d, c * fp)).collect();
                    f.iter_mut().for_each(|x| *x = 0.0);
                    for &(d, v) in &sparse {
                        f[d] += v;
                    }
                    let v_old = slow.v.clone();
                    slow.step(&f);
                    fast.step(&sparse);
                    plain.step(&sparse);
                    // One step from the same state, before round-off has had steps to grow.
                    // The grouped sweeps against the row-by-row ones: to 1e-12 of the largest
                    // entry of Δu (measured ≤ 2.3e-14, the largest where Δu is near a turning
                    // point; one pair multiplier off by 1e-10 of itself fails it). The
                    // proportional form against the three-product one: to 1e-10 of the
                    // largest |u|, since the right-hand side's round-off is relative to K·u
                    // (measured ≤ 5.4e-12, against ≤ 1.4e-12 between the FMA and the baseline
                    // build of either form; both forms are equally far from the
                    // extended-precision reference, tests/precision.rs).
                    if step % 50 == 0 {
                        let mut once = fast.clone();
                        let u0 = fast.u().to_vec();
                        once.step(&sparse);
                        let du: Vec<f64> = once.u().iter().zip(&u0).map(|(a, b)| a - b).collect();
                        let scale = max_abs(&du);
                        // The same state in integrators of the other forms (for α_f schemes
                        // with the last load as F_n).
                        let from_here = |options: StepOptions| {
                            let mut nm = with(options);
                            nm.set_state(
                                fast.u(),
                                fast.v(),
                                fast.a(),
                                if scheme.alpha_f != 0.0 { &sparse } else { &[] },
                            );
                            nm
                        };
                        let rows_once = from_here(StepOptions { grouped_sweeps: false, ..tracked });
                        let three_once = from_here(three_options);
                        let u_scale = max_abs(once.u());
                        for (mut other, what, bound) in [
                            (rows_once, "pairs vs rows", 1e-12 * scale),
                            (three_once, "proportional vs three", 1e-10 * u_scale),
                        ] {
                            other.step(&sparse);
                            let e = max_diff(once.u(), other.u());
                            assert!(
                                scale > 0.0 && e <= bound,
                                "{n} DOFs, build {build}, step {step}: {what} {e:e} (Δu {scale:e}, u {u_scale:e})"
                            );
                        }
                    }
                    no_runs.step(&sparse);
                    assert!(
                        fast.u() == no_runs.u() && fast.v() == no_runs.v() && fast.a() == no_runs.a(),
                        "{n} DOFs, build {build}, step {step}: the periodic runs changed the state"
                    );
                    assert_eq!(fast.dissipated().to_bits(), no_runs.dissipated().to_bits(), "the periodic runs");
                    let [by_row, by_row_no_runs] = &mut by_rows;
                    by_row.step(&sparse);
                    by_row_no_runs.step(&sparse);
                    assert!(
                        by_row.u() == by_row_no_runs.u()
                            && by_row.v() == by_row_no_runs.v()
                            && by_row.a() == by_row_no_runs.a(),
                        "{n} DOFs, build {build}, step {step}: the periodic runs changed the row-by-row state"
                    );
                    assert_eq!(by_row.dissipated().to_bits(), by_row_no_runs.dissipated().to_bits());
                    three.step(&sparse);
                    for (other, worst_other) in [(&*by_row, &mut worst_rows), (&three, &mut worst_three)] {
                        for (q, (x, y)) in [(other.u(), fast.u()), (other.v(), fast.v()), (other.a(), fast.a())]
                            .into_iter()
                            .enumerate()
                        {
                            let s = max_abs(x);
                            let e = max_diff(x, y);
                            worst_other[q] = worst_other[q].max(e / s.max(f64::MIN_POSITIVE));
                        }
                    }
                    assert!(
                        fast.u() == plain.u() && fast.v() == plain.v() && fast.a() == plain.a(),
                        "{n} DOFs, step {step}: tracking the dissipation changed the state"
                    );
                    assert_eq!(plain.dissipated(), 0.0);
                    let vbar: Vec<f64> = v_old.iter().zip(&slow.v).map(|(a, b)| 0.5 * (a + b)).collect();
                    d_slow += dt * sys.c.bilinear(&vbar, &vbar);
                    // The running total after every step: the band step counts a step's
                    // dissipation in the next step's right-hand side pass, so this checks
                    // both the deferred sum and the last step's on-demand term.
                    worst_diss = worst_diss.max((fast.dissipated() - d_slow).abs() / d_slow.abs().max(1e-300));
                    for (q, (x, y)) in
                        [(&slow.u, fast.u()), (&slow.v, fast.v()), (&slow.a, fast.a())].into_iter().enumerate()
                    {
                        let s = max_abs(x);
                        let e = max_diff(x, y);
                        assert!(s > 0.0 || step == 1, "step {step}: zero or non-finite state");
                        worst[q] = worst[q].max(e / s.max(f64::MIN_POSITIVE));
                    }
                    // Each read-out equals its plain sum over the fast integrator's own state.
                    for (g, got) in rows.iter().zip(fast.observed()) {
                        for (q, x) in [fast.u(), fast.v(), fast.a()].into_iter().enumerate() {
                            let want: f64 = g.iter().map(|&(d, c)| c * x[d]).sum();
                            let scale: f64 = g.iter().map(|&(d, c)| (c * x[d]).abs()).sum();
                            assert!(
                                (got[q] - want).abs() <= 1e-13 * scale,
                                "{n} DOFs, step {step}: read-out {q} {} vs {want}",
                                got[q]
                            );
                        }
                    }
                }
                // Round-off, amplified by K_eff's conditioning (≈ 1e6 here) over 600 steps; a
                // is (Δu − Δt·v)/(βΔt²), a difference of nearly equal numbers, so it shows most.
                assert!(
                    worst[0] < 1e-8 && worst[1] < 1e-8 && worst[2] < 1e-6,
                    "{n} DOFs, {scheme:?}, build {build}: fast vs textbook {worst:?}"
                );
                for (worst_other, what) in
                    [(worst_rows, "grouped vs row-by-row"), (worst_three, "proportional vs three")]
                {
                    assert!(
                        worst_other[0] < 1e-8 && worst_other[1] < 1e-8 && worst_other[2] < 1e-6,
                        "{n} DOFs, {scheme:?}, build {build}: {what} {worst_other:?}"
                    );
                }
                let d_fast = fast.dissipated();
                assert!(
                    (d_fast - d_slow).abs() < 1e-10 * d_slow.abs() && worst_diss < 1e-10,
                    "{n} DOFs, {scheme:?}, build {build}: dissipation {d_fast} vs {d_slow} (worst {worst_diss:e})"
                );
            }
        }
    }
}

/// The 512-bit right-hand side is used where the processor has AVX-512F and the system
/// is in-cache sized; above ≈ 3·10⁵ DOFs the state streams from memory, where the 256-bit
/// kernel measured faster (the comment on `WIDE_RHS_MAX_DOFS` in `solve/band_newmark`).
#[test]
fn wide_kernel_only_for_systems_that_fit_in_cache() {
    use beamflow::analysis::plan::calibrated_model;
    use beamflow::assembly::System;
    use beamflow::solve::band_newmark::{BandNewmark, StepOptions};
    let fused = |elements: usize| {
        let lc = common::bare_beam(elements, [5.29, 9.96e-6]);
        let sys = System::assemble(&calibrated_model(&lc).unwrap()).unwrap();
        let scheme = Scheme::average_acceleration();
        BandNewmark::new(&sys.m, &sys.c, &sys.k, &sys.envelope, scheme, 1e-4, StepOptions::default()).unwrap()
    };
    #[cfg(target_arch = "x86_64")]
    let wide = std::arch::is_x86_feature_detected!("avx512f")
        && std::arch::is_x86_feature_detected!("avx2")
        && std::arch::is_x86_feature_detected!("fma");
    #[cfg(not(target_arch = "x86_64"))]
    let wide = false;
    assert_eq!(fused(200).uses_avx512(), wide);
    let large = fused(160_000);
    assert_eq!(large.dim(), 319_998);
    assert!(!large.uses_avx512());
}

/// The proportional form is taken only where C really is a₀·M + a₁·K plus a few entries:
/// given coefficients that do not fit the damping (a₀ off by 1e-6 of itself, so every entry
/// of C leaves a remainder; or a₁ doubled), the integrator declines it and steps with the
/// three products, to the bit.
#[test]
fn proportional_form_declined_where_damping_does_not_fit() {
    use beamflow::analysis::plan::calibrated_model;
    use beamflow::assembly::System;
    use beamflow::solve::band_newmark::{BandNewmark, StepOptions};
    let (a0, a1) = (5.29, 9.96e-6);
    let sys = System::assemble(&calibrated_model(&common::bare_beam(100, [a0, a1])).unwrap()).unwrap();
    let fused = |rayleigh: Option<(f64, f64)>| {
        let options = StepOptions { rayleigh, ..StepOptions::default() };
        BandNewmark::new(&sys.m, &sys.c, &sys.k, &sys.envelope, Scheme::average_acceleration(), 1e-4, options).unwrap()
    };
    let (mut three, mut declined, mut switched) =
        (fused(None), fused(Some((a0 * (1.0 + 1e-6), a1))), fused(Some((a0, a1 * 2.0))));
    assert!(!three.uses_proportional_damping());
    assert!(!declined.uses_proportional_damping());
    assert!(!switched.uses_proportional_damping());
    let mut accepted = fused(Some((a0, a1)));
    assert!(accepted.uses_proportional_damping());
    let probe = sys.n() / 3;
    for k in 1..=200 {
        let f = [(probe, (k as f64 * 0.0377).sin())];
        for nm in [&mut three, &mut declined, &mut switched, &mut accepted] {
            nm.step(&f);
        }
        assert!(declined.u() == three.u() && switched.u() == three.u() && switched.a() == three.a(), "step {k}");
        let scale = max_abs(three.u());
        let e = max_diff(accepted.u(), three.u());
        assert!(e <= 1e-9 * scale, "step {k}: proportional vs three {e:e} of {scale:e}");
    }
}
