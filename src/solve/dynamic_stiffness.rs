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
/// * builds K − ω²M + iωC entry by entry from K, M and C in the profile's order;
/// * keeps 1/d_j and multiplies by it instead of dividing by d_j (one real division per row
///   instead of two per entry; this changes the last bits, not the accuracy);
/// * tests the pivot against 1e-13·|a_ii| with a bound on the modulus first and takes the
///   exact `hypot` only when the bound cannot decide (the same test, without a `hypot` per
///   row);
/// * factorises a band's rows (a beam's are three wide) in loops of fixed length: the same
///   operations in the same order as for any profile, without a loop of unknown length
///   per entry.
///
/// Two frequencies can be factorised and solved at once ([`DynamicStiffness::factorize_pair`],
/// [`DynamicStiffness::solve_pair`]). A factorisation of this size is a chain of dependent
/// operations (each pivot waits for the previous rows, and on a division), so one alone
/// leaves the core mostly idle; two independent chains, row by row in the same loop, run in
/// about the time of one. Each frequency gets exactly the operations it gets alone, so the
/// results do not depend on the pairing, bit for bit.
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
    /// The imaginary stiffness η·K_beam of hysteretic damping (zeros without).
    kl: Vec<f64>,
    /// Each row's band ([`Band`]).
    bands: Vec<Band>,
    /// Two factorisations: [`DynamicStiffness::factorize`] fills the first.
    lanes: [Factor; 2],
}

/// Rows this narrow or narrower are factorised in loops of fixed length.
const NARROW: usize = 3;

/// A row's band for the factorisation: its width i − first[i] where that is at most
/// [`NARROW`] and every row it meets starts no later than it does (a band's rows do; an
/// actuator body's long row does not), else [`Band::WIDE`].
#[derive(Clone, Copy, Debug)]
struct Band(u8);

impl Band {
    const WIDE: Band = Band(u8::MAX);

    fn of(first: &[usize], i: usize) -> Band {
        let w = i - first[i];
        if w <= NARROW && (first[i]..i).all(|j| first[j] <= first[i]) {
            Band(w as u8)
        } else {
            Self::WIDE
        }
    }
}

/// L strictly below the diagonal and D on it, and 1/d_i, of one frequency.
struct Factor {
    values: Vec<Complex64>,
    inv_d: Vec<Complex64>,
    factorized: bool,
    omega: f64,
    /// The coefficients of K + c_m·M + c_c·C factorised.
    c_m: Complex64,
    c_c: Complex64,
}

impl Factor {
    fn new(profile: usize, n: usize) -> Self {
        Factor {
            values: vec![Complex64::default(); profile],
            inv_d: vec![Complex64::default(); n],
            factorized: false,
            omega: f64::NAN,
            c_m: Complex64::default(),
            c_c: Complex64::default(),
        }
    }

    /// K − ω²M + iωC on the envelope.
    fn fill(&mut self, k: &[f64], m: &[f64], c: &[f64], kl: &[f64], omega: f64) {
        self.factorized = false;
        self.omega = omega;
        let w2 = -omega * omega;
        (self.c_m, self.c_c) = (Complex64::new(w2, 0.0), Complex64::new(0.0, omega));
        for ((((v, &k), &m), &c), &kl) in self.values.iter_mut().zip(k).zip(m).zip(c).zip(kl) {
            *v = Complex64::new(k + w2 * m, omega * c + kl);
        }
    }

    /// K + c_m·M + c_c·C on the envelope.
    fn fill_general(&mut self, k: &[f64], m: &[f64], c: &[f64], kl: &[f64], c_m: Complex64, c_c: Complex64) {
        self.factorized = false;
        self.omega = f64::NAN;
        (self.c_m, self.c_c) = (c_m, c_c);
        for ((((v, &k), &m), &c), &kl) in self.values.iter_mut().zip(k).zip(m).zip(c).zip(kl) {
            *v = Complex64::new(k, kl) + c_m * m + c_c * c;
        }
    }

    /// Factorises row i, rows before it being done.
    #[inline(always)]
    fn row(&mut self, first: &[usize], start: &[usize], band: Band, i: usize) -> Result<()> {
        match band.0 {
            0 => self.row_narrow::<0>(first, start, i),
            1 => self.row_narrow::<1>(first, start, i),
            2 => self.row_narrow::<2>(first, start, i),
            3 => self.row_narrow::<3>(first, start, i),
            _ => self.row_any(first, start, i),
        }
    }

