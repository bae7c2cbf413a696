//! Frequency response from impact-test records: the H1 estimator with Welch-style averaging,
//! and the Welch power spectral density ([`welch_psd`]).
//!
//! Inputs are a force record f(t) (hammer, N) and a response record a(t) (acceleration,
//! m/s²), uniformly sampled at `dt`. The records are cut into segments, either
//!
//! * [`Segmentation::Hits`]: one segment per hammer hit, found where |f| first exceeds
//!   `threshold` × max|f| and starting `pre_trigger` samples earlier (fewer for a hit near the
//!   record's start; the next hit is searched after the end of the current segment, and a hit
//!   whose segment would run past the record's end is dropped), or
//! * [`Segmentation::Welch`]: consecutive segments of fixed length with a fractional overlap.
//!
//! In each segment the mean is removed (Hits: the mean of the samples before the trigger,
//! less a 3-sample guard, when at least 4 remain; Welch: the segment mean), the optional windows are applied, and the DFT `X_k = Σ x_n·e^{−i2πkn/N}` is
//! taken. Averaging over segments:
//!
//! ```text
//! S_ff = Σ |F|²,  S_aa = Σ |A|²,  S_fa = Σ conj(F)·A
//! H1 = S_fa / S_ff          (accelerance, (m/s²)/N, for a = H·f with e^{+iωt})
//! γ² = |S_fa|² / (S_ff·S_aa)
//! ```
//!
//! Windows (all optional):
//! * Hann window on both signals, for random excitation with Welch segments (it widens
//!   lightly damped peaks, so impact tests should not use it);
//! * force window: the force is kept for `force_window` seconds from the segment start and
//!   set to zero afterwards (removes the noise that follows the pulse);
//! * exponential window `w(t) = e^{−t/τ}` applied to **both** force and response, with τ set
//!   so that `w` falls to `exponential_window_end` at the segment's end. Because the same
//!   exponential multiplies input and output, the windowed data are exactly those of the
//!   system with every pole shifted by `−1/τ`: [`Frf::exp_decay`] (= 1/τ, 1/s) records the
//!   shift, and the modal fit adds it back, so damping needs no other correction.

use num_complex::Complex64;
use rustfft::FftPlanner;

use crate::error::{Error, Result};
use crate::power::record::{Transforms, Welch};

/// How the records are cut into segments.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Segmentation {
    /// One segment of `length` samples per hammer hit.
    Hits {
        /// Segment length in samples.
        length: usize,
        /// Samples kept before the trigger sample.
        pre_trigger: usize,
        /// Trigger level as a fraction of max|f| over the whole record (0 < threshold < 1).
        threshold: f64,
    },
    /// Consecutive segments of `length` samples overlapping by `overlap` (0 ≤ overlap < 1).
    Welch { length: usize, overlap: f64 },
}

/// Settings of the H1 estimate.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrfOptions {
    /// Segmentation of the records.
    pub segmentation: Segmentation,
    /// Force window length in seconds from the segment start (None: no force window).
    pub force_window: Option<f64>,
    /// Value of the exponential window at the segment end, in (0, 1) (None: no window).
    pub exponential_window_end: Option<f64>,
    /// Hann window on both signals (for random excitation with Welch segments; default
    /// false). It widens peaks, so it is not meant for impact tests.
    #[serde(default)]
    pub hann: bool,
}

impl FrfOptions {
    /// Hit-triggered segments of `length` samples, 5 % pre-trigger, trigger at 10 % of the
    /// peak force, no windows.
    pub fn hits(length: usize) -> Self {
        FrfOptions {
            segmentation: Segmentation::Hits { length, pre_trigger: length / 20, threshold: 0.1 },
            force_window: None,
            exponential_window_end: None,
            hann: false,
        }
    }
}

/// An estimated frequency response function.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Frf {
    /// Frequencies in Hz, k·fs/N for k = 0..=N/2.
    pub freq: Vec<f64>,
    /// H1 accelerance, (m/s²)/N (serialised as `[re, im]` pairs).
    #[serde(serialize_with = "crate::identify::complex_serde::many")]
    pub h1: Vec<Complex64>,
    /// Ordinary coherence γ² in [0, 1].
    pub coherence: Vec<f64>,
    /// Averaged force auto-spectrum Σ|F|²/n_segments (N²), to check the hammer's band.
    pub force_autospectrum: Vec<f64>,
    /// Number of segments averaged.
    pub segments: usize,
    /// Sample interval (s).
    pub dt: f64,
    /// Pole shift introduced by the exponential window, 1/τ (1/s; 0 without window).
    pub exp_decay: f64,
}

