//! The effective piezo coefficient d_p from two records whose voltages differ by a constant.
//!
//! With `V₂(t) = V₁(t) + ΔV` the voltage rates are equal, so in the periodic state the
//! Bouc–Wen variable h is the same in both records and the strokes differ by `d_p·ΔV` only
//! (physics spec §12). Steps:
//!
//! 1. Both records must share the sample interval (to 1e-6 relative).
//! 2. **Alignment**: the records may start at different phases. For every integer shift s
//!    with an overlap of at least `min_overlap` × the shorter record, the variance of
//!    `d_i = V₂[i+s] − V₁[i]` is computed (all shifts at once from an FFT
//!    cross-correlation and prefix sums). Shifts whose variance is within 1.5× of the
//!    smallest (or within a round-off floor) all align the records (they differ by whole
//!    periods); the one with the largest overlap is taken.
//! 3. **Constant-offset check**: ΔV = mean(d); the pair is refused as "not a constant
//!    voltage offset" if |ΔV| is ~0 (below 1e-9 × the largest |V|) or if std(d) exceeds
//!    `offset_tolerance` × |ΔV| (default 0.1).
//! 4. **Least squares** over the M aligned pairs: `d_p = Σ(x₂−x₁)·ΔV / (M·ΔV²)`, residuals
//!    `r_i = (x₂−x₁)_i − d_p·ΔV`, RMS residual, and the standard error
//!    `s_r / (√M·|ΔV|)` with `s_r² = Σr²/(M−1)` (valid for uncorrelated residuals).
//!
//! Assumptions: the displacement sensor has the same zero in both records, and both are in
//! the periodic state.

use num_complex::Complex64;
use rustfft::FftPlanner;

use crate::error::{Error, Result};
use crate::identify::toml_float;
use crate::io::measurement::{self, LoadOptions, Measurement, Quantity};

/// Settings of [`estimate_dp`].
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DpOptions {
    /// Largest accepted std(V₂ − V₁) / |ΔV| (default 0.1).
    pub offset_tolerance: f64,
    /// Smallest overlap of the aligned records as a fraction of the shorter (default 0.5).
    pub min_overlap: f64,
    /// Search the best alignment (default true); false pairs samples by index.
    pub align: bool,
    /// Stack stiffness k_p: if given and a record has no displacement but a (blocked)
    /// force column, the stroke is taken as force / k_p.
    pub k_p: Option<f64>,
}

impl Default for DpOptions {
    fn default() -> Self {
        DpOptions { offset_tolerance: 0.1, min_overlap: 0.5, align: true, k_p: None }
    }
}

/// Result of [`estimate_dp`].
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct DpEstimate {
    /// Estimated d_p (m/V).
    pub d_p: f64,
    /// Estimated offset ΔV = mean(V₂ − V₁) (V).
    pub delta_v: f64,
    /// Standard deviation of V₂ − V₁ over the pairs (V).
    pub offset_std: f64,
    /// RMS of the least-squares residuals (m).
    pub residual_rms: f64,
    /// Standard error of d_p (m/V).
    pub std_error: f64,
    /// Number of sample pairs M.
    pub pairs: usize,
    /// Alignment: sample i of the first record pairs with sample i + shift of the second.
    pub shift: isize,
    /// The two files.
    pub files: (String, String),
}

impl DpEstimate {
    /// `[actuator.stack]` with `d_p`, and the estimate's quality as comments.
    pub fn to_case_fragment(&self) -> String {
        format!(
            "# d_p from {} and {}: delta_V = {} V over {} pairs, std error {} m/V ({} %)\n[{}]\nd_p = {}\n",
            self.files.0,
            self.files.1,
            toml_float(self.delta_v),
            self.pairs,
            toml_float(self.std_error),
            toml_float(100.0 * self.std_error / self.d_p.abs()),
            crate::identify::STACK_TABLE,
            toml_float(self.d_p)
        )
    }
}

