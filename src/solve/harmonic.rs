//! Steady harmonic response: (K − ω²M + iωC)·Q = F, convention q(t) = Re(Q·e^{iωt}).

use crate::error::{Error, Result};
use crate::linalg::{Csr, Skyline};
use num_complex::Complex64;

/// The dynamic stiffness of a system, refactorised per frequency in fixed storage.
///
/// A frequency sweep or a periodic steady state factorises the same complex symmetric
/// profile matrix at many frequencies, and on the paper beam (≈ 400 DOFs, ≈ 4 entries a
/// row) one factorisation is only ≈ 10⁴ flops. At that size the generic
/// [`crate::linalg::SkylineLdlt`] is dominated by overheads, so this holds its own complex
/// LDLᵀ with the same envelope and algorithm (row-oriented, no pivoting), except that it:
/// * builds K − ω²M + iωC entry by entry from K, M and C in the profile's order (the same
///   bits as `Skyline::set_combination`);
/// * keeps 1/d_j and multiplies by it instead of dividing by d_j (one real division per row
///   instead of two per entry; this changes the last bits, not the accuracy);
/// * tests the pivot against 1e-13·|a_ii| with a bound on the modulus first and takes the
///   exact `hypot` only when the bound cannot decide (the same test, without a `hypot` per
///   row).
///
/// Nothing is allocated after [`DynamicStiffness::new`].
pub struct DynamicStiffness {
    /// First stored column of each row and the offset of its first entry (n + 1 offsets).
    first: Vec<usize>,
    start: Vec<usize>,
    /// K, M, C on the envelope (N/m, kg, N·s/m in each DOF's units).
    k: Vec<f64>,
    m: Vec<f64>,
    c: Vec<f64>,
    /// L strictly below the diagonal, D on it, after [`DynamicStiffness::factorize`].
    values: Vec<Complex64>,
    /// 1/d_i.
    inv_d: Vec<Complex64>,
    factorized: bool,
    omega: f64,
}

impl DynamicStiffness {
    pub fn new(k: &Csr, m: &Csr, c: &Csr, envelope: &[usize]) -> Self {
        let to_sky = |a: &Csr| {
            let mut s = Skyline::<f64>::zeros(envelope.to_vec());
            a.add_into_skyline(1.0, &mut s);
            s.into_values()
        };
        let n = envelope.len();
        let mut start = Vec::with_capacity(n + 1);
        let mut off = 0;
        for (i, &f) in envelope.iter().enumerate() {
            start.push(off);
            off += i - f + 1;
        }
        start.push(off);
        DynamicStiffness {
            first: envelope.to_vec(),
            start,
            k: to_sky(k),
            m: to_sky(m),
            c: to_sky(c),
            values: vec![Complex64::default(); off],
            inv_d: vec![Complex64::default(); n],
            factorized: false,
            omega: f64::NAN,
        }
    }

    pub fn dim(&self) -> usize {
        self.first.len()
    }

    /// Factorises K − ω²M + iωC for circular frequency ω (rad/s). Fails on a zero, tiny
    /// or non-finite pivot (a singular system, e.g. undamped at a resonance).
    pub fn factorize(&mut self, omega: f64) -> Result<()> {
        self.factorized = false;
        let w2 = -omega * omega;
        for (((v, &k), &m), &c) in self.values.iter_mut().zip(&self.k).zip(&self.m).zip(&self.c) {
            *v = Complex64::new(k + w2 * m, omega * c);
        }
        let n = self.dim();
        for i in 0..n {
            let fi = self.first[i];
            let si = self.start[i];
            let (done, rest) = self.values.split_at_mut(si);
            let row = &mut rest[..i - fi + 1];
            let a_ii = row[i - fi];
            // Row i holds a_ij; turn it into g_ij = l_ij·d_j, column by column.
            for j in fi..i {
                let fj = self.first[j];
                let lo = fi.max(fj);
                let rj = &done[self.start[j] + (lo - fj)..self.start[j] + (j - fj)];
                let ri = &row[lo - fi..j - fi];
                let mut s = Complex64::default();
                for (a, b) in ri.iter().zip(rj) {
                    s += a * b;
                }
                row[j - fi] -= s;
            }
            // d_i = a_ii − Σ g_ij²/d_j, and l_ij = g_ij/d_j.
            let mut d = a_ii;
            for (g, inv) in row[..i - fi].iter_mut().zip(&self.inv_d[fi..i]) {
                let l = *g * inv;
                d -= *g * l;
                *g = l;
            }
            check_pivot(i, d, a_ii)?;
            row[i - fi] = d;
            let s = 1.0 / d.norm_sqr();
            self.inv_d[i] = Complex64::new(d.re * s, -d.im * s);
        }
        self.factorized = true;
        self.omega = omega;
        Ok(())
    }

    /// Solves for the complex amplitudes Q at the last factorised frequency (in place).
    pub fn solve_in_place(&self, x: &mut [Complex64]) {
        assert!(self.factorized, "factorize before solve");
        let n = self.dim();
        assert_eq!(x.len(), n);
        // L·y = b, row by row.
        for i in 0..n {
            let fi = self.first[i];
            let row = &self.values[self.start[i]..self.start[i] + (i - fi)];
            let mut s = Complex64::default();
            for (l, xk) in row.iter().zip(&x[fi..i]) {
                s += l * xk;
            }
            x[i] -= s;
        }
        // D·z = y.
        for (xi, inv) in x.iter_mut().zip(&self.inv_d) {
            *xi *= inv;
        }
        // Lᵀ·x = z, column-oriented over the same rows.
        for i in (0..n).rev() {
            let fi = self.first[i];
            let xi = x[i];
            let row = &self.values[self.start[i]..self.start[i] + (i - fi)];
            for (l, xk) in row.iter().zip(&mut x[fi..i]) {
                *xk -= l * xi;
            }
        }
    }

    pub fn omega(&self) -> f64 {
        self.omega
    }
}

/// The pivot test of [`crate::linalg::SkylineLdlt`]: d must be finite and
/// |d| > 1e-13·max(|a_ii|, MIN_POSITIVE). max(|re|, |im|) ≤ |z| ≤ √2·max(|re|, |im|) decides
/// almost every pivot without a `hypot`.
#[inline]
fn check_pivot(i: usize, d: Complex64, a_ii: Complex64) -> Result<()> {
    let inf = |z: Complex64| z.re.abs().max(z.im.abs());
    let finite = d.re.is_finite() && d.im.is_finite();
    if finite && inf(d) > 1e-13 * std::f64::consts::SQRT_2 * inf(a_ii).max(f64::MIN_POSITIVE) {
        return Ok(());
    }
    let scale = a_ii.norm().max(f64::MIN_POSITIVE);
    if !finite || d.norm() <= 1e-13 * scale {
        return Err(Error::Numerical(format!(
            "LDLᵀ pivot {i} is {d:?} (diagonal {a_ii:?}): the system is singular or nearly so — is the structure supported?"
        )));
    }
    Ok(())
}

/// Time-averaged power dissipated by a viscous matrix C in harmonic motion Q at ω:
/// ½·ω²·Qᴴ·C·Q (W).
pub fn dissipated_power(c: &Csr, q: &[Complex64], omega: f64) -> f64 {
    0.5 * omega * omega * c.hermitian_form(q)
}

/// Time-averaged power ½·Re(F·conj(V)) (W) of force and velocity amplitudes.
pub fn mean_power(f: Complex64, v: Complex64) -> f64 {
    0.5 * (f * v.conj()).re
}
