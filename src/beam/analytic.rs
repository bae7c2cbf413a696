//! Closed-form results for uniform Euler–Bernoulli beams, used as references.
//!
//! Natural frequencies ω_r = (β_r L)²·√(EI/(ρA L⁴)), with β_r L the r-th root of the
//! characteristic equation of the end conditions, found here by bisection to round-off.

use std::f64::consts::PI;

/// End conditions with a closed-form characteristic equation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum End {
    Clamped,
    Pinned,
    Free,
}

/// The first `count` roots βL of the characteristic equation (flexible modes only).
pub fn beta_l_roots(left: End, right: End, count: usize) -> Option<Vec<f64>> {
    use End::*;
    let (a, b) = if left as u8 <= right as u8 { (left, right) } else { (right, left) };
    // f(x) whose positive roots are the flexible modes' βL; each root lies in the given
    // bracket (r-th interval) where f changes sign exactly once.
    let f: fn(f64) -> f64 = match (a, b) {
        (Clamped, Clamped) | (Free, Free) => |x| x.cos() * x.cosh() - 1.0,
        (Clamped, Free) => |x| x.cos() * x.cosh() + 1.0,
        (Pinned, Pinned) => |x| x.sin(),
        (Clamped, Pinned) | (Pinned, Free) => |x| x.tan() - x.tanh(),
        _ => return None,
    };
    let mut roots = Vec::with_capacity(count);
    for r in 1..=count {
        let rf = r as f64;
        // Brackets from the asymptotic positions of the roots.
        let (lo, hi) = match (a, b) {
            (Clamped, Clamped) | (Free, Free) => ((rf + 0.5) * PI - 0.5, (rf + 0.5) * PI + 0.5),
            (Clamped, Free) => ((rf - 0.5) * PI - 0.5, (rf - 0.5) * PI + 0.5),
            (Pinned, Pinned) => (rf * PI - 0.5, rf * PI + 0.5),
            _ => ((rf + 0.25) * PI - 0.3, (rf + 0.25) * PI + 0.3),
        };
        roots.push(bisect(f, lo.max(1e-3), hi));
    }
    Some(roots)
}

fn bisect(f: fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let mut flo = f(lo);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        let fm = f(mid);
        if (fm < 0.0) == (flo < 0.0) {
            lo = mid;
            flo = fm;
        } else {
            hi = mid;
        }
        if hi - lo <= 4.0 * f64::EPSILON * hi {
            break;
        }
    }
    0.5 * (lo + hi)
}

/// Natural frequencies (Hz) of a uniform beam: length L (m), EI (N·m²), ρA (kg/m).
pub fn natural_frequencies_hz(
    left: End,
    right: End,
    length: f64,
    ei: f64,
    rho_a: f64,
    count: usize,
) -> Option<Vec<f64>> {
    let c = (ei / rho_a).sqrt() / (2.0 * PI * length * length);
    beta_l_roots(left, right, count).map(|r| r.iter().map(|bl| bl * bl * c).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roots_match_published_values() {
        let cc = beta_l_roots(End::Clamped, End::Clamped, 3).unwrap();
        for (r, v) in cc.iter().zip([4.730040745, 7.853204624, 10.995607838]) {
            assert!((r - v).abs() < 1e-8, "{r} vs {v}");
        }
        let cf = beta_l_roots(End::Clamped, End::Free, 2).unwrap();
        assert!((cf[0] - 1.875104069).abs() < 1e-8 && (cf[1] - 4.694091133).abs() < 1e-8);
        let cp = beta_l_roots(End::Clamped, End::Pinned, 1).unwrap();
        assert!((cp[0] - 3.926602312).abs() < 1e-8);
    }
}