/// H1 estimate from force and acceleration samples. `file` names the data's origin in
/// error messages.
pub fn h1(file: &str, force: &[f64], accel: &[f64], dt: f64, opts: &FrfOptions) -> Result<Frf> {
    if force.len() != accel.len() {
        return Err(Error::input(
            file,
            "acceleration",
            format!("force has {} samples but acceleration has {}", force.len(), accel.len()),
        ));
    }
    if !(dt > 0.0 && dt.is_finite()) {
        return Err(Error::input(file, "time", format!("sample interval must be positive, got {dt}")));
    }
    for (name, x) in [("force", force), ("acceleration", accel)] {
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(Error::input(file, name, format!("sample {i} is not finite")));
        }
    }
    let len = match opts.segmentation {
        Segmentation::Hits { length, .. } | Segmentation::Welch { length, .. } => length,
    };
    if len < 8 {
        return Err(Error::input(file, "segmentation.length", "segment length must be at least 8 samples"));
    }
    if len > force.len() {
        return Err(Error::input(
            file,
            "segmentation.length",
            format!("segment length {len} exceeds the record length {}", force.len()),
        ));
    }
    let starts = segment_starts(file, force, &opts.segmentation)?;
    if starts.is_empty() {
        return Err(Error::input(file, "force", "no complete segment (hit) found in the record"));
    }
    let tau = match opts.exponential_window_end {
        None => None,
        Some(e) if e > 0.0 && e < 1.0 => Some((len - 1) as f64 * dt / (1.0 / e).ln()),
        Some(e) => return Err(Error::input(file, "exponential_window_end", format!("must lie in (0, 1), got {e}"))),
    };
    let force_keep = match opts.force_window {
        None => len,
        Some(w) if w > 0.0 => ((w / dt).round() as usize).clamp(1, len),
        Some(w) => return Err(Error::input(file, "force_window", format!("must be positive, got {w}"))),
    };
    let expw: Vec<f64> = (0..len)
        .map(|n| {
            let e = tau.map_or(1.0, |t| (-(n as f64) * dt / t).exp());
            let h =
                if opts.hann { 0.5 - 0.5 * (2.0 * std::f64::consts::PI * n as f64 / len as f64).cos() } else { 1.0 };
            e * h
        })
        .collect();
    let Spectra { sff, saa, sfa } = averaged_spectra(force, accel, &starts, &expw, force_keep);
    let nf = len / 2 + 1;
    let fs = 1.0 / dt;
    let freq: Vec<f64> = (0..nf).map(|k| k as f64 * fs / len as f64).collect();
    let h1: Vec<Complex64> =
        (0..nf).map(|k| if sff[k] > 0.0 { sfa[k] / sff[k] } else { Complex64::new(f64::NAN, f64::NAN) }).collect();
    let coherence: Vec<f64> = (0..nf)
        .map(|k| {
            let d = sff[k] * saa[k];
            if d > 0.0 {
                (sfa[k].norm_sqr() / d).min(1.0)
            } else {
                0.0
            }
        })
        .collect();
    let m = starts.len() as f64;
    Ok(Frf {
        freq,
        h1,
        coherence,
        force_autospectrum: sff.iter().map(|v| v / m).collect(),
        segments: starts.len(),
        dt,
        exp_decay: tau.map_or(0.0, |t| 1.0 / t),
    })
}

