//! Power flow of a record that does not repeat (a chirp, a step, a measured series): no
//! harmonics exist, so what an engineer reads instead is the energy delivered over the
//! record, power spectral densities, and frequency response functions from the drive.
//!
//! A run starts at rest, so before t = 0 every signal's rate (first difference
//! Δx_n = x_n − x_{n−1}, x_{−1} = 0) is zero. FRFs are taken between the rates of drive and
//! response: the same filter on both channels leaves their ratio unchanged, and it turns a
//! step's held value into an impulse. The estimator is the one the record supports
//! ([`choose`]):
//!
//! * **one rectangular segment** of the whole record, when the drive and the response have
//!   died out inside it (a burst, an impact, a ramp to a held value: the rates at the end
//!   are below [`DECAYED`] of their peak, [`PointRecord::end_activity`]). The DFTs of the
//!   rates are then related by the stepped system's transfer function exactly, without
//!   leakage; coherence is not defined for one segment.
//! * **Welch averaging** otherwise (a chirp keeps running at its end frequency; a series
//!   may be cut mid-response): Hann-windowed segments overlapping by three quarters, reaching
//!   back before t = 0 where the record was at rest. With that overlap Σ_s w_s(t)² is the
//!   same at every instant, so an event anywhere in the record (a chirp passing a
//!   frequency) weighs the same, and the error the window's slope puts into H1 cancels to
//!   first order; what is left is of order (π·τ/T_s)², τ the slowest decay time in the
//!   band, T_s the segment. The segment is therefore [`SEGMENT_TIME_CONSTANTS`]·τ long
//!   (for ζ = 1 % that is a resolution of ≈ 0.16·ζ·f, several bins per half-power band).
//!
//! Each segment's mean is removed, and with X_k = Σ_n w_n·x_n·e^{−2πikn/N} the one-sided
//! densities
//!
//! ```text
//! G_xy(f_k) = c_k · mean_segments(conj(X_k)·Y_k) / (f_s · Σ w²),   c_k = 2 (1 at DC and Nyquist)
//! H1 = G_uy / G_uu,   γ² = |G_uy|² / (G_uu·G_yy)
//! ```
//!
//! so Σ_k Re G_fv(f_k)·Δf is the mean of f·v over the windowed segments: the power
//! spectral density of the power into the structure (W/Hz). For a drive u and a point
//! where force F and velocity v respond linearly, `Re(G_Fv)/G_uu = Re(conj(H_F)·H_v)`: a
//! sine drive of amplitude A at f puts ½·A²·that into the structure (the power FRF).
//! Coherence below one says the response is not linear in the drive there (hysteresis,
//! other drives, a segment too short for the response, leakage at sharp resonances).

use super::point::midpoint_work;
use num_complex::Complex64;
use rustfft::FftPlanner;
use serde::Serialize;
use std::f64::consts::PI;

/// How a record is cut into segments for Welch averaging.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Welch {
    /// Segment length (samples).
    pub length: usize,
    /// Fraction of a segment shared with the next, in [0, 1).
    pub overlap: f64,
    /// Hann window on every segment (false: rectangular).
    pub hann: bool,
    /// FRFs from the first differences of the signals.
    pub rates: bool,
    /// Segments reach back before t = 0, where a record that starts at rest was zero.
    pub from_rest: bool,
}

/// The largest end activity (rates over the record's last twentieth, relative to their
/// peak) at which a record counts as holding its whole response: one segment then.
pub const DECAYED: f64 = 1e-3;

/// A Welch segment's length in time constants of the slowest decay in the band.
pub const SEGMENT_TIME_CONSTANTS: f64 = 32.0;

/// Coherence below which an FRF bin is not to be trusted (and is shaded in figures).
pub const COHERENCE_TRUSTED: f64 = 0.9;

/// The share of the band whose coherence may lie below [`COHERENCE_TRUSTED`] before the
/// estimate as a whole is flagged.
pub const LOW_COHERENCE_SHARE: f64 = 0.1;

impl Welch {
    /// Hann-windowed segments of about `length` samples (a multiple of four) overlapping by
    /// three quarters, reaching back before a record that starts at rest; FRFs from rates.
    pub fn hann(length: usize) -> Self {
        Welch { length: length / 4 * 4, overlap: 0.75, hann: true, rates: true, from_rest: true }
    }

