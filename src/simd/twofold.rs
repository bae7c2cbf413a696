//! Sums of products as if computed in twice the working precision and rounded once: the
//! error-free transformations TwoSum (Knuth) and TwoProduct (one fused multiply–add, or
//! Dekker's splitting where the build has no FMA: both give the exact product error, so the
//! two builds agree bit for bit), and the compensated accumulator built on them (Ogita, Rump
//! & Oishi 2005, Sum2/Dot2): the running sum in `hi`, every rounding it made in `lo`.
//!
//! A sum of n products accumulated this way is within u·|sum| + γₙ²·Σ|terms| of exact
//! (u = ε/2, γₙ = n·u/(1 − n·u)).

use super::madd;

/// s + e = a + b exactly, s = fl(a + b).
#[inline(always)]
pub fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// p + e = a·b exactly, p = fl(a·b) (for |a·b| well inside the exponent range).
#[inline(always)]
pub fn two_prod<const FMA: bool>(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    if FMA {
        (p, madd::<true>(a, b, -p))
    } else {
        let (ah, al) = split(a);
        let (bh, bl) = split(b);
        (p, al * bl - (((p - ah * bh) - al * bh) - ah * bl))
    }
}

/// Dekker's splitting of a into two halves of 26 bits: h + l = a.
#[inline(always)]
fn split(a: f64) -> (f64, f64) {
    let c = 134_217_729.0 * a;
    let h = c - (c - a);
    (h, a - h)
}

/// A compensated sum: the value is hi + lo.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Twofold {
    pub hi: f64,
    pub lo: f64,
}

impl Twofold {
    pub fn of(x: f64) -> Self {
        Twofold { hi: x, lo: 0.0 }
    }

    /// a·b exactly (for |a·b| well inside the exponent range).
    pub fn product(a: f64, b: f64) -> Self {
        let (hi, lo) = two_prod::<false>(a, b);
        Twofold { hi, lo }
    }

    /// self += a·b.
    #[inline(always)]
    pub fn add_product<const FMA: bool>(&mut self, a: f64, b: f64) {
        let (p, e) = two_prod::<FMA>(a, b);
        let (s, f) = two_sum(self.hi, p);
        self.hi = s;
        self.lo += e + f;
    }

    /// self += a·b for a twofold a and b (the lo·lo term, u² of the product, left out).
    #[inline(always)]
    pub fn add_twofold_product<const FMA: bool>(&mut self, a: Twofold, b: Twofold) {
        self.add_product::<FMA>(a.hi, b.hi);
        self.lo += a.hi * b.lo + a.lo * b.hi;
    }

    /// self += x.
    #[inline(always)]
    pub fn add(&mut self, x: f64) {
        let (s, f) = two_sum(self.hi, x);
        self.hi = s;
        self.lo += f;
    }

    /// The same value with lo below half an ulp of hi.
    #[inline(always)]
    pub fn normalised(self) -> Twofold {
        let (hi, lo) = two_sum(self.hi, self.lo);
        Twofold { hi, lo }
    }

    /// The nearest double (to within an ulp).
    #[inline(always)]
    pub fn value(self) -> f64 {
        self.hi + self.lo
    }

    pub fn neg(self) -> Twofold {
        Twofold { hi: -self.hi, lo: -self.lo }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both builds give the exact product error, and a cancelling dot product keeps its
    /// remainder.
    #[test]
    fn products_are_exact_in_both_builds_and_sums_keep_what_cancels() {
        let mut seed = 1u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for _ in 0..1000 {
            let (a, b) = (next() * 1e3, next() * 1e-2);
            let (p, e) = two_prod::<false>(a, b);
            assert_eq!((p, e), two_prod::<true>(a, b));
            let (s, f) = two_sum(a, b);
            assert_eq!(s, a + b);
            // The error term is what fl lost: exact in a wider type for these magnitudes.
            assert!((e.abs() <= 0.5 * p.abs() * f64::EPSILON) && (f.abs() <= 0.5 * s.abs() * f64::EPSILON));
        }
        // (1 + 2⁻⁵²)(1 − 2⁻⁵²) − 1 = −2⁻¹⁰⁴ exactly; doubles round the product to 1.
        let (a, b) = (1.0 + f64::EPSILON, 1.0 - f64::EPSILON);
        let mut t = Twofold::default();
        t.add_product::<false>(a, b);
        t.add(-1.0);
        assert_eq!(t.value(), -f64::EPSILON * f64::EPSILON);
        assert_eq!(a * b - 1.0, 0.0);
    }
}
