//! A non-periodic run's record, analysed as a record: each point's channels — its drive,
//! the force into the structure, velocity and acceleration — and each sensor's
//! acceleration handed to [`crate::power::record`], which owns the estimators and chooses
//! the one the record supports.

use super::record::PeriodRecord;
use crate::analysis::series::LinkSeries;
use crate::assembly::{Model, System};
use crate::power::point::net_power;
use crate::power::record::{
    band_coherence, choose, point_record, sensor_record, warnings, DriveRecord, Estimate, PointChannels,
    RecordAnalysis, RecordPlan, Transforms,
};

/// The record analysis of a run's whole window `all` (its links' series `links`), as
/// `plan` asks.
pub(super) fn analyse(
    model: &Model,
    sys: &System,
    links: &[LinkSeries],
    all: &PeriodRecord,
    plan: &RecordPlan,
) -> RecordAnalysis {
    let dt = plan.dt;
    let mut channels = Vec::with_capacity(links.len() + model.loads.len());
    for (l, lk) in sys.links.iter().enumerate() {
        let name = model.actuators[lk.actuator].name();
        let series = &links[l];
        channels.push(PointChannels {
            name: crate::actuator::link_id(name, &lk.name),
            drive_name: name.to_string(),
            drive: &all.v[lk.actuator],
            force: &series.interface,
            velocity: &series.base_velocity,
            acceleration: &series.base_acceleration,
        });
    }
    for (j, load) in model.loads.iter().enumerate() {
        channels.push(PointChannels {
            name: load.name.clone(),
            drive_name: load.name.clone(),
            drive: &all.lf[j],
            force: &all.lf[j],
            velocity: &all.lv[j],
            acceleration: &all.la[j],
        });
    }
    let end_activity = channels.iter().map(PointChannels::end_activity).fold(0.0f64, f64::max);
    let (welch, reason) = choose(plan, end_activity);
    let points: Vec<_> = channels.iter().map(|p| point_record(p, dt, &welch)).collect();
    let drive_names: Vec<(String, &str)> = model
        .actuators
        .iter()
        .map(|a| (a.name().to_string(), "V"))
        .chain(model.loads.iter().map(|l| (l.name.clone(), "N")))
        .collect();
    let drive_series: Vec<&[f64]> = all.v.iter().chain(&all.lf).map(Vec::as_slice).collect();
    let sensors = match (drive_names.first(), drive_series.first()) {
        (Some((name, _)), Some(u)) => model
            .sensors
            .iter()
            .enumerate()
            .map(|(s, se)| sensor_record(&se.name, (name, u), &all.sa[s], dt, &welch))
            .collect(),
        _ => Vec::new(),
    };
    let t = Transforms::new(&drive_series, dt, &welch);
    let drives = drive_names
        .into_iter()
        .enumerate()
        .map(|(c, (name, unit))| DriveRecord { name, unit: unit.to_string(), psd: t.psd(c) })
        .collect();
    let bins: Vec<usize> =
        (1..t.frequency.len()).filter(|&k| (plan.band.0..=plan.band.1).contains(&t.frequency[k])).collect();
    let coherences = points.iter().map(|p| p.acceleration_coherence.as_slice());
    let (min_coherence, low_coherence_share) = band_coherence(coherences, &bins);
    let mut estimate = Estimate { welch, reason, end_activity, min_coherence, low_coherence_share, warnings: vec![] };
    estimate.warnings = warnings(plan, &estimate);
    let link_energy: Vec<f64> = points[..sys.links.len()].iter().map(|p| p.energy).collect();
    RecordAnalysis {
        duration: all.t.len() as f64 * dt,
        dt,
        segment_s: welch.length as f64 * dt,
        segments: t.segments,
        frequency: t.frequency.clone(),
        welch,
        estimate,
        band: plan.band,
        drives,
        points,
        sensors,
        net_energy: net_power(&sys.links, &link_energy, model.actuators.len()),
    }
}