    /// One rectangular segment of the whole record of `samples` samples, FRFs from rates.
    pub fn whole(samples: usize) -> Self {
        Welch { length: samples, overlap: 0.0, hann: false, rates: true, from_rest: false }
    }

    /// Checks the segmentation against a record of `samples` samples; the error is the
    /// reason, for the caller to attach to the setting that chose the segment.
    pub fn check(&self, samples: usize) -> Result<(), String> {
        if self.length < 8 || self.length > samples {
            return Err(format!("a segment of {} samples must lie in [8, {samples}] (the record length)", self.length));
        }
        if !(0.0..1.0).contains(&self.overlap) {
            return Err(format!("overlap {} must lie in [0, 1)", self.overlap));
        }
        Ok(())
    }

    fn window(&self) -> Vec<f64> {
        let n = self.length;
        (0..n).map(|j| if self.hann { 0.5 - 0.5 * (2.0 * PI * j as f64 / n as f64).cos() } else { 1.0 }).collect()
    }

    /// Start sample of each segment in a record of `samples` samples (negative: before
    /// t = 0, where the record was at rest).
    fn starts(&self, samples: usize) -> Vec<isize> {
        let step = ((self.length as f64) * (1.0 - self.overlap)).round().max(1.0) as isize;
        let first = if self.from_rest { step - self.length as isize } else { 0 };
        (0..).map(|s| first + s * step).take_while(|&s| s + self.length as isize <= samples as isize).collect()
    }
}

/// The Welch transforms of a set of channels, kept so that any pair's cross spectrum is a
/// product: X[channel][segment][k], k = 0..=N/2.
pub struct Transforms {
    x: Vec<Vec<Vec<Complex64>>>,
    /// Frequencies k·f_s/N (Hz).
    pub frequency: Vec<f64>,
    /// Segments averaged.
    pub segments: usize,
    /// c_k / (segments · f_s · Σw²): the one-sided density scale per bin.
    scale: Vec<f64>,
}

impl Transforms {
    /// Transforms `channels` (each sampled at `dt` s, all of one length) by `welch`.
    pub fn new(channels: &[&[f64]], dt: f64, welch: &Welch) -> Self {
        let n = welch.length;
        let starts = welch.starts(channels.first().map_or(0, |c| c.len()));
        let w = welch.window();
        let w2: f64 = w.iter().map(|v| v * v).sum();
        let fft = FftPlanner::new().plan_fft_forward(n);
        let nf = n / 2 + 1;
        let mut buf = vec![Complex64::default(); n];
        let x = channels
            .iter()
            .map(|c| {
                starts
                    .iter()
                    .map(|&s| {
                        // Zeros before t = 0: the record starts at rest.
                        let lead = (-s).max(0) as usize;
                        let seg = &c[(s + lead as isize) as usize..(s + n as isize) as usize];
                        let mean = seg.iter().sum::<f64>() / n as f64;
                        let padded = std::iter::repeat(0.0).take(lead).chain(seg.iter().copied());
                        for (b, (v, &wj)) in buf.iter_mut().zip(padded.zip(&w)) {
                            *b = Complex64::new((v - mean) * wj, 0.0);
                        }
                        fft.process(&mut buf);
                        buf[..nf].to_vec()
                    })
                    .collect()
            })
            .collect();
        let fs = 1.0 / dt;
        let segments = starts.len();
        let scale = (0..nf)
            .map(|k| {
                let c = if k == 0 || 2 * k == n { 1.0 } else { 2.0 };
                c / (segments.max(1) as f64 * fs * w2)
            })
            .collect();
        Transforms { x, frequency: (0..nf).map(|k| k as f64 * fs / n as f64).collect(), segments, scale }
    }

    /// One-sided cross-spectral density G_ab (units_a·units_b/Hz) of channels a and b.
    pub fn cross(&self, a: usize, b: usize) -> Vec<Complex64> {
        (0..self.scale.len())
            .map(|k| {
                let s: Complex64 = self.x[a].iter().zip(&self.x[b]).map(|(xa, xb)| xa[k].conj() * xb[k]).sum();
                s * self.scale[k]
            })
            .collect()
    }

