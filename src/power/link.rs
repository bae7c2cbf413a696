//! What a link (a stack or a frame leg) transmits at its foot (physics spec §7, §10): the
//! transmitted force F_T = k·u + c·u̇ − F_p (the stack's active force F_p acts on the stack's
//! own link only) on the base, positive up, and the interface force F_i = F_T − m_foot·ẅ
//! the structure feels across the actuator–structure interface (the foot mass rides on the
//! structure). From time samples and from harmonic amplitudes.

use super::point::mean_power;
use crate::assembly::LinkDofs;
use num_complex::Complex64;

/// The active component of a link's transmitted force (N): −F_p on a stack's link, 0 on a
/// leg. `f_p` is the active force of the link's actuator.
#[inline]
pub fn pzt_force(lk: &LinkDofs, f_p: f64) -> f64 {
    if lk.active {
        -f_p
    } else {
        0.0
    }
}

/// Transmitted force F_T = k·u + c·u̇ − F_p (N) from the stretch u (m), its rate u̇ (m/s) and
/// the active force F_p (N) of the link's actuator.
#[inline]
pub fn transmitted_force(lk: &LinkDofs, u: f64, u_dot: f64, f_p: f64) -> f64 {
    lk.k * u + lk.c * u_dot + pzt_force(lk, f_p)
}

/// Interface force F_i = F_T − m_foot·ẅ (N) from the transmitted force (N) and the base
/// acceleration ẅ at the foot (m/s²).
#[inline]
pub fn interface_force(lk: &LinkDofs, transmitted: f64, foot_acceleration: f64) -> f64 {
    transmitted - lk.foot_mass * foot_acceleration
}

/// Transmitted-force amplitude F̂_T = (k + iωc)·Û − F̂_p (N) at ω (rad/s) from the stretch
/// amplitude Û (m) and the active-force amplitude F̂_p (N) of the link's actuator.
#[inline]
pub fn transmitted_amplitude(lk: &LinkDofs, u: Complex64, omega: f64, f_p: Complex64) -> Complex64 {
    let iw = Complex64::new(0.0, omega);
    u * (lk.k + iw * lk.c) - if lk.active { f_p } else { Complex64::default() }
}

/// Interface-force amplitude F̂_i = F̂_T − m_foot·Â (N) from the transmitted-force amplitude
/// (N) and the base acceleration amplitude Â at the foot (m/s²).
#[inline]
pub fn interface_amplitude(lk: &LinkDofs, transmitted: Complex64, foot_acceleration: Complex64) -> Complex64 {
    transmitted - foot_acceleration * lk.foot_mass
}

/// A link's complex amplitudes at one frequency.
#[derive(Clone, Copy, Debug, Default)]
pub struct LinkHarmonic {
    /// Transmitted force on the base (N), interface force (N).
    pub transmitted: Complex64,
    pub interface: Complex64,
    /// Base velocity (m/s) and acceleration (m/s²) at the foot.
    pub velocity: Complex64,
    pub acceleration: Complex64,
    /// Time-averaged power ½·Re(F_interface·conj(V)) into the base (W).
    pub power: f64,
}

/// A bound (W) on the error of a link's harmonic power ½Re(F̂_i·conj V̂) at ω (rad/s), its
/// interface force `fi` (N) and foot velocity `v` (m/s), from bounds on the errors of its
/// stretch `du` and foot displacement `dfoot` (m): the stretch's through k + iωc, the
/// foot's through the foot mass and the velocity.
pub fn link_power_error(lk: &LinkDofs, du: f64, dfoot: f64, omega: f64, fi: Complex64, v: Complex64) -> f64 {
    let dfi = du * Complex64::new(lk.k, omega * lk.c).norm() + lk.foot_mass * omega * omega * dfoot;
    super::point::mean_power_error(fi, dfi, v, omega * dfoot)
}

/// What a link transmits when the system moves harmonically with DOF amplitudes `q` at ω
/// (rad/s) and the stacks' active forces have amplitudes `f_p` (one per actuator, N).
pub fn link_harmonic(lk: &LinkDofs, q: &[Complex64], omega: f64, f_p: &[Complex64]) -> LinkHarmonic {
    let iw = Complex64::new(0.0, omega);
    let u: Complex64 = lk.stretch.iter().map(|&(d, c)| q[d] * c).sum();
    let foot: Complex64 = lk.foot.iter().map(|&(d, c)| q[d] * c).sum();
    let (v, a) = (iw * foot, iw * iw * foot);
    let ft = transmitted_amplitude(lk, u, omega, f_p[lk.actuator]);
    let fi = interface_amplitude(lk, ft, a);
    LinkHarmonic { transmitted: ft, interface: fi, velocity: v, acceleration: a, power: mean_power(fi, v) }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn link(active: bool) -> LinkDofs {
        LinkDofs {
            actuator: 0,
            name: "l".into(),
            k: 3.0e7,
            c: 45.0,
            stretch: Vec::new(),
            foot_node: None,
            foot_dof: None,
            foot: Vec::new(),
            foot_at: None,
            foot_mass: 0.012,
            active,
        }
    }

    /// The time-sample and the amplitude forms are two writings of one force: sampling a
    /// harmonic motion and applying the first gives Re(amplitude·e^{iωt}) of the second.
    #[test]
    fn sample_and_amplitude_forms_agree_on_a_harmonic_motion() {
        let w = 2.0 * std::f64::consts::PI * 60.0;
        let (u, fp, acc) = (Complex64::new(2e-7, -1e-7), Complex64::new(-0.3, 14.0), Complex64::new(-0.4, 0.9));
        let at = |z: Complex64, t: f64| (z * Complex64::from_polar(1.0, w * t)).re;
        for lk in [link(true), link(false)] {
            let ft = transmitted_amplitude(&lk, u, w, fp);
            let fi = interface_amplitude(&lk, ft, acc);
            for j in 0..16 {
                let t = j as f64 / 16.0 / 60.0;
                let u_dot = at(Complex64::new(0.0, w) * u, t);
                let f = transmitted_force(&lk, at(u, t), u_dot, at(fp, t));
                let scale = ft.norm() + fp.norm();
                assert!((f - at(ft, t)).abs() < 1e-12 * scale, "F_T at sample {j}: {f} vs {}", at(ft, t));
                let i = interface_force(&lk, f, at(acc, t));
                assert!((i - at(fi, t)).abs() < 1e-12 * scale, "F_i at sample {j}");
            }
            // F_p acts on the stack's link only.
            assert_eq!(pzt_force(&lk, 5.0), if lk.active { -5.0 } else { 0.0 });
        }
    }
}
