//! The result vocabulary the time- and frequency-domain analyses share: time series of
//! links, bodies, drives and sensors over a recorded window, a link's harmonic content, and
//! the two energy balances. Output and figures read these; the analyses fill them.

use crate::actuator::bouc_wen::BoucWen;
use crate::assembly::{LinkDofs, Model, System};
use crate::power::balance::EnergyBalance;
use crate::power::point::instantaneous_power;
use crate::power::spectra::{power_from_acceleration, power_per_harmonic};
use crate::structure::Location;
use num_complex::Complex64;
use serde::Serialize;
use std::f64::consts::PI;

/// Time histories of one link (stack or leg), SI units.
#[derive(Clone, Debug, Default, Serialize)]
pub struct LinkSeries {
    pub actuator: usize,
    pub name: String,
    /// Foot position (m): x on a beam or plate, None on the rigid ground.
    pub foot_x: Option<f64>,
    /// Foot y on a plate (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub foot_y: Option<f64>,
    /// The foot's point on the structure (z, node and component on an imported model).
    #[serde(skip)]
    pub foot_at: Option<Location>,
    /// Stretch u = z_top − z_foot (m) and its rate (m/s).
    pub stretch: Vec<f64>,
    pub stretch_rate: Vec<f64>,
    /// Components of the transmitted force (N): k·u, c·u̇, −F_p.
    pub f_stiffness: Vec<f64>,
    pub f_damping: Vec<f64>,
    pub f_pzt: Vec<f64>,
    /// Force on the base at the foot, positive up (N).
    pub transmitted: Vec<f64>,
    /// Force across the actuator–structure interface: transmitted minus foot-mass inertia (N).
    pub interface: Vec<f64>,
    /// Base velocity (m/s) and acceleration (m/s²) at the foot.
    pub base_velocity: Vec<f64>,
    pub base_acceleration: Vec<f64>,
    /// Instantaneous power into the base at the foot (W).
    pub power: Vec<f64>,
}

impl LinkSeries {
    /// An empty series of link `lk`.
    pub fn of(lk: &LinkDofs) -> Self {
        LinkSeries {
            actuator: lk.actuator,
            name: lk.name.clone(),
            foot_x: lk.foot_at.map(|a| a.x()),
            foot_y: lk.foot_at.and_then(|a| a.y()),
            foot_at: lk.foot_at,
            ..Default::default()
        }
    }

    /// Adds what follows from the stretch, its rate and the interface force and velocity:
    /// the stiffness and damping components k·u, c·u̇ (N) and the instantaneous power (W).
    pub fn complete(mut self, lk: &LinkDofs) -> Self {
        self.f_stiffness = self.stretch.iter().map(|x| lk.k * x).collect();
        self.f_damping = self.stretch_rate.iter().map(|x| lk.c * x).collect();
        self.power = instantaneous_power(&self.interface, &self.base_velocity);
        self
    }

    /// The last `n` samples of every series.
    pub fn tail(&self, n: usize) -> LinkSeries {
        let t = |v: &Vec<f64>| v[v.len().saturating_sub(n)..].to_vec();
        LinkSeries {
            actuator: self.actuator,
            name: self.name.clone(),
            foot_x: self.foot_x,
            foot_y: self.foot_y,
            foot_at: self.foot_at,
            stretch: t(&self.stretch),
            stretch_rate: t(&self.stretch_rate),
            f_stiffness: t(&self.f_stiffness),
            f_damping: t(&self.f_damping),
            f_pzt: t(&self.f_pzt),
            transmitted: t(&self.transmitted),
            interface: t(&self.interface),
            base_velocity: t(&self.base_velocity),
            base_acceleration: t(&self.base_acceleration),
            power: t(&self.power),
        }
    }
}

/// History of one body DOF (m or rad, and rates).
#[derive(Clone, Debug, Default, Serialize)]
pub struct BodySeries {
    pub actuator: usize,
    pub dof: String,
    pub q: Vec<f64>,
    pub q_dot: Vec<f64>,
    pub q_ddot: Vec<f64>,
}

/// A body DOF of the system: its actuator, its name (e.g. "z_t", "phi") and its index.
#[derive(Clone, Debug)]
pub struct BodyDof {
    pub actuator: usize,
    pub name: &'static str,
    pub dof: usize,
}

/// Every body DOF of `sys`, actuator by actuator.
pub fn body_dofs(model: &Model, sys: &System) -> Vec<BodyDof> {
    let mut out = Vec::new();
    for (a, ds) in sys.dofs.bodies.iter().enumerate() {
        let names = model.actuators[a].component().dof_names;
        out.extend(ds.iter().zip(names).map(|(&dof, name)| BodyDof { actuator: a, name, dof }));
    }
    out
}

/// The drive of one actuator: voltage (V), hysteretic displacement h (m), free stroke
/// δ = d_p·V − h (m), active force F_p (N).
#[derive(Clone, Debug, Default, Serialize)]
pub struct DriveSeries {
    pub actuator: usize,
    pub voltage: Vec<f64>,
    pub h: Vec<f64>,
    pub stroke: Vec<f64>,
    pub f_p: Vec<f64>,
}

impl DriveSeries {
    /// Actuator `actuator`'s drive from its voltage, h and F_p samples, the free stroke from
    /// its stack's `hysteresis` model.
    pub fn new(actuator: usize, hysteresis: &BoucWen, voltage: Vec<f64>, h: Vec<f64>, f_p: Vec<f64>) -> Self {
        let stroke = voltage.iter().zip(&h).map(|(&v, &h)| hysteresis.stroke(v, h)).collect();
        DriveSeries { actuator, voltage, h, stroke, f_p }
    }