    /// One-sided power spectral density G_aa (units²/Hz) of channel a.
    pub fn psd(&self, a: usize) -> Vec<f64> {
        self.cross(a, a).into_iter().map(|c| c.re).collect()
    }

    /// The H1 estimate G_uy/G_uu of the response y to the drive u, and its coherence.
    pub fn h1(&self, u: usize, y: usize) -> (Vec<Complex64>, Vec<f64>) {
        let (guu, gyy, guy) = (self.psd(u), self.psd(y), self.cross(u, y));
        let h = guy.iter().zip(&guu).map(|(c, &p)| if p > 0.0 { c / p } else { Complex64::default() }).collect();
        let coh = guy
            .iter()
            .zip(guu.iter().zip(&gyy))
            .map(|(c, (&p, &q))| if p * q > 0.0 { (c.norm_sqr() / (p * q)).min(1.0) } else { 0.0 })
            .collect();
        (h, coh)
    }
}

/// How a record is to be analysed, settled before the run: a segment the case gave, or
/// the one the structure's band asks for, and the band itself.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RecordPlan {
    /// Samples in the record and their interval (s).
    pub samples: usize,
    pub dt: f64,
    /// The segmentation the case asked for (`segment`), used as given.
    pub given: Option<Welch>,
    /// The slowest decay rate σ (1/s) of the structure in the drive's band, and the Welch
    /// segment it asks for, [`SEGMENT_TIME_CONSTANTS`]/σ (s; infinite without damping).
    pub decay_rate: f64,
    pub needed_segment_s: f64,
    /// The drive's band (Hz): what its FRFs are read over.
    pub band: (f64, f64),
}

/// How a record was analysed and how far its FRFs can be trusted.
#[derive(Clone, Debug, Serialize)]
pub struct Estimate {
    /// The segmentation used.
    pub welch: Welch,
    /// Why: `given` (the case's `segment`), `decayed` (one segment: the response died out
    /// inside the record) or `welch` (averaged segments from the band's damping).
    pub reason: &'static str,
    /// The largest end activity over the points (see [`PointRecord::end_activity`]).
    pub end_activity: f64,
    /// The least coherence of any point's acceleration FRF in the band (None: one segment),
    /// and the share of the band's bins below [`COHERENCE_TRUSTED`].
    pub min_coherence: Option<f64>,
    pub low_coherence_share: f64,
    /// What makes the estimate untrustworthy, each with what to do (empty when sound).
    pub warnings: Vec<String>,
}

impl Estimate {
    /// One line for people: the estimator, over `segments` segments of `dt` samples, and why.
    pub fn describe(&self, dt: f64, segments: usize) -> String {
        let w = &self.welch;
        match self.reason {
            "decayed" => {
                format!("one segment, response decayed to {:.1e} of its peak (FRFs exact to that)", self.end_activity)
            }
            _ => format!(
                "Welch: {segments} Hann segments of {:.4} s, {:.0} % overlap (Δf = {:.4} Hz){}",
                w.length as f64 * dt,
                100.0 * w.overlap,
                1.0 / (w.length as f64 * dt),
                if self.reason == "given" { ", as the case's `segment`" } else { ", from the band's damping" }
            ),
        }
    }
}

/// Chooses the estimator the record supports (module docs): the case's segment when it
/// gave one; one segment when every point's response died out inside the record (largest
/// end activity `end_activity` ≤ [`DECAYED`]); Welch segments of the length the band's
/// damping asks for otherwise, as long as the record holds.
pub fn choose(plan: &RecordPlan, end_activity: f64) -> (Welch, &'static str) {
    if let Some(w) = plan.given {
        return (w, "given");
    }
    if end_activity <= DECAYED {
        return (Welch::whole(plan.samples), "decayed");
    }
    let needed = (plan.needed_segment_s / plan.dt).ceil();
    let length = if needed.is_finite() { (needed as usize).min(plan.samples) } else { plan.samples };
    (Welch::hann(length.min(plan.samples / 4 * 4).max(8)), "welch")
}

