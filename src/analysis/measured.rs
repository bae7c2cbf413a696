//! Measurements beside predictions: the error between a measured record
//! ([`crate::case::measured`]) and a periodic analysis' prediction at the same point.
//!
//! Both are reduced to complex amplitudes at the drive's harmonics k·f₀ (convention
//! x(t) = Re Σ X_k·e^{ikω₀t}, the measurement's time axis taken as the model's, t = 0 where
//! the drives start): the prediction's from its last period ([`harmonics`]), the
//! measurement's by a least-squares fit of a mean and the harmonics to the whole record
//! (exact for any sampling and any record of at least a period, with no leakage from the
//! harmonics fitted). At each harmonic present in both (within [`PRESENT_DB`] of the
//! largest line of each) the level error is 20·log₁₀|M_k/P_k| dB (10·log₁₀ for power, a
//! squared quantity) and the phase error arg(M_k/P_k); over the record, the RMS of the
//! measured series minus the prediction evaluated at the measured times (means removed).

use super::case_run::{AnalysisResult, Comparison};
use super::series::{LinkSeries, SensorSeries};
use crate::case::measured::{Measured, MeasuredQuantity};
use crate::error::{Error, Result};
use crate::io::measurement::Quantity;
use crate::power::point::mean_power_from_acceleration;
use crate::power::spectra::harmonics;
use num_complex::Complex64;
use std::f64::consts::PI;

/// Lines weaker than this (dB below the largest line of the same record) are not compared:
/// their level is noise or round-off.
pub const PRESENT_DB: f64 = 60.0;

/// The most harmonics fitted to a measured record.
pub const MAX_FITTED_HARMONICS: usize = 32;

/// One period of a prediction: samples of the point's series over its last period, and
/// the time that period starts at (s).
struct Predicted<'a> {
    force: Option<&'a [f64]>,
    acceleration: &'a [f64],
    start: f64,
    /// The harmonics the analysis resolves (a transient's step limits them).
    harmonics: usize,
}

/// The point's last-period series in a periodic result, if the point is there.
fn predicted<'a>(
    t: &[f64],
    links: &'a [LinkSeries],
    sensors: &'a [SensorSeries],
    link_name: &dyn Fn(&LinkSeries) -> String,
    point: &str,
    (per_period, harmonics): (usize, usize),
) -> Option<Predicted<'a>> {
    let n = t.len();
    if per_period == 0 || n < per_period {
        return None;
    }
    let tail = |v: &'a [f64]| &v[v.len() - per_period..];
    let start = t[n - per_period];
    if let Some(l) = links.iter().find(|l| link_name(l) == point) {
        let (force, acceleration) = (Some(tail(&l.interface)), tail(&l.base_acceleration));
        return Some(Predicted { force, acceleration, start, harmonics });
    }
    sensors.iter().find(|s| s.name == point).map(|s| Predicted {
        force: None,
        acceleration: tail(&s.a),
        start,
        harmonics,
    })
}

/// Compares every measurement with every periodic analysis of a run (transient with a
/// periodic drive, steady state). `link_name` names a link as the results do.
pub fn compare_all(
    results: &[AnalysisResult],
    measured: &[Measured],
    link_name: &dyn Fn(&LinkSeries) -> String,
) -> Result<Vec<Comparison>> {
    let mut out = Vec::new();
    for (a, r) in results.iter().enumerate() {
        let (period, series) = match r {
            AnalysisResult::Transient(t) if t.record.is_none() => {
                (t.period, predicted_in(&t.t, &t.links, &t.sensors, link_name, (t.steps_per_period, t.harmonics)))
            }
            AnalysisResult::SteadyState(s) => {
                (s.period, predicted_in(&s.t, &s.links, &s.sensors, link_name, (s.t.len(), s.harmonics)))
            }
            _ => continue,
        };
        for m in measured {
            let p = series(&m.point).ok_or_else(|| {
                Error::case_field(
                    format!("{}.point", m.field),
                    format!("analysis[{a}] recorded no link or sensor named `{}`", m.point),
                )
            })?;
            for &q in &m.quantities {
                out.push(compare(a, m, q, &p, period)?);
            }
        }
    }
    Ok(out)
}

/// A lookup of a point's prediction in one result.
fn predicted_in<'a>(
    t: &'a [f64],
    links: &'a [LinkSeries],
    sensors: &'a [SensorSeries],
    link_name: &'a dyn Fn(&LinkSeries) -> String,
    per_period: (usize, usize),
) -> impl Fn(&str) -> Option<Predicted<'a>> + 'a {
    move |point| predicted(t, links, sensors, link_name, point, per_period)
}