    /// The last `n` samples of every series.
    pub fn tail(&self, n: usize) -> DriveSeries {
        let t = |v: &Vec<f64>| v[v.len().saturating_sub(n)..].to_vec();
        DriveSeries {
            actuator: self.actuator,
            voltage: t(&self.voltage),
            h: t(&self.h),
            stroke: t(&self.stroke),
            f_p: t(&self.f_p),
        }
    }
}

/// Beam motion at a sensor: w (m), ẇ (m/s), ẅ (m/s²).
#[derive(Clone, Debug, Default, Serialize)]
pub struct SensorSeries {
    pub name: String,
    pub x: f64,
    /// y on a plate (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub y: Option<f64>,
    /// The point on the structure (z, node and component on an imported model).
    #[serde(skip)]
    pub at: Option<Location>,
    pub w: Vec<f64>,
    pub v: Vec<f64>,
    pub a: Vec<f64>,
}

/// Harmonic content of a link's signals over one period, k = 0..=harmonics.
#[derive(Clone, Debug, Default, Serialize)]
pub struct LinkSpectrum {
    /// Frequencies k·f₀ (Hz).
    pub frequency: Vec<f64>,
    #[serde(skip)]
    pub transmitted: Vec<Complex64>,
    #[serde(skip)]
    pub interface: Vec<Complex64>,
    #[serde(skip)]
    pub velocity: Vec<Complex64>,
    #[serde(skip)]
    pub acceleration: Vec<Complex64>,
    /// Power per harmonic from force and velocity (W).
    pub power: Vec<f64>,
    /// Power per harmonic from force and acceleration, as measured (W).
    pub power_from_acceleration: Vec<f64>,
    /// Σ over all harmonics up to Nyquist (equals the mean power).
    pub power_total: f64,
}

impl LinkSpectrum {
    /// From the single-sided amplitudes (k = 0, 1, …) of a link's transmitted and interface
    /// forces (N) and its base velocity (m/s) and acceleration (m/s²) over one `period` (s)
    /// of `n_samples` samples, keeping k ≤ `hmax`. The power per harmonic is computed from
    /// velocity and from acceleration, and summed over every harmonic given.
    pub fn new(
        period: f64,
        n_samples: usize,
        hmax: usize,
        transmitted: Vec<Complex64>,
        interface: Vec<Complex64>,
        velocity: Vec<Complex64>,
        acceleration: Vec<Complex64>,
    ) -> Self {
        let omega0 = 2.0 * PI / period;
        let power = power_per_harmonic(&interface, &velocity, n_samples);
        let from_acceleration = power_from_acceleration(&interface, &acceleration, omega0, n_samples);
        let keep = |mut v: Vec<Complex64>| {
            v.truncate(hmax + 1);
            v
        };
        LinkSpectrum {
            frequency: (0..=hmax).map(|k| k as f64 / period).collect(),
            power_total: power.iter().sum(),
            power: power[..=hmax].to_vec(),
            power_from_acceleration: from_acceleration[..=hmax].to_vec(),
            transmitted: keep(transmitted),
            interface: keep(interface),
            velocity: keep(velocity),
            acceleration: keep(acceleration),
        }
    }
}

/// A point load and the beam's motion at its point over a recorded window: force F (N),
/// w (m), ẇ (m/s), ẅ (m/s²).
#[derive(Clone, Debug, Default, Serialize)]
pub struct LoadSeries {
    pub name: String,
    pub x: f64,
    /// y on a plate (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub y: Option<f64>,
    /// The point on the structure (z, node and component on an imported model).
    #[serde(skip)]
    pub at: Option<Location>,
    pub force: Vec<f64>,
    pub w: Vec<f64>,
    pub v: Vec<f64>,
    pub a: Vec<f64>,
}

/// What a point load puts into the beam over one period: its mean power and its harmonic
/// content, k = 0..=harmonics.
#[derive(Clone, Debug, Default, Serialize)]
pub struct LoadSpectrum {
    pub name: String,
    pub x: f64,
    /// Frequencies k·f₀ (Hz).
    pub frequency: Vec<f64>,
    /// Force and velocity amplitudes F̂_k (N), V̂_k (m/s).
    #[serde(skip)]
    pub force: Vec<Complex64>,
    #[serde(skip)]
    pub velocity: Vec<Complex64>,
    /// Power into the beam per harmonic, ½·Re(F̂_k·conj V̂_k) (W).
    pub power: Vec<f64>,
    /// Mean power into the beam: the sum over every harmonic given (W).
    pub power_total: f64,
}

impl LoadSpectrum {
    /// From the single-sided amplitudes of the force and of the velocity at its point over
    /// one `period` (s) of `n_samples` samples, keeping k ≤ `hmax`.
    pub fn new(
        name: &str,
        x: f64,
        (period, n_samples, hmax): (f64, usize, usize),
        mut force: Vec<Complex64>,
        mut velocity: Vec<Complex64>,
    ) -> Self {
        let power = power_per_harmonic(&force, &velocity, n_samples);
        force.truncate(hmax + 1);
        velocity.truncate(hmax + 1);
        LoadSpectrum {
            name: name.to_string(),
            x,
            frequency: (0..=hmax).map(|k| k as f64 / period).collect(),
            power_total: power.iter().sum(),
            power: power[..=hmax].to_vec(),
            force,
            velocity,
        }
    }
}

/// Energy balances of the beam (interface work in) and of the whole system (stack work in).
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Balances {
    pub beam: EnergyBalance,
    pub system: EnergyBalance,
}