/// What makes a record's estimate untrustworthy (module docs), each with the remedy.
pub fn warnings(plan: &RecordPlan, e: &Estimate) -> Vec<String> {
    let mut w = Vec::new();
    let segment_s = e.welch.length as f64 * plan.dt;
    let record_s = plan.samples as f64 * plan.dt;
    if e.reason != "decayed" && segment_s < 0.99 * plan.needed_segment_s {
        let need = if plan.needed_segment_s.is_finite() {
            format!(
                "the {:.3} s ({SEGMENT_TIME_CONSTANTS} time constants) the slowest decay in the band needs",
                plan.needed_segment_s
            )
        } else {
            "the structure has no damping to size it by".to_string()
        };
        w.push(format!(
            "FRFs biased near resonances: segments of {segment_s:.3} s are shorter than {need}, and the response \
             is still active at the record's end ({:.1e} of its peak, above {DECAYED:.0e}); run longer (`duration` \
             of the record {record_s:.3} s + {:.3} s) or leave `duration` out for the default",
            e.end_activity,
            plan.needed_segment_s.min(1e9)
        ));
    }
    if e.min_coherence.is_some() && e.low_coherence_share > LOW_COHERENCE_SHARE {
        w.push(format!(
            "low coherence: {:.0} % of the band {:.1}–{:.1} Hz has coherence below {COHERENCE_TRUSTED} (least {:.2}); \
             FRFs there are not linear in the drive (hysteresis, other drives, segments too short)",
            100.0 * e.low_coherence_share,
            plan.band.0,
            plan.band.1,
            e.min_coherence.unwrap_or(0.0)
        ));
    }
    w
}

/// The least coherence over `bins` of each series in `coherences`, and the share of those
/// bins where any series lies below [`COHERENCE_TRUSTED`] (None, 0 without coherence).
pub fn band_coherence<'a>(coherences: impl Iterator<Item = &'a [f64]>, bins: &[usize]) -> (Option<f64>, f64) {
    let mut least: Option<f64> = None;
    let mut low = vec![false; bins.len()];
    for c in coherences.filter(|c| !c.is_empty()) {
        for (i, &k) in bins.iter().enumerate() {
            least = Some(least.map_or(c[k], |m: f64| m.min(c[k])));
            low[i] |= c[k] < COHERENCE_TRUSTED;
        }
    }
    let share = if bins.is_empty() { 0.0 } else { low.iter().filter(|&&b| b).count() as f64 / bins.len() as f64 };
    (least, share)
}

/// A record's analysis: how it was segmented, each drive's PSD, each point's energy,
/// spectra and FRFs.
#[derive(Clone, Debug, Serialize)]
pub struct RecordAnalysis {
    /// Record length and sample interval (s).
    pub duration: f64,
    pub dt: f64,
    /// The segmentation, its length (s) and the number of segments averaged.
    pub welch: Welch,
    pub segment_s: f64,
    pub segments: usize,
    /// The estimator chosen, why, and how far it can be trusted.
    pub estimate: Estimate,
    /// The drive's band (Hz).
    pub band: (f64, f64),
    /// Frequencies of every spectrum (Hz), k/segment_s.
    pub frequency: Vec<f64>,
    /// Each drive's PSD (V²/Hz for a voltage, N²/Hz for a load), actuators then loads.
    pub drives: Vec<DriveRecord>,
    /// Each link's foot, then each load.
    pub points: Vec<PointRecord>,
    /// Each sensor's acceleration FRF from the first drive.
    pub sensors: Vec<SensorRecord>,
    /// Energy delivered into the structure per actuator (its links' feet together, J).
    pub net_energy: Vec<f64>,
}

/// A drive signal's PSD over a record.
#[derive(Clone, Debug, Default, Serialize)]
pub struct DriveRecord {
    pub name: String,
    /// `V` or `N`.
    pub unit: String,
    pub psd: Vec<f64>,
}