/// One quantity of one measurement against a prediction of period `period` (s).
fn compare(analysis: usize, m: &Measured, q: MeasuredQuantity, p: &Predicted, period: f64) -> Result<Comparison> {
    let d = &m.data;
    let w0 = 2.0 * PI / period;
    let per = p.acceleration.len();
    // Harmonics below both Nyquist frequencies: the prediction's samples and the record's.
    let k_rec = (per.saturating_sub(1) / 2).min(((PI / d.dt) / w0).ceil() as usize - 1);
    // Compared: those the analysis resolves, at most MAX_FITTED_HARMONICS.
    let k_max = k_rec.min(p.harmonics).min(MAX_FITTED_HARMONICS);
    if k_max == 0 {
        return Err(Error::input(
            &d.file,
            "time",
            format!(
                "sampled at {:.4e} s, the record does not resolve the drive frequency {:.4} Hz",
                d.dt,
                1.0 / period
            ),
        ));
    }
    // Prediction harmonics referred to t = 0 (its last period starts at p.start).
    let at_zero = |x: &[f64], k_max: usize| -> Vec<Complex64> {
        let shift = |k: usize| Complex64::from_polar(1.0, -(k as f64) * w0 * p.start);
        harmonics(x).iter().take(k_max + 1).enumerate().map(|(k, c)| c * shift(k)).collect()
    };
    let fit = |c: Quantity| -> Result<Vec<Complex64>> { fit_harmonics(&d.time, d.column(c)?, w0, k_max) };
    let power = |f: &[Complex64], a: &[Complex64]| -> Vec<Complex64> {
        (0..=k_max)
            .map(|k| {
                let pk = if k == 0 { 0.0 } else { mean_power_from_acceleration(f[k], a[k], k as f64 * w0) };
                Complex64::new(pk, 0.0)
            })
            .collect()
    };
    let (meas, pred, rms) = match q {
        MeasuredQuantity::Acceleration => {
            let meas = fit(Quantity::Acceleration)?;
            let rms =
                rms_error(&d.time, d.column(Quantity::Acceleration)?, meas[0].re, &at_zero(p.acceleration, k_rec), w0);
            (meas, at_zero(p.acceleration, k_max), rms)
        }
        MeasuredQuantity::Force => {
            let f = p.force.ok_or_else(|| no_force(m))?;
            let meas = fit(Quantity::Force)?;
            let rms = rms_error(&d.time, d.column(Quantity::Force)?, meas[0].re, &at_zero(f, k_rec), w0);
            (meas, at_zero(f, k_max), rms)
        }
        MeasuredQuantity::Power => {
            let f = p.force.ok_or_else(|| no_force(m))?;
            let pred = power(&at_zero(f, k_max), &at_zero(p.acceleration, k_max));
            let meas = power(&fit(Quantity::Force)?, &fit(Quantity::Acceleration)?);
            (meas, pred, (f64::NAN, f64::NAN))
        }
    };
    let factor = if q == MeasuredQuantity::Power { 10.0 } else { 20.0 };
    let present = |x: &[Complex64], k: usize| {
        let top = x[1..].iter().fold(0.0f64, |t, c| t.max(c.norm()));
        top > 0.0 && x[k].norm() > top * 10f64.powf(-PRESENT_DB / factor)
    };
    let harmonic: Vec<usize> = (1..=k_max).filter(|&k| present(&meas, k) && present(&pred, k)).collect();
    let ratio = |k: usize| meas[k] / pred[k];
    Ok(Comparison {
        analysis,
        name: m.name.clone(),
        point: m.point.clone(),
        quantity: q,
        file: d.file.clone(),
        frequency: harmonic.iter().map(|&k| k as f64 / period).collect(),
        measured: harmonic.iter().map(|&k| meas[k]).collect(),
        predicted: harmonic.iter().map(|&k| pred[k]).collect(),
        error_db: harmonic.iter().map(|&k| factor * ratio(k).norm().log10()).collect(),
        phase_error: harmonic.iter().map(|&k| ratio(k).arg()).collect(),
        harmonic,
        rms_error: rms.0,
        relative_rms_error: rms.1,
        tolerance_db: m.tolerance_db,
    })
}

fn no_force(m: &Measured) -> Error {
    Error::case_field(
        format!("{}.quantities", m.field),
        format!("`{}` is a sensor: it records no force (force and power are measured at links)", m.point),
    )
}

