//! The fast path of the Newmark family for linear systems: one step in two streaming passes.
//!
//! [`Newmark`](super::newmark::Newmark) does a step as the textbook writes it: build two
//! work vectors, two sparse products, a forward sweep, a diagonal scaling, a backward sweep
//! and an update, each a separate pass over n-vectors, plus whatever the caller does with
//! full load vectors and velocity copies. Per degree of freedom a step is only a few dozen
//! flops, so those passes and the sparse index arithmetic, not the flops, set the cost. This
//! kernel does the same arithmetic in two passes:
//!
//! 1. **Forward** (row i ascending): form w₁ᵢ, w₂ᵢ (the M- and C-parts of the known history),
//!    add row i of the symmetric products M·w₁ + C·w₂ (− α_f·K·u) — the row's own sum and its
//!    mirror scattered to earlier rows — plus the load, and forward-substitute L·y = rhs for
//!    every row whose right-hand side is complete. Row r is complete once every row that
//!    reaches back to column r has been added, i.e. after row `reach[r]`.
//! 2. **Backward** (row i descending): xᵢ = yᵢ/dᵢ minus the Lᵀ terms already scattered,
//!    which is the new displacement; update aᵢ, vᵢ, uᵢ in place; and, if asked, accumulate
//!    the midpoint dissipation v̄ᵀ·C·v̄ with the same row of C.
//!
//! Storage. M, C, K and the factor share the effective stiffness's envelope. A beam's rows
//! all reach back at most a few columns (3 for Hermite elements), an actuator's body rows
//! much further. So each matrix is a dense band of fixed half-width B (row i holds columns
//! i−B..=i, zero-padded) plus, for the few rows that reach further, a contiguous tail.
//! With B a compile-time constant the band loops unroll completely; the vectors the band
//! reads at j < i carry B leading zeros so the first rows need no special case. No column
//! indices are stored, loads are sparse (actuators load a handful of DOFs), and nothing in
//! a step allocates.
//!
//! The arithmetic is that of `Newmark::step` with the sums taken in a different order, so
//! the two agree to round-off (`tests/newmark.rs` checks it).

use super::newmark::Scheme;
use crate::error::{Error, Result};
use crate::linalg::{Csr, Skyline};

/// Widths with an unrolled kernel; wider bands (dense reduced systems) use the same code
/// with the width known only at run time.
const FIXED_WIDTHS: [usize; 6] = [0, 1, 2, 3, 4, 5];

/// A row that reaches back beyond the band: columns `first..row − B` live in the tails.
#[derive(Clone, Copy, Debug)]
struct LongRow {
    row: usize,
    first: usize,
    offset: usize,
}

/// A symmetric (or unit-lower) matrix as band + tails in a shared layout.
#[derive(Clone, Debug)]
struct BandMatrix {
    /// n × (B+1), row-major; entry t of row i is column i − B + t.
    band: Vec<f64>,
    tail: Vec<f64>,
}

#[derive(Clone, Debug)]
struct Layout {
    n: usize,
    b: usize,
    long: Vec<LongRow>,
    /// Last row that reaches back to column r, as a running maximum (completion order).
    reach: Vec<usize>,
}

impl Layout {
    fn new(first: &[usize]) -> Self {
        let n = first.len();
        let mut widths: Vec<usize> = first.iter().enumerate().map(|(i, &f)| i - f).collect();
        widths.sort_unstable();
        // Cover nine rows in ten with the band; the rest become tails. The widths with an
        // unrolled kernel are preferred when one covers the same rows.
        let p90 = widths.get((n * 9) / 10).copied().unwrap_or(0);
        let b = FIXED_WIDTHS.iter().copied().find(|&w| w >= p90).unwrap_or(p90);
        let mut long = Vec::new();
        let mut offset = 0;
        for (i, &f) in first.iter().enumerate() {
            if i > b && f < i - b {
                long.push(LongRow { row: i, first: f, offset });
                offset += i - b - f;
            }
        }
        let mut reach: Vec<usize> = (0..n).collect();
        for (i, &f) in first.iter().enumerate() {
            for r in reach.iter_mut().take(i).skip(f) {
                *r = (*r).max(i);
            }
        }
        for r in 1..n {
            reach[r] = reach[r].max(reach[r - 1]);
        }
        Layout { n, b, long, reach }
    }

    /// Splits skyline values (rows from `first[i]` to the diagonal) into band and tails.
    fn split(&self, first: &[usize], values: &[f64]) -> BandMatrix {
        let (n, b) = (self.n, self.b);
        let mut band = vec![0.0; n * (b + 1)];
        let mut tail = vec![0.0; self.long.iter().map(|lr| lr.row - b - lr.first).sum()];
        let mut k = 0;
        let mut lp = 0;
        for (i, &f) in first.iter().enumerate() {
            for j in f..=i {
                let v = values[k];
                k += 1;
                if j + b >= i {
                    band[i * (b + 1) + (j + b - i)] = v;
                } else {
                    let lr = self.long[lp];
                    debug_assert_eq!(lr.row, i);
                    tail[lr.offset + (j - lr.first)] = v;
                }
            }
            if lp < self.long.len() && self.long[lp].row == i {
                lp += 1;
            }
        }
        BandMatrix { band, tail }
    }
}

