//! The per-row algebra of a Newmark step on the increment x = Δu: the update of u, v, a
//! (and the step's mean velocity v̄) and the next step's history terms w₁, w₂; and the
//! same for four rows at once with one AVX2 vector per quantity, the same operations per
//! lane (so the same bits).

use super::madd;

/// Rows per group of the four-row kernels.
pub const G: usize = 4;

/// The step's coefficients: w₁ = c_v·v + c_a·a, w₂ = e_v·v + e_a·a + e_u·u, and the update
/// from the increment x = Δu: a_new = (x − Δt·v)·ab − a_old·a, v_new = v + va_old·a +
/// va_new·a_new. e_u is 0 but in the proportional form of the right-hand side.
#[derive(Clone, Copy, Debug)]
pub struct StepCoeffs {
    pub cv: f64,
    pub ca: f64,
    pub ev: f64,
    pub ea: f64,
    pub eu: f64,
    pub dt: f64,
    pub ab: f64,
    pub a_old: f64,
    pub va_old: f64,
    pub va_new: f64,
}

impl StepCoeffs {
    /// The history terms (w₁, w₂) of one DOF with velocity v and acceleration a. They are
    /// those of the whole displacement less K_eff·u_n's: u enters the increment's
    /// right-hand side only through −K·u.
    #[inline(always)]
    pub fn history<const FMA: bool>(self, u: f64, v: f64, a: f64) -> (f64, f64) {
        (madd::<FMA>(self.cv, v, self.ca * a), madd::<FMA>(self.ev, v, madd::<FMA>(self.ea, a, self.eu * u)))
    }
}

/// The Newmark update of one row from its increment x = Δu: a, v, u, the step's mean
/// velocity v̄ (with `VBAR`: only the dissipation reads it) and the next step's history
/// terms w₁, w₂. The caller passes the solution vector itself as `vbar`: once the row is
/// updated its Δu is read no more, so v̄ stored there costs no stream of its own.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn update_row<const FMA: bool, const VBAR: bool>(
    k: StepCoeffs,
    i: usize,
    x: f64,
    u: &mut [f64],
    v: &mut [f64],
    a: &mut [f64],
    vbar: &mut [f64],
    w1: &mut [f64],
    w2: &mut [f64],
) {
    let (ui, vi, ai) = (u[i], v[i], a[i]);
    let a_new = madd::<FMA>(x - k.dt * vi, k.ab, -k.a_old * ai);
    let v_new = madd::<FMA>(k.va_new, a_new, madd::<FMA>(k.va_old, ai, vi));
    let u_new = ui + x;
    u[i] = u_new;
    v[i] = v_new;
    a[i] = a_new;
    if VBAR {
        vbar[i] = 0.5 * (vi + v_new);
    }
    (w1[i], w2[i]) = k.history::<FMA>(u_new, v_new, a_new);
}

/// w₁, w₂ of every DOF from u, v, a: after `set_state`, before an update has written them.
#[inline(always)]
pub fn fill_history<const FMA: bool>(k: StepCoeffs, u: &[f64], v: &[f64], a: &[f64], w1: &mut [f64], w2: &mut [f64]) {
    for i in 0..v.len() {
        (w1[i], w2[i]) = k.history::<FMA>(u[i], v[i], a[i]);
    }
}

