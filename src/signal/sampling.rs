//! How many samples per period a periodic signal needs: the one rule every analysis, the
//! case validation and the sweeps use.

/// The harmonics `samples` equally spaced samples per period resolve: 1..=⌊(N − 2)/2⌋. For
/// even N that is every harmonic strictly below the Nyquist harmonic N/2 (whose sine
/// samples to zero); for odd N it is one fewer than the samples could carry, which keeps one
/// rule for both.
pub fn resolved_harmonics(samples: usize) -> usize {
    samples.saturating_sub(2) / 2
}

/// Samples per period a periodic analysis of `harmonics` harmonics asks for: 4h + 2, twice
/// what resolving h harmonics takes, so that the harmonics between h and 2h are solved as
/// well and the truncation estimate measures what the kept ones leave out (the stacks'
/// hysteretic forces carry content beyond any h). None if it overflows.
pub fn samples_for_harmonics(harmonics: usize) -> Option<usize> {
    harmonics.checked_mul(4)?.checked_add(2)
}

/// Refuses `samples` per period too few for `harmonics` by [`samples_for_harmonics`]; the
/// error is the reason, for the caller to attach to its field.
pub fn require_samples(harmonics: usize, samples: usize) -> Result<(), String> {
    match samples_for_harmonics(harmonics) {
        Some(n) if samples >= n => Ok(()),
        _ => {
            Err(format!("must be at least 4·harmonics + 2 = {} to resolve the harmonics", 4 * (harmonics as u128) + 2))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_complex::Complex64;

    /// A real sine of harmonic k sampled N times (N even) shows up at bin k of the DFT with
    /// its amplitude exactly when k ≤ resolved_harmonics(N); at k = N/2 it is lost.
    #[test]
    fn resolved_harmonics_are_those_below_nyquist() {
        for n in [6usize, 8, 16, 34] {
            let h = resolved_harmonics(n);
            for k in 1..=n / 2 {
                let x: Vec<f64> =
                    (0..n).map(|i| (2.0 * std::f64::consts::PI * (k * i) as f64 / n as f64 + 0.3).sin()).collect();
                let bin: Complex64 = x
                    .iter()
                    .enumerate()
                    .map(|(i, v)| {
                        v * Complex64::from_polar(1.0, -2.0 * std::f64::consts::PI * (k * i) as f64 / n as f64)
                    })
                    .sum();
                let amplitude = 2.0 * bin.norm() / n as f64;
                let exact = (amplitude - 1.0).abs() < 1e-12;
                assert_eq!(exact, k <= h, "N = {n}, k = {k}, amplitude {amplitude}");
            }
        }
    }

    #[test]
    fn the_analysis_rule_doubles_the_resolution_and_refuses_overflow() {
        for h in [1usize, 9, 100] {
            assert_eq!(resolved_harmonics(samples_for_harmonics(h).unwrap()), 2 * h);
        }
        assert_eq!(samples_for_harmonics(1 << 62), None);
    }
}