/// Segment starts in the record, each with the number of leading samples whose mean is
/// removed (the quiet samples before a hit; a whole Welch segment).
fn segment_starts(file: &str, force: &[f64], segmentation: &Segmentation) -> Result<Vec<(usize, usize)>> {
    Ok(match *segmentation {
        Segmentation::Hits { length, pre_trigger, threshold } => {
            if !(threshold > 0.0 && threshold < 1.0) {
                return Err(Error::input(file, "segmentation.threshold", "must lie in (0, 1)"));
            }
            if pre_trigger >= length {
                return Err(Error::input(file, "segmentation.pre_trigger", "must be shorter than the segment"));
            }
            let peak = force.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            if peak == 0.0 {
                return Err(Error::input(file, "force", "the force record is identically zero: no hit"));
            }
            let level = threshold * peak;
            let mut starts = Vec::new();
            let mut i = 0;
            while i < force.len() {
                if force[i].abs() >= level {
                    let s = i.saturating_sub(pre_trigger);
                    if s + length <= force.len() {
                        // Mean over the quiet samples before the trigger (a guard of 3
                        // samples keeps the pulse's foot out of it).
                        starts.push((s, (i - s).saturating_sub(3)));
                    }
                    i = s + length;
                } else {
                    i += 1;
                }
            }
            starts
        }
        Segmentation::Welch { length, overlap } => {
            if !(0.0..1.0).contains(&overlap) {
                return Err(Error::input(file, "segmentation.overlap", "must lie in [0, 1)"));
            }
            let step = ((length as f64) * (1.0 - overlap)).round().max(1.0) as usize;
            let mut starts = Vec::new();
            let mut s = 0;
            while s + length <= force.len() {
                starts.push((s, length));
                s += step;
            }
            starts
        }
    })
}

/// Auto- and cross-spectra of force and acceleration summed over the segments.
struct Spectra {
    sff: Vec<f64>,
    saa: Vec<f64>,
    sfa: Vec<Complex64>,
}

/// Sums |F|², |A|² and F*·A over the segments at `starts` (each windowed by `expw`, the
/// force kept for its first `force_keep` samples, the leading means removed).
fn averaged_spectra(
    force: &[f64],
    accel: &[f64],
    starts: &[(usize, usize)],
    expw: &[f64],
    force_keep: usize,
) -> Spectra {
    let len = expw.len();
    let nf = len / 2 + 1;
    let mut sff = vec![0.0; nf];
    let mut saa = vec![0.0; nf];
    let mut sfa = vec![Complex64::new(0.0, 0.0); nf];
    let fft = FftPlanner::new().plan_fft_forward(len);
    let mut fb = vec![Complex64::new(0.0, 0.0); len];
    let mut ab = vec![Complex64::new(0.0, 0.0); len];
    for &(s, mean_len) in starts {
        let fseg = &force[s..s + len];
        let aseg = &accel[s..s + len];
        let (fm, am) = if mean_len >= 4 {
            (crate::identify::mean(&fseg[..mean_len]), crate::identify::mean(&aseg[..mean_len]))
        } else {
            (0.0, 0.0)
        };
        for n in 0..len {
            let fv = if n < force_keep { fseg[n] - fm } else { 0.0 };
            fb[n] = Complex64::new(fv * expw[n], 0.0);
            ab[n] = Complex64::new((aseg[n] - am) * expw[n], 0.0);
        }
        fft.process(&mut fb);
        fft.process(&mut ab);
        for k in 0..nf {
            sff[k] += fb[k].norm_sqr();
            saa[k] += ab[k].norm_sqr();
            sfa[k] += fb[k].conj() * ab[k];
        }
    }
    Spectra { sff, saa, sfa }
}

/// H1 estimate from a loaded measurement (its `force` and `acceleration` columns).
pub fn h1_from_measurement(m: &crate::io::measurement::Measurement, opts: &FrfOptions) -> Result<Frf> {
    let f = m.column(crate::io::measurement::Quantity::Force)?;
    let a = m.column(crate::io::measurement::Quantity::Acceleration)?;
    h1(&m.file, f, a, m.dt, opts)
}

/// Trigger samples of the hammer hits: the first sample of each pulse where |f| reaches
/// `threshold` × max|f|; a new hit starts only after |f| has fallen below that level again.
pub fn find_hits(force: &[f64], threshold: f64) -> Vec<usize> {
    let peak = force.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let level = threshold * peak;
    let mut hits = Vec::new();
    let mut inside = false;
    for (i, v) in force.iter().enumerate() {
        if v.abs() >= level && peak > 0.0 {
            if !inside {
                hits.push(i);
            }
            inside = true;
        } else {
            inside = false;
        }
    }
    hits
}

