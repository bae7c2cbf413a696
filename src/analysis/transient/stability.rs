//! The time step of a conditionally stable scheme against the model's highest mode.
//!
//! Linear acceleration (γ = ½, β = 1/6) is stable only for ω_max·Δt < 1/√(γ/2 − β) = 2√3.
//! A beam mesh's highest mode rises as (elements)², so the drive's default step is far
//! beyond that on any useful mesh, and an unstable run grows without bound until its
//! numbers overflow. The run is refused before any step instead, with the admissible step
//! in the message.

use super::super::drive::DriveTiming;
use super::super::modes::DENSE_EIGEN_LIMIT;
use crate::assembly::System;
use crate::error::{Error, Result};
use crate::solve::eigen::modes;
use crate::solve::newmark::Scheme;
use std::f64::consts::PI;

/// Refuses `timing.dt` when `scheme` is conditionally stable and the step exceeds its limit
/// on `sys`. The highest natural frequency comes from the complete eigen-decomposition,
/// which is dense: larger systems are refused for such schemes.
pub(super) fn check_step(sys: &System, scheme: Scheme, timing: &DriveTiming) -> Result<()> {
    let Some(unit_limit) = scheme.critical_step(1.0) else {
        return Ok(());
    };
    let n = sys.n();
    if n > DENSE_EIGEN_LIMIT {
        return Err(Error::analysis_setting(
            "scheme",
            format!(
                "a conditionally stable scheme needs the model's highest natural frequency, computed for \
                 at most {DENSE_EIGEN_LIMIT} DOFs (this model has {n}): use scheme = \"average_acceleration\", \
                 which is stable for every step"
            ),
        ));
    }
    let all: Vec<usize> = (0..n).collect();
    let omega_max = modes(&sys.k, &sys.m, &all, n)?.omega.last().copied().unwrap_or(0.0);
    let limit = unit_limit / omega_max;
    if timing.dt < limit {
        return Ok(());
    }
    let advice = if timing.periodic {
        let steps = (timing.period / limit).floor() as usize + 1;
        format!("give `steps_per_period` = {steps} (Δt = {:.9e} s) or more", timing.period / steps as f64)
    } else {
        format!("give `dt` below {limit:.6e} s")
    };
    Err(Error::analysis_setting(
        "dt",
        format!(
            "Δt = {:.6e} s exceeds the stability limit {limit:.6e} s of this scheme on this model (highest \
             natural frequency {:.4e} Hz): {advice}, or use scheme = \"average_acceleration\", which is \
             stable for every step",
            timing.dt,
            omega_max / (2.0 * PI)
        ),
    ))
}
