//! Power at a point (physics spec §10): p(t) = F(t)·v(t) with F the force on the structure
//! there (positive up) and v its velocity; its time average over whole periods, in time and
//! from harmonic amplitudes (convention q(t) = Re(Q·e^{iωt})); the net power of an actuator;
//! and the power its dampers take out.

use crate::assembly::LinkDofs;
use crate::linalg::Csr;
use num_complex::Complex64;

/// Instantaneous power p = F·v (W) at each sample of a force (N) and a velocity (m/s).
pub fn instantaneous_power(force: &[f64], velocity: &[f64]) -> Vec<f64> {
    force.iter().zip(velocity).map(|(f, v)| f * v).collect()
}

/// Mean of the product of two sampled signals over whole periods (W for force × velocity).
pub fn mean_product(a: &[f64], b: &[f64]) -> f64 {
    if a.is_empty() {
        return 0.0;
    }
    a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>() / a.len() as f64
}

/// A point whose mean power is below this fraction of the largest point power is judged
/// against this fraction of the largest rather than against its own: such a power is the
/// small difference of far larger flows in and out (or zero, as at a foot on a rigid
/// base), and its own relative accuracy would ask more digits of them than the round-off
/// of a solve holds.
pub const SMALL_POWER: f64 = 1e-6;

/// The scale each of `values` (point powers, W, or RMS forces, N) is judged against: its
/// own magnitude, at least [`SMALL_POWER`] of the largest magnitude (0 where all vanish).
pub fn own_scales(values: &[f64]) -> Vec<f64> {
    let floor = SMALL_POWER * values.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    values.iter().map(|x| x.abs().max(floor)).collect()
}

/// |other_i − reference_i| / scale_i per entry, each scale the reference's [`own_scales`]
/// (where every reference value vanishes, the difference itself).
pub fn relative_to_own(reference: &[f64], other: &[f64]) -> Vec<f64> {
    reference
        .iter()
        .zip(other)
        .zip(own_scales(reference))
        .map(|((r, o), s)| if s > 0.0 { (o - r).abs() / s } else { (o - r).abs() })
        .collect()
}

/// The largest of |a_i − b_i| / scale_i, each difference relative to its own scale (a zero
/// scale counts a zero difference only: 0/0 is taken as 0).
pub fn largest_relative(a: &[f64], b: &[f64], scales: &[f64]) -> f64 {
    a.iter().zip(b).zip(scales).fold(0.0f64, |m, ((x, y), s)| {
        let d = (x - y).abs();
        m.max(if d == 0.0 { 0.0 } else { d / s })
    })
}

/// Time-averaged power ½·Re(F·conj(V)) (W) of force (N) and velocity (m/s) amplitudes.
#[inline]
pub fn mean_power(f: Complex64, v: Complex64) -> f64 {
    0.5 * (f * v.conj()).re
}

/// A bound (W) on the error of [`mean_power`] when |δF| ≤ `df` (N) and |δV| ≤ `dv` (m/s):
/// ½(|F|·dv + df·|V| + df·dv). Against the power itself it is as large as the apparent
/// power ½|F||V| is beside the active power ½Re(F·conj(V)): cancellation included.
#[inline]
pub fn mean_power_error(f: Complex64, df: f64, v: Complex64, dv: f64) -> f64 {
    0.5 * (f.norm() * dv + df * v.norm() + df * dv)
}

/// Time-averaged power (W) from force (N) and *acceleration* (m/s²) amplitudes at ω > 0
/// (rad/s), as measured with an impedance head and an accelerometer: V = A/(iω), hence
/// P = −½·Im(F·conj(A))/ω.
#[inline]
pub fn mean_power_from_acceleration(f: Complex64, a: Complex64, omega: f64) -> f64 {
    -0.5 * (f * a.conj()).im / omega
}

/// Work F̄·v̄·Δt (J) of a force over one time step by the midpoint rule, from the force (N)
/// and velocity (m/s) at both ends of the step: what the trapezoidal scheme balances exactly.
#[inline]
pub fn midpoint_work(dt: f64, f0: f64, f1: f64, v0: f64, v1: f64) -> f64 {
    dt * 0.5 * (f0 + f1) * 0.5 * (v0 + v1)
}

/// Energy c·ū̇²·Δt (J) a damper c (N·s/m) dissipates over one time step by the midpoint rule,
/// from its stretch rate (m/s) at both ends.
#[inline]
pub fn damper_dissipation(dt: f64, c: f64, rate0: f64, rate1: f64) -> f64 {
    let mid = 0.5 * (rate0 + rate1);
    dt * c * mid * mid
}

/// Time-averaged power (W) dissipated by a viscous matrix C in harmonic motion Q at ω
/// (rad/s): ½·ω²·Qᴴ·C·Q.
pub fn dissipated_power(c: &Csr, q: &[Complex64], omega: f64) -> f64 {
    0.5 * omega * omega * c.hermitian_form(q)
}

/// Time-averaged power (W) the structure of `sys` dissipates in harmonic motion Q at ω
/// (rad/s): its viscous part ½·ω²·Qᴴ·C_beam·Q and, when hysteretically damped, the loss
/// ½·ω·Qᴴ·(η·K_beam)·Q of its complex stiffness.
pub fn beam_dissipation(sys: &crate::assembly::System, q: &[Complex64], omega: f64) -> f64 {
    let viscous = dissipated_power(&sys.c_beam, q, omega);
    match &sys.k_loss {
        Some(kl) => viscous + 0.5 * omega * kl.hermitian_form(q),
        None => viscous,
    }
}

/// Net power of each of `actuators` actuators (W): the sum of `point_power` (one per link,
/// in the order of `links`) over the actuator's interface points.
pub fn net_power(links: &[LinkDofs], point_power: &[f64], actuators: usize) -> Vec<f64> {
    (0..actuators)
        .map(|a| links.iter().zip(point_power).filter(|(lk, _)| lk.actuator == a).map(|(_, p)| p).sum())
        .collect()
}