/// What one point of a structure takes from the drives over a record.
#[derive(Clone, Debug, Default, Serialize)]
pub struct PointRecord {
    /// The point (a link `<actuator>_<link>` or a load) and the drive its FRFs refer to.
    pub name: String,
    pub drive: String,
    /// Energy delivered into the structure at the point over the record, ∫F·v dt (J).
    pub energy: f64,
    /// Power spectral density of the power into the structure, Re G_Fv (W/Hz).
    pub power_density: Vec<f64>,
    /// PSDs of the force (N²/Hz) and of the acceleration ((m/s²)²/Hz) at the point.
    pub force_psd: Vec<f64>,
    pub acceleration_psd: Vec<f64>,
    /// H1 from the drive to the force (N per drive unit) and to the acceleration
    /// ((m/s²) per drive unit), with their coherences (empty for one segment).
    #[serde(skip)]
    pub force_frf: Vec<Complex64>,
    pub force_coherence: Vec<f64>,
    #[serde(skip)]
    pub acceleration_frf: Vec<Complex64>,
    pub acceleration_coherence: Vec<f64>,
    /// Re G_Fv / G_uu: the power a sine drive of unit amplitude would put in, times two
    /// (W per drive unit²).
    pub power_frf: Vec<f64>,
    /// The largest |rate| (first difference) of drive and velocity over the record's last
    /// twentieth, relative to its largest over the record, the larger of the two: ≈ 0 when
    /// the record holds the whole response, so that one-segment FRFs are exact; of order
    /// one when a drive or a response continues past the record's end. Not the
    /// acceleration (nor a force holding an inertia term): average acceleration leaves the
    /// stiffest, overdamped mesh modes alternating at the Nyquist frequency in it, out of
    /// every band, while the velocity, its trapezoidal integral, is free of them.
    pub end_activity: f64,
}

/// A sensor's acceleration over a record, from the first drive.
#[derive(Clone, Debug, Default, Serialize)]
pub struct SensorRecord {
    pub name: String,
    pub drive: String,
    pub acceleration_psd: Vec<f64>,
    #[serde(skip)]
    pub acceleration_frf: Vec<Complex64>,
    pub acceleration_coherence: Vec<f64>,
}

/// The channels of one point: force F (N), velocity v (m/s) and acceleration a (m/s²)
/// samples, and the drive u its FRFs refer to.
pub struct PointChannels<'a> {
    pub name: String,
    pub drive_name: String,
    pub drive: &'a [f64],
    pub force: &'a [f64],
    pub velocity: &'a [f64],
    pub acceleration: &'a [f64],
}

impl PointChannels<'_> {
    /// The end activity of drive and velocity (see [`PointRecord::end_activity`]).
    pub fn end_activity(&self) -> f64 {
        [self.drive, self.velocity].iter().map(|x| end_peak_ratio(&rate(x))).fold(0.0f64, f64::max)
    }
}

/// The record analysis of one point, sampled at `dt` (s).
pub fn point_record(p: &PointChannels, dt: f64, welch: &Welch) -> PointRecord {
    let t = Transforms::new(&[p.drive, p.force, p.velocity, p.acceleration], dt, welch);
    let rates = welch.rates.then(|| {
        let r = [rate(p.drive), rate(p.force), rate(p.velocity), rate(p.acceleration)];
        Transforms::new(&[&r[0], &r[1], &r[2], &r[3]], dt, welch)
    });
    let ft = rates.as_ref().unwrap_or(&t);
    let (force_frf, mut force_coherence) = ft.h1(0, 1);
    let (acceleration_frf, mut acceleration_coherence) = ft.h1(0, 3);
    if ft.segments < 2 {
        force_coherence.clear();
        acceleration_coherence.clear();
    }
    let power_density: Vec<f64> = t.cross(1, 2).iter().map(|c| c.re).collect();
    // Re(G_Fv)/G_uu; on rates the factors |1 − e^{−iωΔt}|² of both cancel.
    let power_frf = ft.cross(1, 2).iter().zip(ft.psd(0)).map(|(c, u)| if u > 0.0 { c.re / u } else { 0.0 }).collect();
    PointRecord {
        name: p.name.clone(),
        drive: p.drive_name.clone(),
        energy: energy(p.force, p.velocity, dt),
        force_psd: t.psd(1),
        acceleration_psd: t.psd(3),
        power_density,
        force_frf,
        force_coherence,
        acceleration_frf,
        acceleration_coherence,
        power_frf,
        end_activity: p.end_activity(),
    }
}

/// A sensor's record: its acceleration `a` against the drive `u` (named `drive`).
pub fn sensor_record(name: &str, drive: (&str, &[f64]), a: &[f64], dt: f64, welch: &Welch) -> SensorRecord {
    let t = Transforms::new(&[drive.1, a], dt, welch);
    let (ru, ra) = (rate(drive.1), rate(a));
    let rt = Transforms::new(&[&ru, &ra], dt, welch);
    let (acceleration_frf, mut acceleration_coherence) = rt.h1(0, 1);
    if rt.segments < 2 {
        acceleration_coherence.clear();
    }
    SensorRecord {
        name: name.to_string(),
        drive: drive.0.to_string(),
        acceleration_psd: t.psd(1),
        acceleration_frf,
        acceleration_coherence,
    }
}

