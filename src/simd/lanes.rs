//! Dense products over lanes of four: dot products, matrix–vector products and the three
//! products of a read-out row with u, v and a. Every build rounds each row the same way
//! (four lane sums added as (l₀ + l₁) + (l₂ + l₃)) up to fused multiply–adds.

/// a·b + c, fused (one rounding) when compiled for a processor with FMA.
#[inline(always)]
pub fn madd<const FMA: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FMA {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

/// Σ aᵢ·bᵢ over a (b at least as long) in four lanes (lane l takes the terms i ≡ l mod 4),
/// summed as (l₀ + l₁) + (l₂ + l₃): the rounding of `gemv_avx2` when the length is a
/// multiple of four; four independent chains rather than one for a long row of the factor.
#[inline(always)]
pub fn dot_lanes<const FMA: bool>(a: &[f64], b: &[f64]) -> f64 {
    let b = &b[..a.len()];
    let mut acc = [0.0f64; 4];
    let (ac, bc) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ar, br) = (ac.remainder(), bc.remainder());
    for (x, y) in ac.zip(bc) {
        for l in 0..4 {
            acc[l] = madd::<FMA>(x[l], y[l], acc[l]);
        }
    }
    for (l, (x, y)) in ar.iter().zip(br).enumerate() {
        acc[l] = madd::<FMA>(*x, *y, acc[l]);
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3])
}

/// out = A·w for a row-major A with `stride` numbers per row (a multiple of four), at least
/// out.len() rounded up to four rows (zero rows past the end), and w of length ≥ stride. Each
/// row is `dot_lanes` of the row and w, so every build rounds the same way up to fused
/// multiply–adds.
#[inline(always)]
pub fn gemv<const FMA: bool>(a: &[f64], stride: usize, w: &[f64], out: &mut [f64]) {
    assert!(stride.is_multiple_of(4) && w.len() >= stride && a.len() >= out.len().next_multiple_of(4) * stride);
    #[cfg(target_arch = "x86_64")]
    if FMA {
        // SAFETY: `FMA` is true only where the caller checked `has_fma` (the module's
        // contract); the sizes are checked above.
        return unsafe { gemv_avx2(a, stride, w, out) };
    }
    for (i, o) in out.iter_mut().enumerate() {
        *o = dot_lanes::<FMA>(&a[i * stride..(i + 1) * stride], &w[..stride]);
    }
}

/// `gemv` four rows at a time: four independent accumulators share each load of w, and
/// one horizontal reduction yields four results.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn gemv_avx2(a: &[f64], stride: usize, w: &[f64], out: &mut [f64]) {
    use std::arch::x86_64::*;
    let n = out.len();
    let (pa, pw) = (a.as_ptr(), w.as_ptr());
    let mut i = 0;
    while i < n {
        let r = pa.add(i * stride);
        let (mut a0, mut a1, mut a2, mut a3) =
            (_mm256_setzero_pd(), _mm256_setzero_pd(), _mm256_setzero_pd(), _mm256_setzero_pd());
        let mut k = 0;
        while k < stride {
            let x = _mm256_loadu_pd(pw.add(k));
            a0 = _mm256_fmadd_pd(_mm256_loadu_pd(r.add(k)), x, a0);
            a1 = _mm256_fmadd_pd(_mm256_loadu_pd(r.add(stride + k)), x, a1);
            a2 = _mm256_fmadd_pd(_mm256_loadu_pd(r.add(2 * stride + k)), x, a2);
            a3 = _mm256_fmadd_pd(_mm256_loadu_pd(r.add(3 * stride + k)), x, a3);
            k += 4;
        }
        let sum = row_sums4([a0, a1, a2, a3]);
        if i + 4 <= n {
            _mm256_storeu_pd(out.as_mut_ptr().add(i), sum);
        } else {
            // The last, partial group, lane by lane with explicit stores (a copy loop of
            // variable length is turned into a call to memcpy).
            let (lo, hi) = (_mm256_castpd256_pd128(sum), _mm256_extractf128_pd(sum, 1));
            let o = out.as_mut_ptr().add(i);
            _mm_storel_pd(o, lo);
            if n - i > 1 {
                _mm_storeh_pd(o.add(1), lo);
            }
            if n - i > 2 {
                _mm_storel_pd(o.add(2), hi);
            }
        }
        i += 4;
    }
}