/// A group's y into `z` and y/d (as y·(1/d)) into `x`; one vector each in the FMA build.
#[inline(always)]
pub fn store_group<const FMA: bool>(z: &mut [f64], x: &mut [f64], ys: [f64; 4], d_inv: [f64; 4]) {
    assert!(z.len() == G && x.len() == G);
    #[cfg(target_arch = "x86_64")]
    if FMA {
        // SAFETY: as in `update_group`; both slices hold four numbers.
        unsafe { store_group_avx2(z, x, ys, d_inv) };
        return;
    }
    for j in 0..G {
        z[j] = ys[j];
        x[j] = ys[j] * d_inv[j];
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
unsafe fn store_group_avx2(z: &mut [f64], x: &mut [f64], ys: [f64; 4], d_inv: [f64; 4]) {
    use std::arch::x86_64::{
        _mm256_loadu_pd as load, _mm256_mul_pd as mul, _mm256_set_pd as set, _mm256_storeu_pd as store,
    };
    let y = set(ys[3], ys[2], ys[1], ys[0]);
    store(z.as_mut_ptr(), y);
    store(x.as_mut_ptr(), mul(y, load(d_inv.as_ptr())));
}

/// `update_row` of rows g..g + 4 from their increments `xs`; one AVX2 vector per
/// quantity in the FMA build, with the same operations per lane (so the same bits).
#[inline(always)]
pub fn update_group<const FMA: bool, const VBAR: bool>(
    k: StepCoeffs,
    g: usize,
    xs: [f64; 4],
    [u, v, a]: [&mut [f64]; 3],
    vbar: &mut [f64],
    [w1, w2]: [&mut [f64]; 2],
) {
    #[cfg(target_arch = "x86_64")]
    if FMA {
        assert!(g + G <= u.len().min(v.len()).min(a.len()).min(vbar.len()).min(w1.len()).min(w2.len()));
        // SAFETY: `FMA` is true only where the caller checked `has_fma`; the bounds are
        // checked above.
        unsafe { update_group_avx2::<VBAR>(k, g, xs, [u, v, a], vbar, [w1, w2]) };
        return;
    }
    for j in 0..G {
        update_row::<FMA, VBAR>(k, g + j, xs[j], u, v, a, vbar, w1, w2);
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
unsafe fn update_group_avx2<const VBAR: bool>(
    k: StepCoeffs,
    g: usize,
    xs: [f64; 4],
    [u, v, a]: [&mut [f64]; 3],
    vbar: &mut [f64],
    [w1, w2]: [&mut [f64]; 2],
) {
    use std::arch::x86_64::{
        _mm256_add_pd as add, _mm256_fmadd_pd as fmadd, _mm256_loadu_pd as load, _mm256_mul_pd as mul,
        _mm256_set1_pd as splat, _mm256_set_pd as set, _mm256_storeu_pd as store, _mm256_sub_pd as sub,
    };
    let x = set(xs[3], xs[2], xs[1], xs[0]);
    let (ui, vi, ai) = (load(u.as_ptr().add(g)), load(v.as_ptr().add(g)), load(a.as_ptr().add(g)));
    // As update_row: a = (x − Δt·v)·ab − a_old·a, v = va_new·a_new + (va_old·a + v), u += x.
    let a_new = fmadd(sub(x, mul(splat(k.dt), vi)), splat(k.ab), mul(splat(-k.a_old), ai));
    let v_new = fmadd(splat(k.va_new), a_new, fmadd(splat(k.va_old), ai, vi));
    let u_new = add(ui, x);
    store(u.as_mut_ptr().add(g), u_new);
    store(v.as_mut_ptr().add(g), v_new);
    store(a.as_mut_ptr().add(g), a_new);
    if VBAR {
        store(vbar.as_mut_ptr().add(g), mul(splat(0.5), add(vi, v_new)));
    }
    // As StepCoeffs::history.
    let h1 = fmadd(splat(k.cv), v_new, mul(splat(k.ca), a_new));
    let h2 = fmadd(splat(k.ev), v_new, fmadd(splat(k.ea), a_new, mul(splat(k.eu), u_new)));
    store(w1.as_mut_ptr().add(g), h1);
    store(w2.as_mut_ptr().add(g), h2);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simd::builds;

    fn coeffs() -> StepCoeffs {
        StepCoeffs {
            cv: 4.0e4,
            ca: 1.0,
            ev: -1.0,
            ea: -5.0e-5,
            eu: 0.3,
            dt: 1e-4,
            ab: 4.0e8,
            a_old: 1.0,
            va_old: 5e-5,
            va_new: 5e-5,
        }
    }

    fn state(seed: usize) -> Vec<f64> {
        (0..G).map(|i| (((i + 3 * seed) * 7919 % 101) as f64 - 50.0) * 1e-3).collect()
    }

    /// `update_group` is `update_row` of its four rows, bit for bit, in every build.
    #[test]
    fn update_group_is_four_update_rows() {
        let xs = [1.5e-6, -2.0e-6, 3.25e-7, -4.0e-9];
        for fma in builds() {
            for vbar in [false, true] {
                let mut g = [state(1), state(2), state(3), vec![0.0; G], vec![0.0; G], vec![0.0; G]];
                let mut r = g.clone();
                let [u, v, a, vb, w1, w2] = &mut g;
                let [ur, vr, ar, vbr, w1r, w2r] = &mut r;
                macro_rules! run {
                    ($f:literal, $v:literal) => {{
                        update_group::<$f, $v>(coeffs(), 0, xs, [u, v, a], vb, [w1, w2]);
                        for j in 0..G {
                            update_row::<$f, $v>(coeffs(), j, xs[j], ur, vr, ar, vbr, w1r, w2r);
                        }
                    }};
                }
                match (fma, vbar) {
                    (false, false) => run!(false, false),
                    (false, true) => run!(false, true),
                    (true, false) => run!(true, false),
                    (true, true) => run!(true, true),
                }
                for (q, (x, y)) in g.iter().zip(&r).enumerate() {
                    let (xb, yb): (Vec<u64>, Vec<u64>) =
                        (x.iter().map(|v| v.to_bits()).collect(), y.iter().map(|v| v.to_bits()).collect());
                    assert_eq!(xb, yb, "fma {fma}, vbar {vbar}, quantity {q}");
                }
            }
        }
    }

    /// `store_group` stores y and y·(1/d), bit for bit, in every build.
    #[test]
    fn store_group_is_y_and_y_over_d() {
        let ys = [1.0 / 3.0, -2.5, 7.0e-9, 4.0e5];
        let d_inv = [0.7, 1.0 / 7.0, -3.0, 1e-6];
        for fma in builds() {
            let (mut z, mut x) = ([0.0; G], [0.0; G]);
            if fma {
                store_group::<true>(&mut z, &mut x, ys, d_inv);
            } else {
                store_group::<false>(&mut z, &mut x, ys, d_inv);
            }
            for j in 0..G {
                assert_eq!(z[j].to_bits(), ys[j].to_bits());
                assert_eq!(x[j].to_bits(), (ys[j] * d_inv[j]).to_bits());
            }
        }
    }
}
