//! Closed-form references for rectangular plates (spec §16): the simply supported plate's
//! modes (Navier) and the clamped square plate's frequency parameters (Leissa).

use std::f64::consts::PI;

/// ω_mn (rad/s) of the simply supported plate: π²·((m/L_x)² + (n/L_y)²)·√(D/ρh).
pub fn omega(m: usize, n: usize, lx: f64, ly: f64, d: f64, rho_h: f64) -> f64 {
    let (a, b) = (m as f64 / lx, n as f64 / ly);
    PI * PI * (a * a + b * b) * (d / rho_h).sqrt()
}

/// The mode shape sin(mπx/L_x)·sin(nπy/L_y) at (x, y); its modal mass is ρh·L_x·L_y/4.
pub fn shape(m: usize, n: usize, lx: f64, ly: f64, x: f64, y: f64) -> f64 {
    (m as f64 * PI * x / lx).sin() * (n as f64 * PI * y / ly).sin()
}

/// The `count` lowest (m, n, ω_mn) of the simply supported plate, ascending.
pub fn lowest(count: usize, lx: f64, ly: f64, d: f64, rho_h: f64) -> Vec<(usize, usize, f64)> {
    let reach = count + 2;
    let mut all: Vec<(usize, usize, f64)> =
        (1..=reach).flat_map(|m| (1..=reach).map(move |n| (m, n, omega(m, n, lx, ly, d, rho_h)))).collect();
    all.sort_by(|a, b| a.2.total_cmp(&b.2));
    all.truncate(count);
    all
}

/// Leissa's frequency parameters λ = ω·L²·√(ρh/D) of the clamped square plate, modes 1–6.
pub const CLAMPED_SQUARE_LAMBDA: [f64; 6] = [35.985, 73.394, 73.394, 108.22, 131.58, 132.20];
