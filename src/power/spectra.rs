//! Harmonic content of periodic signals.
//!
//! Convention: a periodic signal sampled N times over one period T is written
//! x(t) = Re Σ_k X̂_k·e^{+i·k·ω₀·t}, ω₀ = 2π/T. With the DFT X_k = Σ_n x_n·e^{−2πikn/N}
//! (rustfft's forward transform) the single-sided amplitudes are X̂₀ = X₀/N,
//! X̂_k = 2X_k/N for 0 < k < N/2 and X̂_{N/2} = X_{N/2}/N. No window: over a whole period
//! the harmonics fall exactly on bins.

use super::point::{mean_power, mean_power_from_acceleration};
use num_complex::Complex64;
use rustfft::FftPlanner;

/// Single-sided complex amplitudes X̂_k, k = 0..=N/2, of one period of samples.
pub fn harmonics(samples: &[f64]) -> Vec<Complex64> {
    let n = samples.len();
    if n == 0 {
        return Vec::new();
    }
    let mut buf: Vec<Complex64> = samples.iter().map(|&x| Complex64::new(x, 0.0)).collect();
    FftPlanner::new().plan_fft_forward(n).process(&mut buf);
    let half = n / 2;
    (0..=half)
        .map(|k| {
            let s = if is_unpaired(k, n) { 1.0 } else { 2.0 };
            buf[k] * (s / n as f64)
        })
        .collect()
}

/// Whether harmonic k of a single-sided spectrum of N samples per period carries its full
/// amplitude rather than twice its half (the mean, and the Nyquist term of an even N).
fn is_unpaired(k: usize, n_samples: usize) -> bool {
    k == 0 || (n_samples.is_multiple_of(2) && k == n_samples / 2)
}

/// Time-averaged power per harmonic from force and velocity amplitudes:
/// P_k = ½·Re(F̂_k·conj(V̂_k)); the mean (k = 0) and, for even N, the Nyquist term carry no ½.
/// Σ_k P_k equals the mean of the sampled product f·v exactly.
pub fn power_per_harmonic(f: &[Complex64], v: &[Complex64], n_samples: usize) -> Vec<f64> {
    f.iter()
        .zip(v)
        .enumerate()
        .map(|(k, (&a, &b))| {
            let p = mean_power(a, b);
            if is_unpaired(k, n_samples) {
                2.0 * p
            } else {
                p
            }
        })
        .collect()
}

/// Power per harmonic from force and *acceleration* amplitudes, as measured with an
/// impedance head and an accelerometer: V̂ = Â/(iω_k), hence
/// P_k = −½·Im(F̂_k·conj(Â_k))/ω_k (k ≥ 1; the mean carries no power in steady state).
pub fn power_from_acceleration(f: &[Complex64], a: &[Complex64], omega0: f64, n_samples: usize) -> Vec<f64> {
    f.iter()
        .zip(a)
        .enumerate()
        .map(|(k, (&fk, &ak))| {
            if k == 0 {
                return 0.0;
            }
            let p = mean_power_from_acceleration(fk, ak, k as f64 * omega0);
            if is_unpaired(k, n_samples) {
                2.0 * p
            } else {
                p
            }
        })
        .collect()
}

/// Level in dB re `reference` of an amplitude.
pub fn db(amplitude: f64, reference: f64) -> f64 {
    20.0 * (amplitude.max(f64::MIN_POSITIVE) / reference).log10()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn harmonics_recover_amplitudes_and_phases() {
        let n = 64;
        let x: Vec<f64> = (0..n)
            .map(|i| {
                let t = i as f64 / n as f64;
                0.5 + 2.0 * (2.0 * PI * t + 0.3).cos() + 0.7 * (2.0 * PI * 3.0 * t - 1.1).cos()
            })
            .collect();
        let h = harmonics(&x);
        assert!((h[0].re - 0.5).abs() < 1e-14);
        assert!((h[1] - Complex64::from_polar(2.0, 0.3)).norm() < 1e-13);
        assert!((h[3] - Complex64::from_polar(0.7, -1.1)).norm() < 1e-13);
        assert!(h[2].norm() < 1e-13);
    }

    #[test]
    fn power_from_acceleration_equals_power_from_velocity_and_sums_to_the_mean() {
        // f = F cos(kωt + φ_f), v = V cos(kωt + φ_v), a = dv/dt exactly, sampled.
        let n = 200;
        let w0 = 2.0 * PI * 60.0;
        let comps = [(1, 3.0, 0.2, 0.01, -0.4), (3, 1.5, -0.9, 0.002, 1.2), (5, 0.4, 2.0, 0.0007, 0.1)];
        let t: Vec<f64> = (0..n).map(|i| i as f64 / n as f64 / 60.0).collect();
        let mut f = vec![0.0; n];
        let mut v = vec![0.0; n];
        let mut a = vec![0.0; n];
        for &(k, fa, fp, va, vp) in &comps {
            let w = k as f64 * w0;
            for i in 0..n {
                f[i] += fa * (w * t[i] + fp).cos();
                v[i] += va * (w * t[i] + vp).cos();
                a[i] += -va * w * (w * t[i] + vp).sin();
            }
        }
        let (fh, vh, ah) = (harmonics(&f), harmonics(&v), harmonics(&a));
        let pv = power_per_harmonic(&fh, &vh, n);
        let pa = power_from_acceleration(&fh, &ah, w0, n);
        let mean: f64 = f.iter().zip(&v).map(|(x, y)| x * y).sum::<f64>() / n as f64;
        let total: f64 = pv.iter().sum();
        assert!((total - mean).abs() <= 1e-9 * mean.abs());
        for k in 0..pv.len() {
            assert!((pv[k] - pa[k]).abs() <= 1e-9 * mean.abs(), "harmonic {k}: {} vs {}", pv[k], pa[k]);
        }
        for &(k, fa, fp, va, vp) in &comps {
            let exact = 0.5 * fa * va * (fp - vp).cos();
            assert!((pv[k] - exact).abs() < 1e-12 * mean.abs().max(1e-12));
        }
    }
}