/// Least-squares fit of x(t) ≈ Re Σ_{k=0..=k_max} X_k·e^{ikω₀t} to samples (t, x): the
/// normal equations of the mean and the cosine and sine of each harmonic, solved by
/// Cholesky (well conditioned for a record of at least one period).
pub fn fit_harmonics(t: &[f64], x: &[f64], w0: f64, k_max: usize) -> Result<Vec<Complex64>> {
    let m = 2 * k_max + 1;
    let mut g = nalgebra::DMatrix::<f64>::zeros(m, m);
    let mut b = nalgebra::DVector::<f64>::zeros(m);
    let mut phi = vec![0.0; m];
    for (&ti, &xi) in t.iter().zip(x) {
        basis(ti, w0, k_max, &mut phi);
        for r in 0..m {
            b[r] += phi[r] * xi;
            for c in 0..=r {
                g[(r, c)] += phi[r] * phi[c];
            }
        }
    }
    for r in 0..m {
        for c in r + 1..m {
            g[(r, c)] = g[(c, r)];
        }
    }
    let coef = g
        .cholesky()
        .ok_or_else(|| Error::Numerical("the harmonic fit of a measured record is singular".into()))?
        .solve(&b);
    // x = a_0 + Σ a_k cos + b_k sin = Re Σ (a_k − i·b_k)·e^{ikωt}.
    Ok((0..=k_max)
        .map(|k| if k == 0 { Complex64::new(coef[0], 0.0) } else { Complex64::new(coef[2 * k - 1], -coef[2 * k]) })
        .collect())
}

/// [1, cos ω₀t, sin ω₀t, cos 2ω₀t, …] by powers of e^{iω₀t}.
fn basis(t: f64, w0: f64, k_max: usize, phi: &mut [f64]) {
    let z = Complex64::from_polar(1.0, w0 * t);
    let mut zk = Complex64::new(1.0, 0.0);
    phi[0] = 1.0;
    for k in 1..=k_max {
        zk *= z;
        phi[2 * k - 1] = zk.re;
        phi[2 * k] = zk.im;
    }
}

/// The RMS of the measured series minus the prediction at the measured times (every
/// harmonic of `pred` both resolve), both without their means (`mean`: the record's),
/// absolute and relative to the prediction's RMS there.
fn rms_error(t: &[f64], x: &[f64], mean: f64, pred: &[Complex64], w0: f64) -> (f64, f64) {
    let k_max = pred.len() - 1;
    let mut phi = vec![0.0; 2 * k_max + 1];
    let (mut e2, mut p2) = (0.0, 0.0);
    for (&ti, &xi) in t.iter().zip(x) {
        basis(ti, w0, k_max, &mut phi);
        let p: f64 = (1..=k_max).map(|k| pred[k].re * phi[2 * k - 1] - pred[k].im * phi[2 * k]).sum();
        let e = xi - mean - p;
        e2 += e * e;
        p2 += p * p;
    }
    let n = t.len().max(1) as f64;
    ((e2 / n).sqrt(), (e2 / p2).sqrt())
}

/// Checks a case's measurements against its model before any solve: each point is a link
/// (`<actuator>_<link>`) or a sensor, force and power are asked of links only, the drive
/// repeats, a periodic analysis is there to compare with, and each record resolves the
/// drive frequency and holds at least one period of it.
pub fn check(
    measured: &[Measured],
    model: &crate::assembly::Model,
    sys: &crate::assembly::System,
    periodic_analyses: usize,
) -> Result<()> {
    if measured.is_empty() {
        return Ok(());
    }
    let field = |m: &Measured, f: &str| format!("{}.{f}", m.field);
    let period = super::drive::common_period(model)?;
    for m in measured {
        let links: Vec<String> =
            sys.links.iter().map(|l| format!("{}_{}", model.actuators[l.actuator].name(), l.name)).collect();
        let is_link = links.contains(&m.point);
        if !is_link && !model.sensors.iter().any(|s| s.name == m.point) {
            let sensors: Vec<&str> = model.sensors.iter().map(|s| s.name.as_str()).collect();
            return Err(Error::case_field(
                field(m, "point"),
                format!(
                    "`{}` is neither a link ({}) nor a sensor ({})",
                    m.point,
                    links.join(", "),
                    if sensors.is_empty() { "none".to_string() } else { sensors.join(", ") }
                ),
            ));
        }
        if !is_link && m.quantities.iter().any(|&q| q != MeasuredQuantity::Acceleration) {
            return Err(no_force(m));
        }
        let Some(t) = period else {
            return Err(Error::case_field(
                field(m, "file"),
                "measurements are compared at the drive's harmonics, and this case's drive does not repeat",
            ));
        };
        if periodic_analyses == 0 {
            return Err(Error::case_field(
                field(m, "file"),
                "no steady_state or periodic transient analysis to compare the measurement with",
            ));
        }
        let d = &m.data;
        if 2.0 * d.dt >= t {
            return Err(Error::input(
                &d.file,
                "time",
                format!(
                    "sampled every {:.4e} s, the record does not resolve the drive frequency {:.4} Hz",
                    d.dt,
                    1.0 / t
                ),
            ));
        }
        let span = d.dt * d.len() as f64;
        if span < t * (1.0 - 1e-9) {
            return Err(Error::input(
                &d.file,
                "time",
                format!("the record spans {span:.4e} s, less than one drive period ({t:.4e} s)"),
            ));
        }
    }
    Ok(())
}
