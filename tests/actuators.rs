//! Actuator models on a rigid base: exact static limits, force balance, the inertial
//! force law, and the paper's qualitative claims with the default parameters.

mod common;
use beamflow::analysis::plan::calibrated_model;
use beamflow::analysis::transient::{self, TransientResult, TransientSettings};
use beamflow::assembly::System;
use beamflow::case::LoadedCase;
use common::*;
use std::path::Path;

fn rigid_case(extra: &str) -> LoadedCase {
    case(&format!("base = \"rigid\"\n{extra}"))
}

fn run(lc: &LoadedCase) -> TransientResult {
    let model = calibrated_model(lc).unwrap();
    let sys = System::assemble(&model).unwrap();
    transient::run(&model, &sys, &TransientSettings::default()).unwrap()
}

fn link<'a>(r: &'a TransientResult, actuator: usize, name: &str) -> &'a beamflow::analysis::series::LinkSeries {
    r.links.iter().find(|l| l.actuator == actuator && l.name == name).unwrap()
}

#[test]
fn frame_static_limit_with_centred_stack() {
    // e = 0: the stack's active force splits between the stack spring and the two legs.
    let (kp, kl) = (3.0e7, 1.5e9);
    let lc = rigid_case("[[actuator]]\ntype = \"frame\"\ne = 0.0\nk_l_right = 1.5e9\n[actuator.voltage]\nkind = \"sine\"\namplitude = 1.0\nfrequency = 1.0\n");
    let model = calibrated_model(&lc).unwrap();
    let sys = System::assemble(&model).unwrap();
    let fp = 123.0;
    let mut f = vec![0.0; sys.n()];
    for &(d, c) in &sys.drives[0] {
        f[d] += c * fp;
    }
    let q = sys.static_solve(&f).unwrap();
    let force = |name: &str| {
        let l = sys.links.iter().find(|l| l.name == name).unwrap();
        let u: f64 = l.stretch.iter().map(|&(d, c)| c * q[d]).sum();
        l.k * u - if l.active { fp } else { 0.0 }
    };
    let fe = force("stack");
    let exact = -fp * 2.0 * kl / (kp + 2.0 * kl);
    assert!(rel(fe, exact) < 1e-12, "F_E = {fe} vs {exact}");
    assert!(rel(force("left_leg"), force("right_leg")) < 1e-12);
    assert!((fe + force("left_leg") + force("right_leg")).abs() < 1e-9 * fp, "static: forces on the base balance");
}

#[test]
fn rigid_base_forces_sum_to_minus_the_top_inertia_at_every_step() {
    let lc = rigid_case(
        "[[actuator]]\ntype = \"frame\"\n[actuator.voltage]\nkind = \"sine\"\namplitude = 48.0\nfrequency = 30.0\n",
    );
    let r = run(&lc);
    let model = calibrated_model(&lc).unwrap();
    let comp = model.actuators[0].component();
    let (y, phi) = (&r.bodies[0], &r.bodies[1]);
    let mut worst = 0.0f64;
    let mut scale = 0.0f64;
    for j in 0..r.t.len() {
        let sum: f64 = r.links.iter().map(|l| l.transmitted[j]).sum();
        let inertia = comp.mass[(0, 0)] * y.q_ddot[j] + comp.mass[(0, 1)] * phi.q_ddot[j];
        worst = worst.max((sum + inertia).abs());
        scale = scale.max(link(&r, 0, "stack").transmitted[j].abs());
    }
    assert!(worst < 1e-9 * scale, "imbalance {worst:e} N against forces of {scale:e} N");
}

#[test]
fn inertial_force_below_resonance_is_mass_times_acceleration() {
    let lc = rigid_case(
        "[[actuator]]\ntype = \"inertial\"\n[actuator.voltage]\nkind = \"sine\"\namplitude = 48.0\nfrequency = 30.0\n",
    );
    let r = run(&lc);
    let spec = &r.spectra[0];
    let w = 2.0 * std::f64::consts::PI * 30.0;
    let z1 = beamflow::power::spectra::harmonics(&r.bodies[0].q[r.t.len() - r.steps_per_period..])[1];
    let expected = (0.1 + 0.015) * w * w * z1.norm(); // the default m_t with half the stack mass
    let ft1 = spec.transmitted[1].norm();
    assert!(rel(ft1, expected) < 1e-3, "F_T = {ft1} N vs (m_t + m_p/2)·ω²·z_t = {expected} N");
    assert!(r.converged, "steady state reached");
}

#[test]
fn paper_claims_on_rigid_base_48v_30hz() {
    let lc = LoadedCase::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/rigid-base-48V-30Hz.toml")).unwrap();
    let r = run(&lc);
    let fi = r.spectra[0].transmitted[1].norm();
    let stack_f = r.links.iter().position(|l| l.actuator == 1 && l.name == "stack").unwrap();
    let ff = r.spectra[stack_f].transmitted[1].norm();
    let ratio = ff / fi;
    assert!(ratio > 100.0, "frame/inertial force ratio {ratio}: the paper's more than two orders");
    // Both stacks make the same stroke δ (same voltage, same hysteresis). Far below the
    // inertial actuator's resonance its force is the top inertia (m_t + m_p/2)·ω²·δ; the
    // frame's stack pushes against its legs, k_p in series with 2·k_l (the bar is rigid at
    // 30 Hz and the 1 mm offset adds e²/a² = 6e-4 to the legs' compliance).
    let (k_p, k_l, m_eff, w) = (3.0e7, 1.5e9, 0.1 + 0.03 / 2.0, 2.0 * std::f64::consts::PI * 30.0);
    let expected = (k_p * 2.0 * k_l / (k_p + 2.0 * k_l)) / (m_eff * w * w);
    assert!(rel(ratio, expected) < 0.02, "force ratio {ratio:.0} against the estimate {expected:.0}");
    let amp = |q: &[f64]| q.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let zt = amp(&r.bodies[0].q);
    let y = amp(&r.bodies[1].q);
    let dratio = zt / y;
    assert!((30.0..3000.0).contains(&dratio), "top displacements z_t/y = {dratio}: about two orders apart");
    // Odd harmonics carry the hysteresis; even ones vanish for a zero-offset sine.
    for s in [&r.spectra[0], &r.spectra[stack_f]] {
        let f1 = s.transmitted[1].norm();
        assert!(s.transmitted[3].norm() > 1e-3 * f1, "third harmonic present");
        for k in [2, 4, 6, 8] {
            assert!(s.transmitted[k].norm() < 1e-4 * f1, "harmonic {k}: {:e} of {f1:e}", s.transmitted[k].norm());
        }
    }
    // The frame's stack force opposes its leg forces.
    let legs = r.spectra[stack_f + 1].transmitted[1] + r.spectra[stack_f + 2].transmitted[1];
    let c = (r.spectra[stack_f].transmitted[1] * legs.conj()).re;
    assert!(c < 0.0, "stack and legs in opposite phase");
}