/// The band half-width as a type, so that fixed widths unroll.
trait Width: Copy {
    fn b(self) -> usize;
}
#[derive(Clone, Copy)]
struct Fixed<const B: usize>;
impl<const B: usize> Width for Fixed<B> {
    #[inline(always)]
    fn b(self) -> usize {
        B
    }
}
#[derive(Clone, Copy)]
struct Dynamic(usize);
impl Width for Dynamic {
    #[inline(always)]
    fn b(self) -> usize {
        self.0
    }
}

/// The step's coefficients: w₁ = c_u·u + c_v·v + c_a·a, w₂ = e_u·u + e_v·v + e_a·a, and the
/// update a_new = (x − u − Δt·v)·ab − a_old·a, v_new = v + va_old·a + va_new·a_new.
#[derive(Clone, Copy)]
struct Coeffs {
    cu: f64,
    cv: f64,
    ca: f64,
    eu: f64,
    ev: f64,
    ea: f64,
    af: f64,
    dt: f64,
    ab: f64,
    a_old: f64,
    va_old: f64,
    va_new: f64,
}

/// A linear system's Newmark integrator with the fused two-pass step.
pub struct FusedNewmark {
    scheme: Scheme,
    dt: f64,
    layout: Layout,
    m: BandMatrix,
    c: BandMatrix,
    /// Only when α_f ≠ 0.
    k: Option<BandMatrix>,
    /// Unit-lower L of K_eff = L·D·Lᵀ (its diagonal slot holds D).
    l: BandMatrix,
    /// D and 1/D, with B leading zeros (padded like the work vectors).
    d: Vec<f64>,
    d_inv: Vec<f64>,
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    /// Padded by B: right-hand side, then y, then x, of the step in progress.
    z: Vec<f64>,
    w1: Vec<f64>,
    w2: Vec<f64>,
    /// Padded copy of u (only read when α_f ≠ 0).
    up: Vec<f64>,
    /// Padded: Σ_{k>i} c_ki·v̄_k, accumulated in the backward pass for the dissipation.
    acc: Vec<f64>,
    /// Dense load of the step in progress, zero except at the DOFs just loaded.
    load: Vec<f64>,
    touched: Vec<usize>,
    /// F_n, kept for α_f ≠ 0.
    f_prev: Vec<(usize, f64)>,
    /// Accumulate Δt·v̄ᵀ·C·v̄ during the backward pass.
    pub track_dissipation: bool,
}