/// A segment length for [`Segmentation::Hits`] from the record itself: the shortest spacing
/// between consecutive hits (with one hit: from the hit to the record's end). Errors naming
/// `file` if there is no hit or the hits are closer than 64 samples (double hits: give the
/// length explicitly).
pub fn auto_segment_length(file: &str, force: &[f64], threshold: f64) -> Result<usize> {
    let hits = find_hits(force, threshold);
    let Some(&first) = hits.first() else {
        return Err(Error::input(file, "force", "the force record is identically zero: no hit"));
    };
    let len =
        if hits.len() == 1 { force.len() - first } else { hits.windows(2).map(|w| w[1] - w[0]).min().unwrap_or(0) };
    if len < 64 {
        return Err(Error::input(
            file,
            "force",
            format!(
                "hits only {len} samples apart (a double hit?); give the segment length explicitly \
                 ({} hits found at samples {:?}...)",
                hits.len(),
                &hits[..hits.len().min(5)]
            ),
        ));
    }
    Ok(len)
}

/// One-sided power spectral density by Welch averaging.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Psd {
    /// Frequencies in Hz, k·fs/N for k = 0..=N/2.
    pub freq: Vec<f64>,
    /// One-sided density (units²/Hz), scaled so that Σ psd·Δf is the mean square of the
    /// windowed segments divided by the window's mean square (Parseval).
    pub psd: Vec<f64>,
    /// Number of segments averaged.
    pub segments: usize,
}

/// Welch PSD of `x` sampled at `dt`: segments of `length` samples overlapping by `overlap`
/// (0 ≤ overlap < 1), each with its mean removed and, if `hann`, a Hann window applied.
/// `P_k = c_k·mean_seg|X_k|² / (fs·Σw²)` with `c_k = 2` except at DC and Nyquist (1), so
/// `Σ P_k·fs/N` equals the mean over segments of `Σ(w·x)²/Σw²` exactly.
pub fn welch_psd(file: &str, field: &str, x: &[f64], dt: f64, length: usize, overlap: f64, hann: bool) -> Result<Psd> {
    if !(dt > 0.0 && dt.is_finite()) {
        return Err(Error::input(file, "time", format!("sample interval must be positive, got {dt}")));
    }
    if let Some(i) = x.iter().position(|v| !v.is_finite()) {
        return Err(Error::input(file, field, format!("sample {i} is not finite")));
    }
    if length < 8 || length > x.len() {
        return Err(Error::input(
            file,
            "segmentation.length",
            format!("segment length {length} must lie in [8, {}] (the record length)", x.len()),
        ));
    }
    if !(0.0..1.0).contains(&overlap) {
        return Err(Error::input(file, "segmentation.overlap", "must lie in [0, 1)"));
    }
    let t = Transforms::new(&[x], dt, &Welch { length, overlap, hann, rates: false, from_rest: false });
    Ok(Psd { psd: t.psd(0), freq: t.frequency, segments: t.segments })
}

impl Frf {
    /// Receptance (m/N) at bin k: accelerance / (iω)²; NaN at f = 0.
    pub fn receptance(&self, k: usize) -> Complex64 {
        let w = 2.0 * std::f64::consts::PI * self.freq[k];
        if w == 0.0 {
            Complex64::new(f64::NAN, f64::NAN)
        } else {
            self.h1[k] / (-(w * w))
        }
    }
}

// ---------------------------------------------------------------------------------------
// Synthetic impact tests: exact response of a linear lumped system.
// ---------------------------------------------------------------------------------------

/// A hammer pulse: half-sine of `peak` N lasting `duration` s, starting at `start` s,
/// sampled at `dt` over `n` samples (added into `out`).
pub fn add_hammer_pulse(out: &mut [f64], dt: f64, start: f64, duration: f64, peak: f64) {
    for (i, v) in out.iter_mut().enumerate() {
        let t = i as f64 * dt - start;
        if t > 0.0 && t < duration {
            *v += peak * (std::f64::consts::PI * t / duration).sin();
        }
    }
}