    /// [`Factor::row_any`] for a row of width W whose rows met start no later than it
    /// does: the same operations in the same order, in loops of fixed length.
    #[inline(always)]
    fn row_narrow<const W: usize>(&mut self, first: &[usize], start: &[usize], i: usize) -> Result<()> {
        let fi = i - W;
        let (done, rest) = self.values.split_at_mut(start[i]);
        let row = &mut rest[..W + 1];
        let a_ii = row[W];
        for jj in 0..W {
            let j = fi + jj;
            let from = start[j] + (fi - first[j]);
            let rj = &done[from..from + jj];
            let mut s = Complex64::default();
            for t in 0..jj {
                s += row[t] * rj[t];
            }
            row[jj] -= s;
        }
        let inv_d = &self.inv_d[fi..i];
        let mut d = a_ii;
        for t in 0..W {
            let l = row[t] * inv_d[t];
            d -= row[t] * l;
            row[t] = l;
        }
        check_pivot(i, d, a_ii)?;
        row[W] = d;
        let s = 1.0 / d.norm_sqr();
        self.inv_d[i] = Complex64::new(d.re * s, -d.im * s);
        Ok(())
    }

    /// Factorises row i of any profile, rows before it being done.
    #[inline(always)]
    fn row_any(&mut self, first: &[usize], start: &[usize], i: usize) -> Result<()> {
        let fi = first[i];
        let (done, rest) = self.values.split_at_mut(start[i]);
        let row = &mut rest[..i - fi + 1];
        let a_ii = row[i - fi];
        // Row i holds a_ij; turn it into g_ij = l_ij·d_j, column by column.
        for j in fi..i {
            let fj = first[j];
            let lo = fi.max(fj);
            let rj = &done[start[j] + (lo - fj)..start[j] + (j - fj)];
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
        Ok(())
    }

    /// L·y = b for row i (x holds b, rows before i hold y).
    #[inline(always)]
    fn forward(&self, first: &[usize], start: &[usize], i: usize, x: &mut [Complex64]) {
        let fi = first[i];
        let row = &self.values[start[i]..start[i] + (i - fi)];
        let mut s = Complex64::default();
        for (l, xk) in row.iter().zip(&x[fi..i]) {
            s += l * xk;
        }
        x[i] -= s;
    }

    /// Lᵀ·x = z, the column of row i (x[i] final).
    #[inline(always)]
    fn backward(&self, first: &[usize], start: &[usize], i: usize, x: &mut [Complex64]) {
        let fi = first[i];
        let xi = x[i];
        let row = &self.values[start[i]..start[i] + (i - fi)];
        for (l, xk) in row.iter().zip(&mut x[fi..i]) {
            *xk -= l * xi;
        }
    }

    fn scale(&self, x: &mut [Complex64]) {
        for (xi, inv) in x.iter_mut().zip(&self.inv_d) {
            *xi *= inv;
        }
    }
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
            bands: (0..n).map(|i| Band::of(envelope, i)).collect(),
            first: envelope.to_vec(),
            start,
            k: to_sky(k),
            m: to_sky(m),
            c: to_sky(c),
            kl: vec![0.0; off],
            lanes: [Factor::new(off, n), Factor::new(off, n)],
        }
    }

    /// The dynamic stiffness of an assembled system: K − ω²M + iωC, plus i·η·K_beam when
    /// the structure is hysteretically damped.
    pub fn of(sys: &crate::assembly::System) -> Self {
        let mut d = DynamicStiffness::new(&sys.k, &sys.m, &sys.c, &sys.envelope);
        if let Some(kl) = &sys.k_loss {
            let mut s = Skyline::<f64>::zeros(sys.envelope.clone());
            kl.add_into_skyline(1.0, &mut s);
            d.kl = s.into_values();
        }
        d
    }

    pub fn dim(&self) -> usize {
        self.first.len()
    }

    /// Factorises K − ω²M + iωC for circular frequency ω (rad/s). Fails on a zero, tiny
    /// or non-finite pivot (a singular system, e.g. undamped at a resonance).
    pub fn factorize(&mut self, omega: f64) -> Result<()> {
        let [a, _] = &mut self.lanes;
        a.fill(&self.k, &self.m, &self.c, &self.kl, omega);
        for i in 0..self.first.len() {
            a.row(&self.first, &self.start, self.bands[i], i)?;
        }
        a.factorized = true;
        Ok(())
    }

    /// Factorises K + c_m·M + c_c·C for complex coefficients: the periodic response of a
    /// time-stepping scheme is a dynamic stiffness of this form (c_m = −ω², c_c = iω for the
    /// continuous system). Fails as [`DynamicStiffness::factorize`] does.
    pub fn factorize_general(&mut self, c_m: Complex64, c_c: Complex64) -> Result<()> {
        let [a, _] = &mut self.lanes;
        a.fill_general(&self.k, &self.m, &self.c, &self.kl, c_m, c_c);
        for i in 0..self.first.len() {
            a.row(&self.first, &self.start, self.bands[i], i)?;
        }
        a.factorized = true;
        Ok(())
    }

    /// Factorises at ω_a and ω_b (rad/s) at once, for [`DynamicStiffness::solve_pair`];
    /// each as [`DynamicStiffness::factorize`] would. The first frequency is also the one
    /// [`DynamicStiffness::solve_in_place`] then solves at.
    pub fn factorize_pair(&mut self, omega_a: f64, omega_b: f64) -> Result<()> {
        let [a, b] = &mut self.lanes;
        a.fill(&self.k, &self.m, &self.c, &self.kl, omega_a);
        b.fill(&self.k, &self.m, &self.c, &self.kl, omega_b);
        for i in 0..self.first.len() {
            a.row(&self.first, &self.start, self.bands[i], i)?;
            b.row(&self.first, &self.start, self.bands[i], i)?;
        }
        a.factorized = true;
        b.factorized = true;
        Ok(())
    }

    /// Solves for the complex amplitudes Q at the last factorised frequency (in place).
    pub fn solve_in_place(&self, x: &mut [Complex64]) {
        self.solve_lane(0, x);
    }

    /// Solves with factorisation `lane` (0: the one [`DynamicStiffness::factorize`] and
    /// the first of [`DynamicStiffness::factorize_pair`] fill, 1: the pair's second), in
    /// place: what a refinement of either of a pair's solutions needs.
    pub fn solve_lane(&self, lane: usize, x: &mut [Complex64]) {
        let a = &self.lanes[lane];
        assert!(a.factorized, "factorize before solve");
        let n = self.dim();
        assert_eq!(x.len(), n);
        for i in 0..n {
            a.forward(&self.first, &self.start, i, x);
        }
        a.scale(x);
        for i in (0..n).rev() {
            a.backward(&self.first, &self.start, i, x);
        }
    }

    /// Solves at the two frequencies of the last [`DynamicStiffness::factorize_pair`], `xa`
    /// at ω_a and `xb` at ω_b (in place).
    pub fn solve_pair(&self, xa: &mut [Complex64], xb: &mut [Complex64]) {
        let [a, b] = &self.lanes;
        assert!(a.factorized && b.factorized, "factorize_pair before solve_pair");
        let n = self.dim();
        assert!(xa.len() == n && xb.len() == n);
        for i in 0..n {
            a.forward(&self.first, &self.start, i, xa);
            b.forward(&self.first, &self.start, i, xb);
        }
        a.scale(xa);
        b.scale(xb);
        for i in (0..n).rev() {
            a.backward(&self.first, &self.start, i, xa);
            b.backward(&self.first, &self.start, i, xb);
        }
    }

    /// Solves one or two right-hand sides in place, `xs[l]` with lane l: [`Self::solve_pair`]
    /// for two (the last [`Self::factorize_pair`]), [`Self::solve_lane`] 0 for one.
    pub fn solve_lanes(&self, xs: &mut [Vec<Complex64>]) {
        match xs {
            [a, b] => self.solve_pair(a, b),
            [a] => self.solve_lane(0, a),
            _ => panic!("one or two right-hand sides, not {}", xs.len()),
        }
    }

    /// The coefficients (c_m, c_c) of K + c_m·M + c_c·C factorised in `lane`.
    pub fn coefficients(&self, lane: usize) -> (Complex64, Complex64) {
        (self.lanes[lane].c_m, self.lanes[lane].c_c)
    }

    /// The (first) frequency factorised last (rad/s).
    pub fn omega(&self) -> f64 {
        self.lanes[0].omega
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
        return Err(Error::Singular {
            row: i,
            detail: format!("LDLᵀ pivot {d:?} against the diagonal {a_ii:?}: the system is singular or nearly so"),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chain of masses and spring–dampers with one long row (like an actuator's body).
    fn chain(n: usize) -> (Csr, Csr, Csr, Vec<usize>) {
        let (mut k, mut m, mut c) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..n {
            m.push((i, i, 1.0 + 0.1 * i as f64));
            k.push((i, i, 2000.0 + 10.0 * i as f64));
            c.push((i, i, 0.3));
            if i > 0 {
                for (t, v) in [(&mut k, -900.0), (&mut c, -0.1)] {
                    t.push((i, i - 1, v));
                    t.push((i - 1, i, v));
                }
            }
        }
        k.push((n - 1, 2, -50.0));
        k.push((2, n - 1, -50.0));
        let envelope = Skyline::<f64>::envelope_of(n, k.iter().map(|&(i, j, _)| (i, j)));
        (Csr::from_triplets(n, &k), Csr::from_triplets(n, &m), Csr::from_triplets(n, &c), envelope)
    }

    /// The fixed-length loops of narrow rows give the bits of the loops for any profile, on
    /// a band of width three (a beam's) with one long row: the factor and its solves.
    #[test]
    fn narrow_rows_give_the_bits_of_any_profile() {
        let n = 30;
        let (mut k, mut m, mut c) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..n {
            m.push((i, i, 1.0 + 0.1 * i as f64));
            k.push((i, i, 5000.0 + 10.0 * i as f64));
            c.push((i, i, 0.3));
            for d in 1..=3.min(i) {
                let v = -(900.0 + 37.0 * d as f64) / d as f64 + 0.01 * i as f64;
                for (t, v) in [(&mut k, v), (&mut m, 0.01 * v), (&mut c, -0.1 / d as f64)] {
                    t.push((i, i - d, v));
                    t.push((i - d, i, v));
                }
            }
        }
        k.push((n - 1, 2, -50.0));
        k.push((2, n - 1, -50.0));
        let envelope = Skyline::<f64>::envelope_of(n, k.iter().map(|&(i, j, _)| (i, j)));
        let (k, m, c) = (Csr::from_triplets(n, &k), Csr::from_triplets(n, &m), Csr::from_triplets(n, &c));
        let mut narrow = DynamicStiffness::new(&k, &m, &c, &envelope);
        let mut any = DynamicStiffness::new(&k, &m, &c, &envelope);
        assert!(narrow.bands.iter().filter(|b| b.0 == 3).count() > n / 2);
        any.bands.iter_mut().for_each(|b| *b = Band::WIDE);
        let bits = |x: &[Complex64]| x.iter().flat_map(|z| [z.re.to_bits(), z.im.to_bits()]).collect::<Vec<_>>();
        let b: Vec<Complex64> = (0..n).map(|i| Complex64::new(1.0 / (1.0 + i as f64), 0.1 * i as f64)).collect();
        for dk in [&mut narrow, &mut any] {
            dk.factorize_pair(17.0, 41.5).unwrap();
        }
        for l in 0..2 {
            assert_eq!(bits(&narrow.lanes[l].values), bits(&any.lanes[l].values));
            assert_eq!(bits(&narrow.lanes[l].inv_d), bits(&any.lanes[l].inv_d));
            let (mut x, mut y) = (b.clone(), b.clone());
            narrow.solve_lane(l, &mut x);
            any.solve_lane(l, &mut y);
            assert_eq!(bits(&x), bits(&y));
        }
    }

    #[test]
    fn pairs_give_the_bits_of_single_solves_and_solve_the_system() {
        let (k, m, c, env) = chain(14);
        let mut dk = DynamicStiffness::new(&k, &m, &c, &env);
        let b: Vec<Complex64> = (0..14).map(|i| Complex64::new(1.0 / (1.0 + i as f64), 0.1 * i as f64)).collect();
        let (wa, wb) = (17.0, 41.5);
        let mut single = Vec::new();
        for w in [wa, wb] {
            dk.factorize(w).unwrap();
            let mut x = b.clone();
            dk.solve_in_place(&mut x);
            // The residual of (K − ω²M + iωC)·x = b.
            let (mut kx, mut mx, mut cx) =
                (vec![Complex64::default(); 14], vec![Complex64::default(); 14], vec![Complex64::default(); 14]);
            k.mul_vec(&x, &mut kx);
            m.mul_vec(&x, &mut mx);
            c.mul_vec(&x, &mut cx);
            for i in 0..14 {
                let r = kx[i] - mx[i] * (w * w) + cx[i] * Complex64::new(0.0, w) - b[i];
                assert!(r.norm() < 1e-12, "ω = {w}, row {i}: residual {r}");
            }
            single.push(x);
        }
        dk.factorize_pair(wa, wb).unwrap();
        let (mut xa, mut xb) = (b.clone(), b.clone());
        dk.solve_pair(&mut xa, &mut xb);
        let bits = |x: &[Complex64]| x.iter().flat_map(|z| [z.re.to_bits(), z.im.to_bits()]).collect::<Vec<_>>();
        assert_eq!(bits(&xa), bits(&single[0]));
        assert_eq!(bits(&xb), bits(&single[1]));
    }
}