impl FusedNewmark {
    /// Sets up the integrator and factorises the effective stiffness. `envelope` must cover
    /// the patterns of M, C and K.
    pub fn new(m: &Csr, c: &Csr, k: &Csr, envelope: &[usize], scheme: Scheme, dt: f64) -> Result<Self> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(Error::Numerical(format!("time step must be positive, got {dt}")));
        }
        let n = m.dim();
        let s = scheme;
        let profile = |a: &Csr, scale: f64| {
            let mut sk = Skyline::<f64>::zeros(envelope.to_vec());
            a.add_into_skyline(scale, &mut sk);
            sk
        };
        let mut k_eff = profile(k, 1.0 - s.alpha_f);
        c.add_into_skyline((1.0 - s.alpha_f) * s.gamma / (s.beta * dt), &mut k_eff);
        m.add_into_skyline((1.0 - s.alpha_m) / (s.beta * dt * dt), &mut k_eff);
        let (first, _, l, d) = k_eff.factorize()?.into_parts();
        let layout = Layout::new(&first);
        let b = layout.b;
        let padded = |x: &[f64]| [vec![0.0; b], x.to_vec()].concat();
        Ok(FusedNewmark {
            scheme,
            dt,
            m: layout.split(&first, &profile(m, 1.0).into_values()),
            c: layout.split(&first, &profile(c, 1.0).into_values()),
            k: (s.alpha_f != 0.0).then(|| layout.split(&first, &profile(k, 1.0).into_values())),
            l: layout.split(&first, &l),
            d_inv: padded(&d.iter().map(|x| 1.0 / x).collect::<Vec<_>>()),
            d: padded(&d),
            layout,
            u: vec![0.0; n],
            v: vec![0.0; n],
            a: vec![0.0; n],
            z: vec![0.0; n + b],
            w1: vec![0.0; n + b],
            w2: vec![0.0; n + b],
            up: vec![0.0; n + b],
            acc: vec![0.0; n + b],
            load: vec![0.0; n],
            touched: Vec::new(),
            f_prev: Vec::new(),
            track_dissipation: false,
        })
    }

    pub fn dt(&self) -> f64 {
        self.dt
    }

    pub fn dim(&self) -> usize {
        self.u.len()
    }

    /// Half-width of the band part of the storage (rows reaching further have tails).
    pub fn band_width(&self) -> usize {
        self.layout.b
    }

    /// Displacement, velocity and acceleration at the current time.
    pub fn u(&self) -> &[f64] {
        &self.u
    }
    pub fn v(&self) -> &[f64] {
        &self.v
    }
    pub fn a(&self) -> &[f64] {
        &self.a
    }

    /// Starts from displacement u₀, velocity v₀ and acceleration a₀ (which should be the
    /// consistent one, M⁻¹·(F₀ − C·v₀ − K·u₀)), with load F₀ as sparse pairs.
    pub fn set_state(&mut self, u0: &[f64], v0: &[f64], a0: &[f64], f0: &[(usize, f64)]) {
        self.u.copy_from_slice(u0);
        self.v.copy_from_slice(v0);
        self.a.copy_from_slice(a0);
        self.f_prev.clear();
        self.f_prev.extend_from_slice(f0);
    }

    /// Advances one step to the load F_{n+1} (sparse pairs, duplicates summed). Returns
    /// Δt·v̄ᵀ·C·v̄ with v̄ the step's mean velocity if `track_dissipation` is set, else 0.
    pub fn step(&mut self, f_next: &[(usize, f64)]) -> f64 {
        let s = self.scheme;
        let dt = self.dt;
        let (am, af, g, b) = (s.alpha_m, s.alpha_f, s.gamma, s.beta);
        for &(d, f) in f_next {
            self.load[d] += (1.0 - af) * f;
            self.touched.push(d);
        }
        if af != 0.0 {
            for &(d, f) in &self.f_prev {
                self.load[d] += af * f;
                self.touched.push(d);
            }
        }
        let cu = (1.0 - am) / (b * dt * dt);
        let k = Coeffs {
            cu,
            cv: cu * dt,
            ca: (1.0 - am) * (0.5 / b - 1.0) - am,
            eu: (1.0 - af) * g / (b * dt),
            ev: -(1.0 - af) * (1.0 - g / b) - af,
            ea: -(1.0 - af) * dt * (1.0 - 0.5 * g / b),
            af,
            dt,
            ab: 1.0 / (b * dt * dt),
            a_old: 0.5 / b - 1.0,
            va_old: dt * (1.0 - g),
            va_new: dt * g,
        };
        let diss = match self.layout.b {
            0 => self.run(Fixed::<0>, k),
            1 => self.run(Fixed::<1>, k),
            2 => self.run(Fixed::<2>, k),
            3 => self.run(Fixed::<3>, k),
            4 => self.run(Fixed::<4>, k),
            5 => self.run(Fixed::<5>, k),
            w => self.run(Dynamic(w), k),
        };
        for &d in &self.touched {
            self.load[d] = 0.0;
        }
        self.touched.clear();
        if af != 0.0 {
            self.f_prev.clear();
            self.f_prev.extend_from_slice(f_next);
        }
        diss * dt
    }

    fn run<W: Width>(&mut self, w: W, k: Coeffs) -> f64 {
        if self.k.is_some() {
            self.up[w.b()..].copy_from_slice(&self.u);
        }
        self.forward(w, k);
        self.backward(w, k)
    }

    #[inline(never)]
    fn forward<W: Width>(&mut self, w: W, k: Coeffs) {
        let b = w.b();
        let n = self.layout.n;
        let mut lp = 0;
        let mut next = 0; // next row to forward-substitute
        let mut lsp = 0; // next long row among those
        for i in 0..n {
            let (ui, vi, ai) = (self.u[i], self.v[i], self.a[i]);
            let w1i = k.cu * ui + k.cv * vi + k.ca * ai;
            let w2i = k.eu * ui + k.ev * vi + k.ea * ai;
            // Padded index of column j is j + b; row i's band starts at column i − b.
            self.w1[i + b] = w1i;
            self.w2[i + b] = w2i;
            let mrow = &self.m.band[i * (b + 1)..(i + 1) * (b + 1)];
            let crow = &self.c.band[i * (b + 1)..(i + 1) * (b + 1)];
            let w1 = &self.w1[i..i + b];
            let w2 = &self.w2[i..i + b];
            let mut sum = mrow[b] * w1i + crow[b] * w2i + self.load[i];
            {
                let z = &mut self.z[i..i + b];
                for t in 0..b {
                    sum += mrow[t] * w1[t] + crow[t] * w2[t];
                    z[t] += mrow[t] * w1i + crow[t] * w2i;
                }
            }
            if let Some(kk) = &self.k {
                let krow = &kk.band[i * (b + 1)..(i + 1) * (b + 1)];
                let up = &self.up[i..=i + b];
                let z = &mut self.z[i..i + b];
                sum -= k.af * krow[b] * ui;
                for t in 0..b {
                    sum -= k.af * krow[t] * up[t];
                    z[t] -= k.af * krow[t] * ui;
                }
            }
            if lp < self.layout.long.len() && self.layout.long[lp].row == i {
                let lr = self.layout.long[lp];
                let len = i - b - lr.first;
                let (mt, ct) = (&self.m.tail[lr.offset..lr.offset + len], &self.c.tail[lr.offset..lr.offset + len]);
                let cols = lr.first + b..lr.first + b + len;
                for (t, j) in cols.clone().enumerate() {
                    sum += mt[t] * self.w1[j] + ct[t] * self.w2[j];
                    self.z[j] += mt[t] * w1i + ct[t] * w2i;
                }
                if let Some(kk) = &self.k {
                    let kt = &kk.tail[lr.offset..lr.offset + len];
                    for (t, j) in cols.enumerate() {
                        sum -= k.af * kt[t] * self.up[j];
                        self.z[j] -= k.af * kt[t] * ui;
                    }
                }
                lp += 1;
            }
            self.z[i + b] = sum;
            while next <= i && self.layout.reach[next] <= i {
                self.forward_substitute(w, next, &mut lsp);
                next += 1;
            }
        }
        while next < n {
            self.forward_substitute(w, next, &mut lsp);
            next += 1;
        }
    }

    /// y_r = rhs_r − Σ_j l_rj·y_j over the band and, for a long row, its tail.
    #[inline(always)]
    fn forward_substitute<W: Width>(&mut self, w: W, r: usize, lp: &mut usize) {
        let b = w.b();
        let row = &self.l.band[r * (b + 1)..r * (b + 1) + b];
        let y = &self.z[r..r + b];
        let mut s = 0.0;
        for t in 0..b {
            s += row[t] * y[t];
        }
        // Rows are substituted in ascending order, so one pointer walks the long rows.
        if *lp < self.layout.long.len() && self.layout.long[*lp].row == r {
            {
                let lr = self.layout.long[*lp];
                *lp += 1;
                let len = r - b - lr.first;
                let lt = &self.l.tail[lr.offset..lr.offset + len];
                let y = &self.z[lr.first + b..lr.first + b + len];
                for t in 0..len {
                    s += lt[t] * y[t];
                }
            }
        }
        self.z[r + b] -= s;
    }

    #[inline(never)]
    fn backward<W: Width>(&mut self, w: W, k: Coeffs) -> f64 {
        let b = w.b();
        let n = self.layout.n;
        let long = &self.layout.long;
        let track = self.track_dissipation;
        let mut lp = long.len();
        let mut diss = 0.0;
        for i in (0..n).rev() {
            // z holds y with the Lᵀ terms of later rows already subtracted (scaled by d).
            let x = self.z[i + b] * self.d_inv[i + b];
            let (ui, vi, ai) = (self.u[i], self.v[i], self.a[i]);
            let a_new = (x - ui - k.dt * vi) * k.ab - k.a_old * ai;
            let v_new = vi + k.va_old * ai + k.va_new * a_new;
            self.u[i] = x;
            self.v[i] = v_new;
            self.a[i] = a_new;
            let vb = 0.5 * (vi + v_new);
            // Lᵀ: y_j −= d_j·l_ij·x_i for the columns of row i.
            {
                let row = &self.l.band[i * (b + 1)..i * (b + 1) + b];
                let d = &self.d[i..i + b];
                let z = &mut self.z[i..i + b];
                for t in 0..b {
                    z[t] -= row[t] * x * d[t];
                }
            }
            if track {
                let crow = &self.c.band[i * (b + 1)..(i + 1) * (b + 1)];
                diss += vb * (crow[b] * vb + 2.0 * self.acc[i + b]);
                self.acc[i + b] = 0.0;
                let acc = &mut self.acc[i..i + b];
                for t in 0..b {
                    acc[t] += crow[t] * vb;
                }
            }
            if lp > 0 && long[lp - 1].row == i {
                lp -= 1;
                let lr = long[lp];
                let len = i - b - lr.first;
                let cols = lr.first + b..lr.first + b + len;
                let lt = &self.l.tail[lr.offset..lr.offset + len];
                for (t, j) in cols.clone().enumerate() {
                    self.z[j] -= lt[t] * x * self.d[j];
                }
                if track {
                    let ct = &self.c.tail[lr.offset..lr.offset + len];
                    for (t, j) in cols.enumerate() {
                        self.acc[j] += ct[t] * vb;
                    }
                }
            }
        }
        diss
    }
}