/// Exact sampled acceleration of DOF `output` of the linear system `M·ẍ + C·ẋ + K·x = e_input·f(t)`,
/// starting at rest, when f varies linearly between its samples (first-order hold). The
/// state-space model is discretised with the matrix exponential of the augmented system,
/// so the only approximation is the hold assumption on the force.
pub fn impact_response(
    mass: &[Vec<f64>],
    damping: &[Vec<f64>],
    stiffness: &[Vec<f64>],
    input: usize,
    output: usize,
    force: &[f64],
    dt: f64,
) -> Result<Vec<f64>> {
    let n = mass.len();
    let square = |m: &[Vec<f64>]| m.len() == n && m.iter().all(|r| r.len() == n);
    if n == 0 || !square(damping) || !square(stiffness) || !square(mass) || input >= n || output >= n {
        return Err(Error::argument("matrices", "M, C, K must be square of equal size with valid DOFs"));
    }
    let minv = dense::inverse(mass).ok_or_else(|| Error::Numerical("singular mass matrix".into()))?;
    let mk = dense::matmul(&minv, stiffness);
    let mc = dense::matmul(&minv, damping);
    // Augmented state [x; v; f; g], ġ = 0, ḟ = g.
    let ns = 2 * n + 2;
    let mut a = vec![vec![0.0; ns]; ns];
    for i in 0..n {
        a[i][n + i] = 1.0;
        for j in 0..n {
            a[n + i][j] = -mk[i][j];
            a[n + i][n + j] = -mc[i][j];
        }
        a[n + i][2 * n] = minv[i][input];
    }
    a[2 * n][2 * n + 1] = 1.0;
    for row in a.iter_mut() {
        for v in row.iter_mut() {
            *v *= dt;
        }
    }
    let phi = dense::expm(&a);
    let mut z = vec![0.0; 2 * n];
    let mut out = Vec::with_capacity(force.len());
    let acc = |z: &[f64], f: f64| -> f64 {
        let mut s = minv[output][input] * f;
        for j in 0..n {
            s -= mk[output][j] * z[j] + mc[output][j] * z[n + j];
        }
        s
    };
    for k in 0..force.len() {
        out.push(acc(&z, force[k]));
        if k + 1 < force.len() {
            let g = (force[k + 1] - force[k]) / dt;
            let mut zn = vec![0.0; 2 * n];
            for (i, zi) in zn.iter_mut().enumerate() {
                let mut s = phi[i][2 * n] * force[k] + phi[i][2 * n + 1] * g;
                for j in 0..2 * n {
                    s += phi[i][j] * z[j];
                }
                *zi = s;
            }
            z = zn;
        }
    }
    Ok(out)
}

/// Small dense helpers (row-major `Vec<Vec<f64>>`), for system sizes of a few DOFs.
pub(crate) mod dense {
    pub fn matmul(a: &[Vec<f64>], b: &[Vec<f64>]) -> Vec<Vec<f64>> {
        let (n, m, p) = (a.len(), b.len(), b[0].len());
        let mut c = vec![vec![0.0; p]; n];
        for i in 0..n {
            for k in 0..m {
                let aik = a[i][k];
                if aik != 0.0 {
                    for j in 0..p {
                        c[i][j] += aik * b[k][j];
                    }
                }
            }
        }
        c
    }

    /// Gauss–Jordan inverse with partial pivoting; None when singular.
    pub fn inverse(a: &[Vec<f64>]) -> Option<Vec<Vec<f64>>> {
        let n = a.len();
        let mut m: Vec<Vec<f64>> = a.to_vec();
        let mut inv: Vec<Vec<f64>> = (0..n).map(|i| (0..n).map(|j| if i == j { 1.0 } else { 0.0 }).collect()).collect();
        let scale = a.iter().flatten().fold(0.0f64, |s, v| s.max(v.abs()));
        for col in 0..n {
            let p = (col..n).max_by(|&i, &j| m[i][col].abs().total_cmp(&m[j][col].abs()))?;
            if m[p][col].abs() <= 1e-14 * scale || scale == 0.0 {
                return None;
            }
            m.swap(p, col);
            inv.swap(p, col);
            let d = m[col][col];
            for j in 0..n {
                m[col][j] /= d;
                inv[col][j] /= d;
            }
            for i in 0..n {
                if i != col {
                    let f = m[i][col];
                    if f != 0.0 {
                        for j in 0..n {
                            m[i][j] -= f * m[col][j];
                            inv[i][j] -= f * inv[col][j];
                        }
                    }
                }
            }
        }
        Some(inv)
    }