/// First differences x_n − x_{n−1} with x_{−1} = 0 (a run starts at rest).
fn rate(x: &[f64]) -> Vec<f64> {
    let mut prev = 0.0;
    x.iter()
        .map(|&v| {
            let d = v - prev;
            prev = v;
            d
        })
        .collect()
}

/// The largest |x| over the last twentieth of `x` relative to the largest over all of it
/// (0 for zeros; 1 for a record too short to have a last twentieth).
fn end_peak_ratio(x: &[f64]) -> f64 {
    let peak = |s: &[f64]| s.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let all = peak(x);
    if x.len() < 20 {
        1.0
    } else if all > 0.0 {
        peak(&x[x.len() - x.len() / 20..]) / all
    } else {
        0.0
    }
}

/// ∫F·v dt over the samples (J), step by step by the midpoint rule the run's energy
/// balance uses ([`midpoint_work`]).
pub fn energy(force: &[f64], velocity: &[f64], dt: f64) -> f64 {
    force.windows(2).zip(velocity.windows(2)).map(|(f, v)| midpoint_work(dt, f[0], f[1], v[0], v[1])).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Parseval: the PSD integrates to the windowed mean square, the cross density of F
    /// and v to the windowed mean product.
    #[test]
    fn densities_integrate_to_mean_squares() {
        let dt = 1e-3;
        let f: Vec<f64> = (0..4096).map(|j| (j as f64 * 0.37).sin() + 0.3 * (j as f64 * 1.1).cos()).collect();
        let v: Vec<f64> = (0..4096).map(|j| 0.5 * (j as f64 * 0.37 + 0.4).sin()).collect();
        let welch = Welch::whole(4096);
        let t = Transforms::new(&[&f, &v], dt, &welch);
        let df = t.frequency[1];
        let mf = f.iter().sum::<f64>() / 4096.0;
        let ms: f64 = f.iter().map(|x| (x - mf) * (x - mf)).sum::<f64>() / 4096.0;
        let integral: f64 = t.psd(0).iter().sum::<f64>() * df;
        assert!((integral - ms).abs() < 1e-12 * ms, "{integral} vs {ms}");
        let mv = v.iter().sum::<f64>() / 4096.0;
        let mp: f64 = f.iter().zip(&v).map(|(a, b)| (a - mf) * (b - mv)).sum::<f64>() / 4096.0;
        let cross: f64 = t.cross(0, 1).iter().map(|c| c.re).sum::<f64>() * df;
        assert!((cross - mp).abs() < 1e-12 * mp.abs(), "{cross} vs {mp}");
    }

    /// A pure gain with a delay of whole samples is recovered exactly by H1 on periodic
    /// segments, with unit coherence.
    #[test]
    fn h1_recovers_a_linear_relation() {
        let n = 1024;
        let u: Vec<f64> = (0..4 * n).map(|j| ((j * 7919) % 1000) as f64 / 1000.0 - 0.5).collect();
        let y: Vec<f64> = u.iter().map(|x| 3.0 * x).collect();
        let t = Transforms::new(&[&u, &y], 1e-3, &Welch::hann(n));
        let (h, coh) = t.h1(0, 1);
        for k in 1..n / 2 {
            assert!((h[k] - 3.0).norm() < 1e-9, "bin {k}: {}", h[k]);
            assert!((coh[k] - 1.0).abs() < 1e-9, "bin {k}: {}", coh[k]);
        }
        assert_eq!(t.segments, 16);
    }

    #[test]
    fn energy_is_the_midpoint_integral() {
        // F = 2 N, v = t m/s over 1 s: ∫ = 1 J, exact for a linear integrand.
        let v: Vec<f64> = (0..=100).map(|j| j as f64 * 0.01).collect();
        let f = vec![2.0; 101];
        assert!((energy(&f, &v, 0.01) - 1.0).abs() < 1e-12);
    }
}