fn stroke<'a>(m: &'a Measurement, opts: &DpOptions) -> Result<std::borrow::Cow<'a, [f64]>> {
    if let Some(x) = &m.displacement {
        return Ok(std::borrow::Cow::Borrowed(x));
    }
    if let (Some(f), Some(k)) = (&m.force, opts.k_p) {
        if !(k > 0.0 && k.is_finite()) {
            return Err(Error::input(&m.file, "k_p", format!("must be positive, got {k}")));
        }
        return Ok(std::borrow::Cow::Owned(f.iter().map(|v| v / k).collect()));
    }
    m.column(Quantity::Displacement).map(std::borrow::Cow::Borrowed)
}

/// d_p from two loaded records (voltage + displacement, or force with `opts.k_p`).
pub fn estimate_dp(first: &Measurement, second: &Measurement, opts: &DpOptions) -> Result<DpEstimate> {
    let pair = format!("{} and {}", first.file, second.file);
    let tol_ok = opts.offset_tolerance > 0.0 && opts.offset_tolerance.is_finite();
    if !(tol_ok && opts.min_overlap > 0.0 && opts.min_overlap <= 1.0) {
        return Err(Error::input(&pair, "dp options", "offset_tolerance must be > 0 and min_overlap in (0, 1]"));
    }
    let v1 = first.column(Quantity::Voltage)?;
    let v2 = second.column(Quantity::Voltage)?;
    let x1 = stroke(first, opts)?;
    let x2 = stroke(second, opts)?;
    if (first.dt - second.dt).abs() > 1e-6 * first.dt {
        return Err(Error::input(
            &pair,
            "time",
            format!("sample intervals differ ({:e} s and {:e} s); resample to a common rate", first.dt, second.dt),
        ));
    }
    let min_len = v1.len().min(v2.len());
    let min_pairs = ((opts.min_overlap * min_len as f64).ceil() as usize).max(2);
    let shift = if opts.align {
        best_shift(v1, v2, min_pairs)
    } else {
        if v1.len() != v2.len() {
            return Err(Error::input(&pair, "time", "without alignment both records must have the same length"));
        }
        0
    };
    let lo = 0isize.max(-shift) as usize;
    let hi = (v1.len() as isize).min(v2.len() as isize - shift) as usize;
    if hi <= lo + 1 {
        return Err(Error::input(&pair, "time", "the records do not overlap"));
    }
    let m = hi - lo;
    let d: Vec<f64> = (lo..hi).map(|i| v2[(i as isize + shift) as usize] - v1[i]).collect();
    let dv = crate::identify::mean(&d);
    let sd = crate::identify::std_dev(&d);
    let vmax = v1.iter().chain(v2.iter()).fold(0.0f64, |a, v| a.max(v.abs()));
    let offset_is_zero = dv.is_nan() || dv.abs() <= 1e-9 * vmax;
    if offset_is_zero || sd > opts.offset_tolerance * dv.abs() {
        return Err(Error::input(
            &pair,
            "voltage",
            format!(
                "not a constant voltage offset: V2 - V1 has mean {dv:.4e} V and std-dev {sd:.4e} V over {m} aligned pairs \
                 (need |mean| > 0 and std-dev <= {} x |mean|); d_p needs two records whose voltages differ only by a constant",
                opts.offset_tolerance
            ),
        ));
    }
    let e: Vec<f64> = (lo..hi).map(|i| x2[(i as isize + shift) as usize] - x1[i]).collect();
    let d_p = e.iter().map(|v| v * dv).sum::<f64>() / (m as f64 * dv * dv);
    let ss: f64 = e.iter().map(|v| (v - d_p * dv).powi(2)).sum();
    let residual_rms = (ss / m as f64).sqrt();
    let std_error = (ss / (m - 1) as f64).sqrt() / ((m as f64).sqrt() * dv.abs());
    if d_p.is_nan() || d_p <= 0.0 {
        return Err(Error::input(
            &pair,
            "displacement",
            format!(
                "estimated d_p = {d_p:e} m/V is not positive; check the signs of the voltage and displacement columns"
            ),
        ));
    }
    Ok(DpEstimate {
        d_p,
        delta_v: dv,
        offset_std: sd,
        residual_rms,
        std_error,
        pairs: m,
        shift,
        files: (first.file.clone(), second.file.clone()),
    })
}