/// The four lanes of each of four accumulators summed as (l₀ + l₁) + (l₂ + l₃), for four
/// rows at once: lane r of the result is accumulator r's sum.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
unsafe fn row_sums4(acc: [std::arch::x86_64::__m256d; 4]) -> std::arch::x86_64::__m256d {
    use std::arch::x86_64::*;
    // [l0+l1, l2+l3] of each accumulator, interleaved by pairs, then the two halves added.
    let h01 = _mm256_hadd_pd(acc[0], acc[1]);
    let h23 = _mm256_hadd_pd(acc[2], acc[3]);
    _mm256_add_pd(_mm256_permute2f128_pd(h01, h23, 0x20), _mm256_permute2f128_pd(h01, h23, 0x31))
}

/// out[i] = (rowᵢ·u, rowᵢ·v, rowᵢ·a) for a row-major A as in `gemv` (zero rows up to a
/// multiple of four) and u, v, a of length ≥ stride: the three products of each row in one
/// pass over A, each rounded as `dot_lanes`.
pub fn gemv3<const FMA: bool>(a: &[f64], stride: usize, u: &[f64], v: &[f64], acc: &[f64], out: &mut [[f64; 3]]) {
    assert!(stride.is_multiple_of(4) && a.len() >= out.len().next_multiple_of(4) * stride);
    assert!(u.len() >= stride && v.len() >= stride && acc.len() >= stride);
    #[cfg(target_arch = "x86_64")]
    if FMA {
        // SAFETY: as in `gemv`; the sizes are checked above.
        return unsafe { gemv3_avx2(a, stride, [u, v, acc], out) };
    }
    for (i, o) in out.iter_mut().enumerate() {
        let row = &a[i * stride..(i + 1) * stride];
        *o = [dot_lanes::<FMA>(row, u), dot_lanes::<FMA>(row, v), dot_lanes::<FMA>(row, acc)];
    }
}

/// `gemv3` four rows at a time: each load of a row's four entries serves u, v and a, twelve
/// accumulators in all.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn gemv3_avx2(a: &[f64], stride: usize, x: [&[f64]; 3], out: &mut [[f64; 3]]) {
    use std::arch::x86_64::*;
    let n = out.len();
    let pa = a.as_ptr();
    let px = [x[0].as_ptr(), x[1].as_ptr(), x[2].as_ptr()];
    let mut i = 0;
    while i < n {
        let r = pa.add(i * stride);
        let mut acc = [[_mm256_setzero_pd(); 4]; 3];
        let mut k = 0;
        while k < stride {
            let xs = [_mm256_loadu_pd(px[0].add(k)), _mm256_loadu_pd(px[1].add(k)), _mm256_loadu_pd(px[2].add(k))];
            for row in 0..4 {
                let g = _mm256_loadu_pd(r.add(row * stride + k));
                for q in 0..3 {
                    acc[q][row] = _mm256_fmadd_pd(g, xs[q], acc[q][row]);
                }
            }
            k += 4;
        }
        let mut sums = [[0.0f64; 4]; 3];
        for q in 0..3 {
            _mm256_storeu_pd(sums[q].as_mut_ptr(), row_sums4(acc[q]));
        }
        for row in 0..4.min(n - i) {
            *out.get_unchecked_mut(i + row) = [sums[0][row], sums[1][row], sums[2][row]];
        }
        i += 4;
    }
}

/// `dot_lanes` kept out of line, for callers in hot loops that take it rarely (a long row
/// of a band factor: a handful a step). Inlined, such a call grew the AVX2 step by 60 %
/// (13,200 → 20,900 instructions) and slowed the rows that never take it: out of line, the
/// step took 0.87 (bare beam) and 0.89 (frame system) of the time in alternating pairs.
#[inline(always)]
pub fn dot_lanes_cold<const FMA: bool>(a: &[f64], b: &[f64]) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if FMA {
        // SAFETY: `FMA` is true only where the caller checked `has_fma`.
        return unsafe { dot_fma_cold(a, b) };
    }
    dot_plain_cold(a, b)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[cold]
