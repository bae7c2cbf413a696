//! One row of a real dynamic stiffness times a complex vector: the refinement residual of
//! a placement's coupled solve (`solve::modal_coupling`) reads every row of K, M and C per
//! frequency and step, and the baseline build does it two numbers at a time.
//!
//! Both builds take the same multiplies and adds in the same order (no fused
//! multiply–adds), so they agree bit for bit.

/// Σ_j (k_j + c_m·m_j)·(re_j, im_j) and Σ_j c_j·(re_j, im_j): one row of (K − ω²M)·x and
/// C·x for x = re + i·im (c_m = −ω²). Each sum runs in four lanes (lane l takes the terms
/// j ≡ l mod 4 below the last multiple of four), the lanes added in order, then the terms
/// past them in order.
pub fn kmc_row(k: &[f64], m: &[f64], c: &[f64], c_m: f64, re: &[f64], im: &[f64]) -> [f64; 4] {
    let n = k.len();
    assert!(m.len() == n && c.len() == n && re.len() == n && im.len() == n, "one row's lengths");
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the processor reports AVX; the lengths are checked above.
        let lanes = unsafe { kmc_lanes_avx(k, m, c, c_m, re, im) };
        return finish(lanes, k, m, c, c_m, re, im);
    }
    kmc_row_plain(k, m, c, c_m, re, im)
}

/// [`kmc_row`] as plain loops (the scalar twin).
pub fn kmc_row_plain(k: &[f64], m: &[f64], c: &[f64], c_m: f64, re: &[f64], im: &[f64]) -> [f64; 4] {
    let mut sums = [[0.0; 4]; 4];
    for j0 in (0..k.len() / 4 * 4).step_by(4) {
        for l in 0..4 {
            let j = j0 + l;
            let real = k[j] + c_m * m[j];
            sums[0][l] += real * re[j];
            sums[1][l] += real * im[j];
            sums[2][l] += c[j] * re[j];
            sums[3][l] += c[j] * im[j];
        }
    }
    finish(sums, k, m, c, c_m, re, im)
}

/// The lanes' sums added in order, then the terms past the last multiple of four.
fn finish(sums: [[f64; 4]; 4], k: &[f64], m: &[f64], c: &[f64], c_m: f64, re: &[f64], im: &[f64]) -> [f64; 4] {
    let mut out = sums.map(|s| s.iter().sum::<f64>());
    for j in k.len() / 4 * 4..k.len() {
        let real = k[j] + c_m * m[j];
        out[0] += real * re[j];
        out[1] += real * im[j];
        out[2] += c[j] * re[j];
        out[3] += c[j] * im[j];
    }
    out
}

/// The four lanes of each sum of [`kmc_row_plain`], four terms per vector operation.
///
/// # Safety
/// The processor has AVX, and every slice is as long as `k`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
unsafe fn kmc_lanes_avx(k: &[f64], m: &[f64], c: &[f64], c_m: f64, re: &[f64], im: &[f64]) -> [[f64; 4]; 4] {
    use std::arch::x86_64::*;
    let scale = _mm256_set1_pd(c_m);
    let mut acc = [_mm256_setzero_pd(); 4];
    let mut j = 0;
    while j + 4 <= k.len() {
        let (kj, mj) = (_mm256_loadu_pd(k.as_ptr().add(j)), _mm256_loadu_pd(m.as_ptr().add(j)));
        let (cj, rj) = (_mm256_loadu_pd(c.as_ptr().add(j)), _mm256_loadu_pd(re.as_ptr().add(j)));
        let ij = _mm256_loadu_pd(im.as_ptr().add(j));
        let real = _mm256_add_pd(kj, _mm256_mul_pd(scale, mj));
        acc[0] = _mm256_add_pd(acc[0], _mm256_mul_pd(real, rj));
        acc[1] = _mm256_add_pd(acc[1], _mm256_mul_pd(real, ij));
        acc[2] = _mm256_add_pd(acc[2], _mm256_mul_pd(cj, rj));
        acc[3] = _mm256_add_pd(acc[3], _mm256_mul_pd(cj, ij));
        j += 4;
    }
    let mut out = [[0.0; 4]; 4];
    for (o, a) in out.iter_mut().zip(acc) {
        _mm256_storeu_pd(o.as_mut_ptr(), a);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The vector build's sums are the plain loops', bit for bit, for every row length
    /// around the lanes' multiples and for values whose sums round.
    #[test]
    fn kmc_row_is_its_plain_twin_bit_for_bit() {
        for n in 0..23usize {
            let v = |s: f64| -> Vec<f64> {
                (0..n).map(|j| ((j as f64 + s) * 0.7371).sin() * 10f64.powi((j % 7) as i32 - 3)).collect()
            };
            let (k, m, c, re, im) = (v(0.1), v(1.3), v(2.9), v(4.1), v(5.7));
            let c_m = -(2.0 * std::f64::consts::PI * 140.0f64).powi(2);
            let (fast, plain) = (kmc_row(&k, &m, &c, c_m, &re, &im), kmc_row_plain(&k, &m, &c, c_m, &re, &im));
            assert_eq!(fast.map(f64::to_bits), plain.map(f64::to_bits), "row length {n}");
        }
    }
}
