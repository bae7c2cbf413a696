//! A non-periodic run's record, analysed as a record: each point's channels — its drive,
//! the force into the structure, velocity and acceleration — handed to
//! [`crate::power::record`], which owns the estimators.

use super::record::PeriodRecord;
use crate::analysis::series::LinkSeries;
use crate::assembly::{Model, System};
use crate::power::point::net_power;
use crate::power::record::{point_record, DriveRecord, PointChannels, RecordAnalysis, Transforms, Welch};

/// The record analysis of a run's whole window `all` (its links' series `links`), sampled
/// at `dt` (s), segmented by `welch`.
pub(super) fn analyse(
    model: &Model,
    sys: &System,
    links: &[LinkSeries],
    all: &PeriodRecord,
    dt: f64,
    welch: Welch,
) -> RecordAnalysis {
    let mut points = Vec::with_capacity(links.len() + model.loads.len());
    for (l, lk) in sys.links.iter().enumerate() {
        let name = model.actuators[lk.actuator].name();
        let series = &links[l];
        points.push(point_record(
            &PointChannels {
                name: crate::actuator::link_id(name, &lk.name),
                drive_name: name.to_string(),
                drive: &all.v[lk.actuator],
                force: &series.interface,
                velocity: &series.base_velocity,
                acceleration: &series.base_acceleration,
            },
            dt,
            &welch,
        ));
    }
    for (j, load) in model.loads.iter().enumerate() {
        points.push(point_record(
            &PointChannels {
                name: load.name.clone(),
                drive_name: load.name.clone(),
                drive: &all.lf[j],
                force: &all.lf[j],
                velocity: &all.lv[j],
                acceleration: &all.la[j],
            },
            dt,
            &welch,
        ));
    }
    let channels: Vec<&[f64]> = all.v.iter().chain(&all.lf).map(Vec::as_slice).collect();
    let t = Transforms::new(&channels, dt, &welch);
    let names = model
        .actuators
        .iter()
        .map(|a| (a.name().to_string(), "V"))
        .chain(model.loads.iter().map(|l| (l.name.clone(), "N")));
    let drives = names
        .enumerate()
        .map(|(c, (name, unit))| DriveRecord { name, unit: unit.to_string(), psd: t.psd(c) })
        .collect();
    let link_energy: Vec<f64> = points[..sys.links.len()].iter().map(|p| p.energy).collect();
    let samples = all.t.len();
    RecordAnalysis {
        duration: samples as f64 * dt,
        dt,
        segment_s: welch.length as f64 * dt,
        segments: t.segments,
        frequency: t.frequency.clone(),
        welch,
        drives,
        points,
        net_energy: net_power(&sys.links, &link_energy, model.actuators.len()),
    }
}