#[inline(never)]
unsafe fn dot_fma_cold(a: &[f64], b: &[f64]) -> f64 {
    dot_lanes::<true>(a, b)
}

#[cold]
#[inline(never)]
fn dot_plain_cold(a: &[f64], b: &[f64]) -> f64 {
    dot_lanes::<false>(a, b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simd::builds;

    /// Every row count (whole groups of four and each partial last group), both builds:
    /// the product equals plain sums to round-off and writes nothing past `out`.
    #[test]
    fn gemv_matches_plain_sums_for_every_row_count() {
        let stride = 8;
        let w: Vec<f64> = (0..stride).map(|k| 0.3 + 0.7 * ((k * 7 % 5) as f64) - 1.1).collect();
        for rows in 1..=9usize {
            let a: Vec<f64> = (0..rows.next_multiple_of(4) * stride)
                .map(|q| if q < rows * stride { ((q * 13 % 11) as f64 - 5.0) / 3.0 } else { 0.0 })
                .collect();
            for fma in builds() {
                // A sentinel past the rows checks that the last group stores only its rows.
                let mut out = vec![f64::NAN; rows + 1];
                let (head, tail) = out.split_at_mut(rows);
                tail[0] = 42.0;
                if fma {
                    gemv::<true>(&a, stride, &w, head);
                } else {
                    gemv::<false>(&a, stride, &w, head);
                }
                for (i, &got) in out[..rows].iter().enumerate() {
                    let row = &a[i * stride..(i + 1) * stride];
                    let want: f64 = row.iter().zip(&w).map(|(x, y)| x * y).sum();
                    let scale: f64 = row.iter().zip(&w).map(|(x, y)| (x * y).abs()).sum();
                    assert!((got - want).abs() <= 1e-14 * scale, "rows {rows}, fma {fma}, row {i}: {got} vs {want}");
                }
                assert_eq!(out[rows], 42.0, "rows {rows}, fma {fma}: wrote past the end");
            }
        }
    }

    /// `gemv3` gives, for every row count and both builds, the bits of three `gemv`s (the
    /// same lanes in the same order) and writes nothing past `out`.
    #[test]
    fn gemv3_is_three_gemvs_for_every_row_count() {
        let stride = 12;
        let x: Vec<Vec<f64>> =
            (0..3).map(|q| (0..stride).map(|k| ((k * 7 + q * 3) % 5) as f64 * 0.37 - 0.6).collect()).collect();
        for rows in 1..=9usize {
            let a: Vec<f64> = (0..rows.next_multiple_of(4) * stride)
                .map(|p| if p < rows * stride { ((p * 13 % 11) as f64 - 5.0) / 3.0 } else { 0.0 })
                .collect();
            for fma in builds() {
                let mut out = vec![[f64::NAN; 3]; rows + 1];
                out[rows] = [42.0; 3];
                let mut one = vec![0.0; rows];
                if fma {
                    gemv3::<true>(&a, stride, &x[0], &x[1], &x[2], &mut out[..rows]);
                } else {
                    gemv3::<false>(&a, stride, &x[0], &x[1], &x[2], &mut out[..rows]);
                }
                for q in 0..3 {
                    if fma {
                        gemv::<true>(&a, stride, &x[q], &mut one);
                    } else {
                        gemv::<false>(&a, stride, &x[q], &mut one);
                    }
                    for i in 0..rows {
                        assert_eq!(
                            out[i][q].to_bits(),
                            one[i].to_bits(),
                            "rows {rows}, fma {fma}, row {i}, vector {q}"
                        );
                    }
                }
                assert_eq!(out[rows], [42.0; 3], "rows {rows}, fma {fma}: wrote past the end");
            }
        }
    }
}