/// Loads the two files (time, voltage and displacement — or force when `opts.k_p` is set)
/// and calls [`estimate_dp`].
pub fn estimate_dp_files(
    first: &std::path::Path,
    second: &std::path::Path,
    opts: &DpOptions,
    load: &LoadOptions,
) -> Result<DpEstimate> {
    let req: &[Quantity] =
        if opts.k_p.is_some() { &[Quantity::Voltage] } else { &[Quantity::Voltage, Quantity::Displacement] };
    let a = measurement::load(first, req, load)?;
    let b = measurement::load(second, req, load)?;
    estimate_dp(&a, &b, opts)
}

/// The shift s (sample i of `a` ↔ sample i+s of `b`) with the least variance of b − a,
/// among shifts with at least `min_pairs` pairs; ties (within 1.5×) go to the larger overlap.
fn best_shift(a: &[f64], b: &[f64], min_pairs: usize) -> isize {
    let (na, nb) = (a.len(), b.len());
    let l = (na + nb).next_power_of_two();
    let mut planner = FftPlanner::new();
    let fwd = planner.plan_fft_forward(l);
    let inv = planner.plan_fft_inverse(l);
    let mut fa: Vec<Complex64> = (0..l).map(|i| Complex64::new(if i < na { a[i] } else { 0.0 }, 0.0)).collect();
    let mut fb: Vec<Complex64> = (0..l).map(|i| Complex64::new(if i < nb { b[i] } else { 0.0 }, 0.0)).collect();
    fwd.process(&mut fa);
    fwd.process(&mut fb);
    let mut c: Vec<Complex64> = fa.iter().zip(&fb).map(|(x, y)| x.conj() * y).collect();
    inv.process(&mut c);
    // c[s mod l] / l = Σ_i a[i]·b[i+s].
    let prefix = |x: &[f64], sq: bool| {
        let mut p = vec![0.0; x.len() + 1];
        for (i, v) in x.iter().enumerate() {
            p[i + 1] = p[i] + if sq { v * v } else { *v };
        }
        p
    };
    let (pa, pa2, pb, pb2) = (prefix(a, false), prefix(a, true), prefix(b, false), prefix(b, true));
    let scale = pa2[na] / na as f64 + pb2[nb] / nb as f64;
    let mut cands: Vec<(isize, usize, f64)> = Vec::new();
    for s in -(na as isize - 1)..(nb as isize) {
        let lo = 0isize.max(-s) as usize;
        let hi = (na as isize).min(nb as isize - s) as usize;
        if hi < lo + min_pairs {
            continue;
        }
        let m = (hi - lo) as f64;
        let (blo, bhi) = ((lo as isize + s) as usize, (hi as isize + s) as usize);
        let sab = c[s.rem_euclid(l as isize) as usize].re / l as f64;
        let sd = (pb[bhi] - pb[blo]) - (pa[hi] - pa[lo]);
        let sd2 = (pb2[bhi] - pb2[blo]) + (pa2[hi] - pa2[lo]) - 2.0 * sab;
        let var = (sd2 / m - (sd / m).powi(2)).max(0.0);
        cands.push((s, hi - lo, var));
    }
    let vmin = cands.iter().map(|c| c.2).fold(f64::INFINITY, f64::min);
    let floor = 1e-10 * scale;
    cands
        .iter()
        .filter(|c| c.2 <= 1.5 * vmin + floor)
        .max_by(|x, y| x.1.cmp(&y.1).then(y.2.total_cmp(&x.2)))
        .map(|c| c.0)
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::identify::frf::tests::add_noise;
    use crate::identify::pso::Rng;
    use std::f64::consts::PI;

    /// Two records: V₁ = 48 sin(2πft) + v0, V₂ = V₁ + dv, stroke x = d_p·V − h with a
    /// hysteretic-looking h that depends on the phase only (as the periodic Bouc–Wen h does);
    /// the second record starts `lag` samples later. 1 % noise on the strokes.
    fn pair(dv: f64, lag: usize, noise: f64, seed: u64) -> (Measurement, Measurement) {
        let (d_p, f, fs) = (1.3e-7, 30.0, 6000.0);
        let n = 2000;
        let mut rng = Rng::new(seed);
        let mk = |start: usize, off: f64, rng: &mut Rng, name: &str| {
            let t: Vec<f64> = (0..n).map(|i| (i + start) as f64 / fs).collect();
            let v: Vec<f64> = t.iter().map(|t| 48.0 * (2.0 * PI * f * t).sin() + 5.0 + off).collect();
            let h: Vec<f64> = t.iter().map(|t| 0.3 * d_p * 40.0 * (2.0 * PI * f * t - 0.4).sin()).collect();
            let mut x: Vec<f64> = v.iter().zip(&h).map(|(v, h)| d_p * v - h).collect();
            add_noise(&mut x, noise, rng);
            let t0: Vec<f64> = (0..n).map(|i| i as f64 / fs).collect();
            Measurement::new(name, t0, vec![(Quantity::Voltage, v), (Quantity::Displacement, x)]).unwrap()
        };
        let a = mk(0, 0.0, &mut rng, "low.csv");
        let b = mk(lag, dv, &mut rng, "high.csv");
        (a, b)
    }

    #[test]
    fn recovers_dp_within_half_a_percent_with_one_percent_noise() {
        for (lag, seed) in [(0, 1), (37, 2), (1234, 3)] {
            let (a, b) = pair(20.0, lag, 0.01, seed);
            let est = estimate_dp(&a, &b, &DpOptions::default()).unwrap();
            let err = (est.d_p / 1.3e-7 - 1.0).abs();
            eprintln!(
                "d_p: lag {lag}: rel error {err:.2e}, std error {:.2e} rel, shift {}",
                est.std_error / est.d_p,
                est.shift
            );
            assert!(err < 0.005, "lag {lag}: {}", est.d_p);
            assert!((est.delta_v - 20.0).abs() < 1e-9);
            assert_eq!(est.shift.rem_euclid(200), (-(lag as isize)).rem_euclid(200));
            // The stated standard error is consistent with the actual error.
            assert!((est.d_p / 1.3e-7 - 1.0).abs() < 5.0 * est.std_error / est.d_p + 1e-12);
        }
    }

    #[test]
    fn bouc_wen_records_with_noise_on_voltage_and_stroke() {
        // The real physics: the true stack (d_p = 1.3e-7, α = 0.3, β = 0.02, γ = 0.005)
        // driven by 48 V sines with offsets 0 V and 12 V; strokes from the exact periodic
        // Bouc–Wen state; 1 % noise on both voltage and stroke of both records; the second
        // record starts 53 samples into its cycle.
        use crate::actuator::bouc_wen::BoucWen;
        use crate::signal::voltage::VoltageInput;
        let bw = BoucWen::default();
        let spp = 250;
        let mut rng = Rng::new(99);
        let mut rec = |offset: f64, start: usize, name: &str| {
            let input = VoltageInput::Sine { amplitude: 48.0, frequency: 30.0, offset, phase: 0.0 };
            let cyc = bw.periodic_cycle(&input, spp, 1e-13, 500).unwrap();
            let n = 8 * spp;
            let mut v: Vec<f64> = (0..n).map(|i| cyc.v[(i + start) % spp]).collect();
            let mut x: Vec<f64> = (0..n).map(|i| cyc.stroke[(i + start) % spp]).collect();
            add_noise(&mut v, 0.01, &mut rng);
            add_noise(&mut x, 0.01, &mut rng);
            let t: Vec<f64> = (0..n).map(|i| i as f64 / (30.0 * spp as f64)).collect();
            Measurement::new(name, t, vec![(Quantity::Voltage, v), (Quantity::Displacement, x)]).unwrap()
        };
        let a = rec(0.0, 0, "v0.csv");
        let b = rec(12.0, 53, "v12.csv");
        let est = estimate_dp(&a, &b, &DpOptions::default()).unwrap();
        let err = (est.d_p / bw.d_p - 1.0).abs();
        eprintln!(
            "d_p (Bouc-Wen records, noisy V and x): rel error {err:.2e}, delta_V {:.4} V, shift {}",
            est.delta_v, est.shift
        );
        assert!(err < 0.005, "{}", est.d_p);
        assert!((est.delta_v - 12.0).abs() < 0.05);
        assert_eq!(est.shift.rem_euclid(spp as isize), (spp - 53) as isize);
    }

    #[test]
    fn fragment_is_pasteable() {
        let (a, b) = pair(10.0, 0, 0.0, 1);
        let est = estimate_dp(&a, &b, &DpOptions::default()).unwrap();
        assert!((est.d_p / 1.3e-7 - 1.0).abs() < 1e-9);
        let t: toml::Table = toml::from_str(&est.to_case_fragment()).unwrap();
        let dp = t["actuator"]["stack"]["d_p"].as_float().unwrap();
        assert!((dp / 1.3e-7 - 1.0).abs() < 1e-5);
    }

    #[test]
    fn refuses_a_pair_without_a_constant_offset() {
        // Scaled voltage instead of an offset.
        let (a, mut b) = pair(0.0, 0, 0.0, 1);
        b.voltage = Some(a.voltage.as_ref().unwrap().iter().map(|v| 1.1 * v + 3.0).collect());
        let e = estimate_dp(&a, &b, &DpOptions::default()).unwrap_err().to_string();
        assert!(e.contains("low.csv") && e.contains("high.csv") && e.contains("not a constant voltage offset"), "{e}");
        // Zero offset.
        let (a, b) = pair(0.0, 0, 0.0, 1);
        let e = estimate_dp(&a, &b, &DpOptions::default()).unwrap_err().to_string();
        assert!(e.contains("not a constant voltage offset"), "{e}");
        // Different sample rates.
        let (a, mut b) = pair(10.0, 0, 0.0, 1);
        b.dt *= 2.0;
        let e = estimate_dp(&a, &b, &DpOptions::default()).unwrap_err().to_string();
        assert!(e.contains("sample intervals differ"), "{e}");
        // Missing displacement column.
        let (a, mut b) = pair(10.0, 0, 0.0, 1);
        b.displacement = None;
        let e = estimate_dp(&a, &b, &DpOptions::default()).unwrap_err().to_string();
        assert!(e.contains("high.csv") && e.contains("displacement") && e.contains("missing"), "{e}");
    }

    #[test]
    fn from_files_and_from_blocked_force() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = pair(15.0, 11, 0.01, 9);
        let (pa, pb) = (dir.path().join("a.csv"), dir.path().join("b.csv"));
        measurement::write(&pa, &a).unwrap();
        measurement::write(&pb, &b).unwrap();
        let est = estimate_dp_files(&pa, &pb, &DpOptions::default(), &LoadOptions::default()).unwrap();
        assert!((est.d_p / 1.3e-7 - 1.0).abs() < 0.005);
        assert!(est.files.0.ends_with("a.csv"));
        // Blocked force F = k_p·stroke with k_p given.
        let kp = 3.0e7;
        let to_force = |m: &Measurement| {
            let f: Vec<f64> = m.displacement.as_ref().unwrap().iter().map(|x| kp * x).collect();
            Measurement::new(
                m.file.clone(),
                m.time.clone(),
                vec![(Quantity::Voltage, m.voltage.clone().unwrap()), (Quantity::Force, f)],
            )
            .unwrap()
        };
        let est2 =
            estimate_dp(&to_force(&a), &to_force(&b), &DpOptions { k_p: Some(kp), ..Default::default() }).unwrap();
        assert!((est2.d_p / est.d_p - 1.0).abs() < 1e-9);
    }
}