    /// Matrix exponential by scaling and squaring with a Taylor series (norm ≤ 1/2 after
    /// scaling, 20 terms: error below machine precision).
    pub fn expm(a: &[Vec<f64>]) -> Vec<Vec<f64>> {
        let n = a.len();
        let norm = a.iter().map(|r| r.iter().map(|v| v.abs()).sum::<f64>()).fold(0.0, f64::max);
        let mut s = 0;
        while norm / 2f64.powi(s) > 0.5 {
            s += 1;
        }
        let f = 2f64.powi(-s);
        let x: Vec<Vec<f64>> = a.iter().map(|r| r.iter().map(|v| v * f).collect()).collect();
        let mut result: Vec<Vec<f64>> =
            (0..n).map(|i| (0..n).map(|j| if i == j { 1.0 } else { 0.0 }).collect()).collect();
        let mut term = result.clone();
        for k in 1..=20 {
            term = matmul(&term, &x);
            for row in term.iter_mut() {
                for v in row.iter_mut() {
                    *v /= k as f64;
                }
            }
            for i in 0..n {
                for j in 0..n {
                    result[i][j] += term[i][j];
                }
            }
        }
        for _ in 0..s {
            result = matmul(&result, &result);
        }
        result
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::identify::pso::Rng;
    use std::f64::consts::PI;

    /// Adds Gaussian noise with std = `level` × RMS of the signal.
    pub(crate) fn add_noise(x: &mut [f64], level: f64, rng: &mut Rng) {
        let rms = (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt();
        for v in x.iter_mut() {
            *v += level * rms * rng.normal();
        }
    }

    /// The stack-on-mass impact test of the brief: m = 0.33 kg, k = 3e7 N/m, c = 200 N·s/m,
    /// `hits` hammer hits, one every `spacing` samples, 1 % noise on both channels.
    pub(crate) fn sdof_impact(hits: usize, spacing: usize, dt: f64, seed: u64) -> (Vec<f64>, Vec<f64>) {
        let n = hits * spacing;
        let mut f = vec![0.0; n];
        let mut rng = Rng::new(seed);
        for h in 0..hits {
            let start = (h * spacing) as f64 * dt + 50.0 * dt + rng.uniform() * dt;
            add_hammer_pulse(&mut f, dt, start, 2.0e-4, 200.0 * (1.0 + 0.2 * rng.uniform()));
        }
        let a = impact_response(&[vec![0.33]], &[vec![200.0]], &[vec![3.0e7]], 0, 0, &f, dt).unwrap();
        let (mut f, mut a) = (f, a);
        add_noise(&mut f, 0.01, &mut rng);
        add_noise(&mut a, 0.01, &mut rng);
        (f, a)
    }

    #[test]
    fn expm_matches_rotation_and_decay() {
        let th = 2.7;
        let e = dense::expm(&[vec![0.0, -th], vec![th, 0.0]]);
        assert!((e[0][0] - th.cos()).abs() < 1e-13 && (e[1][0] - th.sin()).abs() < 1e-13);
        let e = dense::expm(&[vec![-30.0]]);
        assert!((e[0][0] / (-30.0f64).exp() - 1.0).abs() < 1e-12);
        let inv = dense::inverse(&[vec![2.0, 1.0], vec![1.0, 3.0]]).unwrap();
        assert!((inv[0][0] - 0.6).abs() < 1e-15 && (inv[0][1] + 0.2).abs() < 1e-15);
        assert!(dense::inverse(&[vec![1.0, 2.0], vec![2.0, 4.0]]).is_none());
    }

    #[test]
    fn impact_response_matches_analytic_impulse_response() {
        // A very short triangular pulse of area I approximates an impulse: a(t) after the
        // pulse = I/m · d²/dt² of e^{-σt} sin(ω_d t)/ω_d.
        let (m, k, c) = (0.33, 3.0e7, 200.0);
        let dt = 1e-7;
        let mut f = vec![0.0; 4000];
        f[1] = 1.0; // triangle over [0, 2dt], area dt
        let a = impact_response(&[vec![m]], &[vec![c]], &[vec![k]], 0, 0, &f, dt).unwrap();
        let wn = (k / m).sqrt();
        let sig = c / (2.0 * m);
        let wd = (wn * wn - sig * sig).sqrt();
        let imp = dt;
        for &i in &[500usize, 1500, 3999] {
            let t = i as f64 * dt - dt; // impulse centred at dt
            let e = (-sig * t).exp();
            let x_dd = imp / m * e * ((sig * sig - wd * wd) * (wd * t).sin() - 2.0 * sig * wd * (wd * t).cos()) / wd;
            assert!((a[i] - x_dd).abs() < 1e-3 * (imp / m * wn), "{i}: {} vs {}", a[i], x_dd);
        }
    }

    #[test]
    fn h1_of_noise_free_sdof_matches_the_analytic_accelerance() {
        let dt = 1.0 / 25600.0;
        let n = 4096;
        let mut f = vec![0.0; 2 * n];
        add_hammer_pulse(&mut f, dt, 40.0 * dt, 2e-4, 100.0);
        add_hammer_pulse(&mut f, dt, (n + 40) as f64 * dt, 2e-4, 150.0);
        let a = impact_response(&[vec![0.33]], &[vec![200.0]], &[vec![3.0e7]], 0, 0, &f, dt).unwrap();
        let frf = h1("<synthetic>", &f, &a, dt, &FrfOptions::hits(n)).unwrap();
        assert_eq!(frf.segments, 2);
        assert_eq!(frf.freq.len(), n / 2 + 1);
        // Compare near resonance (1517 Hz) and at low frequency; the sampled (FOH) data differ
        // from the continuous FRF by O((ω·dt)²) in magnitude only.
        for &fr in &[300.0, 1000.0, 1517.0, 2000.0] {
            let k = (fr / frf.freq[1]).round() as usize;
            let w = 2.0 * PI * frf.freq[k];
            let exact = Complex64::new(-w * w, 0.0) / Complex64::new(3.0e7 - w * w * 0.33, w * 200.0);
            let rel = (frf.h1[k] - exact).norm() / exact.norm();
            assert!(rel < 0.02, "{fr} Hz: {} vs {exact} ({rel})", frf.h1[k]);
            assert!(frf.coherence[k] > 0.999);
        }
    }

    #[test]
    fn noise_lowers_coherence_and_averaging_works() {
        let dt = 1.0 / 25600.0;
        let (f, a) = sdof_impact(6, 4096, dt, 9);
        let frf = h1("<synthetic>", &f, &a, dt, &FrfOptions::hits(4096)).unwrap();
        assert_eq!(frf.segments, 6);
        let k = (1517.0 / frf.freq[1]).round() as usize;
        assert!(frf.coherence[k] > 0.95, "{}", frf.coherence[k]);
        // Far above the hammer's band the force carries only noise: coherence drops.
        let kh = frf.freq.len() - 10;
        assert!(frf.coherence[kh] < 0.9, "{}", frf.coherence[kh]);
    }

    #[test]
    fn exponential_window_shifts_poles_by_its_decay() {
        let dt = 1.0 / 25600.0;
        let n = 4096;
        let mut f = vec![0.0; n];
        add_hammer_pulse(&mut f, dt, 40.0 * dt, 2e-4, 100.0);
        let a = impact_response(&[vec![0.33]], &[vec![200.0]], &[vec![3.0e7]], 0, 0, &f, dt).unwrap();
        let opts = FrfOptions { exponential_window_end: Some(0.01), ..FrfOptions::hits(n) };
        let frf = h1("<synthetic>", &f, &a, dt, &opts).unwrap();
        let tau = (n - 1) as f64 * dt / 100f64.ln();
        assert!((frf.exp_decay - 1.0 / tau).abs() < 1e-9);
        // Windowed FRF = FRF of the system with damping raised by 2m/τ.
        let k = (1500.0 / frf.freq[1]).round() as usize;
        let s = Complex64::new(0.0, 2.0 * PI * frf.freq[k]);
        let sw = s + 1.0 / tau;
        let exact = sw * sw / (0.33 * sw * sw + 200.0 * sw + 3.0e7);
        let rel = (frf.h1[k] - exact).norm() / exact.norm();
        assert!(rel < 0.02, "{rel}");
    }

    #[test]
    fn welch_segments_with_random_excitation() {
        // White-noise force, 50 % overlapping Hann-windowed segments.
        let dt = 1.0 / 25600.0;
        let mut rng = Rng::new(5);
        let f: Vec<f64> = (0..40 * 4096).map(|_| rng.normal()).collect();
        let a = impact_response(&[vec![0.33]], &[vec![200.0]], &[vec![3.0e7]], 0, 0, &f, dt).unwrap();
        let opts = FrfOptions {
            segmentation: Segmentation::Welch { length: 4096, overlap: 0.5 },
            force_window: None,
            exponential_window_end: None,
            hann: true,
        };
        let frf = h1("<random>", &f, &a, dt, &opts).unwrap();
        assert_eq!(frf.segments, 79);
        for &fr in &[500.0, 1000.0, 1517.0, 2500.0] {
            let k = (fr / frf.freq[1]).round() as usize;
            let w = 2.0 * PI * frf.freq[k];
            let exact = Complex64::new(-w * w, 0.0) / Complex64::new(3.0e7 - w * w * 0.33, w * 200.0);
            let rel = (frf.h1[k] - exact).norm() / exact.norm();
            assert!(rel < 0.03, "{fr} Hz: {rel}");
        }
    }

    #[test]
    fn bad_inputs_are_errors() {
        let f = vec![0.0; 100];
        let a = vec![0.0; 99];
        let e = h1("hits.csv", &f, &a, 1e-3, &FrfOptions::hits(32)).unwrap_err().to_string();
        assert!(e.contains("hits.csv") && e.contains("samples"), "{e}");
        let a = vec![0.0; 100];
        let e = h1("hits.csv", &f, &a, 1e-3, &FrfOptions::hits(32)).unwrap_err().to_string();
        assert!(e.contains("no hit"), "{e}");
        let mut f2 = f.clone();
        f2[3] = f64::NAN;
        let e = h1("hits.csv", &f2, &a, 1e-3, &FrfOptions::hits(32)).unwrap_err().to_string();
        assert!(e.contains("force") && e.contains("not finite"), "{e}");
        let e = h1("hits.csv", &f, &a, 1e-3, &FrfOptions::hits(200)).unwrap_err().to_string();
        assert!(e.contains("exceeds"), "{e}");
    }

    #[test]
    fn welch_psd_obeys_parseval() {
        // Rectangular window, no overlap: Σ P·Δf is the mean square of the mean-removed
        // segments, to round-off (Parseval for the DFT).
        let dt = 1.0 / 1000.0;
        let mut rng = Rng::new(11);
        let x: Vec<f64> = (0..8 * 256).map(|_| 0.3 + 2.0 * rng.normal()).collect();
        let p = welch_psd("<noise>", "x", &x, dt, 256, 0.0, false).unwrap();
        assert_eq!(p.segments, 8);
        let df = p.freq[1];
        let total: f64 = p.psd.iter().sum::<f64>() * df;
        let ms: f64 = x
            .chunks(256)
            .map(|c| {
                let m = crate::identify::mean(c);
                c.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / 256.0
            })
            .sum::<f64>()
            / 8.0;
        assert!((total - ms).abs() < 1e-12 * ms, "{total} vs {ms}");
        // Hann, 50 % overlap: a sine of amplitude A carries A²/2 in its band, whatever the
        // window (leakage stays within the main lobe's ±2 bins).
        let a = 1.5;
        let f0 = 125.0;
        let y: Vec<f64> = (0..8192).map(|n| a * (2.0 * PI * f0 * n as f64 * dt).sin()).collect();
        let p = welch_psd("<sine>", "y", &y, dt, 512, 0.5, true).unwrap();
        let k0 = (f0 / p.freq[1]).round() as usize;
        let band: f64 = p.psd[k0 - 2..=k0 + 2].iter().sum::<f64>() * p.freq[1];
        assert!((band - a * a / 2.0).abs() < 1e-3 * a * a / 2.0, "{band}");
    }

    #[test]
    fn welch_psd_refuses_bad_records() {
        let x = vec![0.0; 100];
        let e = welch_psd("run.h5", "force", &x, 1e-3, 200, 0.5, true).unwrap_err().to_string();
        assert!(e.contains("run.h5") && e.contains("record length"), "{e}");
        let e = welch_psd("run.h5", "force", &x, 1e-3, 50, 1.0, true).unwrap_err().to_string();
        assert!(e.contains("overlap"), "{e}");
        let mut y = x.clone();
        y[7] = f64::INFINITY;
        let e = welch_psd("run.h5", "force", &y, 1e-3, 50, 0.5, true).unwrap_err().to_string();
        assert!(e.contains("force") && e.contains("not finite"), "{e}");
    }
}
