//! Actuators and their stacks as a case file writes them.

use super::d_true;
use super::signal::SignalSpec;
use super::{non_negative, on_beam, positive, BaseKind};
use crate::actuator::bouc_wen::BoucWen;
use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum ActuatorType {
    Inertial,
    Frame,
}

/// An actuator. Fields that do not apply to its type are rejected.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ActuatorSpec {
    #[serde(rename = "type")]
    pub kind: ActuatorType,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Stack foot position on the beam x_E (m); default 0.150.
    #[serde(default = "d_x_e")]
    pub x_e: f64,
    /// Inertial: top mass m_t (kg), default 0.1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub m_t: Option<f64>,
    /// Frame: top beam mass m_b (kg), default 0.2.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub m_b: Option<f64>,
    /// Frame: top beam moment of inertia J_b (kg·m²), default 1.6667e-4.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub j_b: Option<f64>,
    /// Frame: half leg spacing a (m), default 0.040.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub a: Option<f64>,
    /// Frame: stack offset from the centre e (m), default 0.001.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub e: Option<f64>,
    /// Frame: leg stiffness k_l (N/m), default 1.5e9, and damping c_l (N·s/m), default 100.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_l: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub c_l: Option<f64>,
    /// Frame: right-leg values where the legs differ (default: as the left).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_l_right: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub c_l_right: Option<f64>,
    #[serde(default)]
    pub stack: StackSpec,
    pub voltage: SignalSpec,
}

fn d_x_e() -> f64 {
    0.150
}

/// The piezo stack (defaults: the spec's 7×7×20 mm PZT stack).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct StackSpec {
    /// N/m
    #[serde(default = "d_kp")]
    pub k_p: f64,
    /// N·s/m
    #[serde(default = "d_cp")]
    pub c_p: f64,
    /// kg
    #[serde(default = "d_mp")]
    pub m_p: f64,
    /// m/V
    #[serde(default = "d_dp")]
    pub d_p: f64,
    /// –
    #[serde(default = "d_alpha")]
    pub alpha: f64,
    /// 1/V
    #[serde(default = "d_beta")]
    pub beta: f64,
    /// 1/V
    #[serde(default = "d_gamma")]
    pub gamma: f64,
    /// Initial hysteretic displacement h(0) (m).
    #[serde(default)]
    pub h0: f64,
    /// false: linear stack, δ = d_p·V.
    #[serde(default = "d_true")]
    pub hysteresis: bool,
}

fn d_kp() -> f64 {
    3.0e7
}
fn d_cp() -> f64 {
    200.0
}
fn d_mp() -> f64 {
    0.030
}
fn d_dp() -> f64 {
    1.3e-7
}
fn d_alpha() -> f64 {
    0.3
}
fn d_beta() -> f64 {
    0.02
}
fn d_gamma() -> f64 {
    0.005
}

impl Default for StackSpec {
    fn default() -> Self {
        toml::from_str("").expect("defaults")
    }
}

impl StackSpec {
    pub fn bouc_wen(&self) -> BoucWen {
        BoucWen { d_p: self.d_p, alpha: self.alpha, beta: self.beta, gamma: self.gamma }
    }
}

impl ActuatorSpec {
    /// Its name: as given, or its type (with its index when the case has several).
    pub fn effective_name(&self, index: usize, count: usize) -> String {
        self.name.clone().unwrap_or_else(|| {
            let kind = match self.kind {
                ActuatorType::Inertial => "inertial",
                ActuatorType::Frame => "frame",
            };
            if count > 1 {
                format!("{kind}_{index}")
            } else {
                kind.to_string()
            }
        })
    }

    pub(super) fn validate(&self, file: &str, f: &str, base: BaseKind, length: f64) -> Result<()> {
        let frame_only = [
            ("m_b", self.m_b),
            ("j_b", self.j_b),
            ("a", self.a),
            ("e", self.e),
            ("k_l", self.k_l),
            ("c_l", self.c_l),
            ("k_l_right", self.k_l_right),
            ("c_l_right", self.c_l_right),
        ];
        match self.kind {
            ActuatorType::Inertial => {
                if let Some((n, _)) = frame_only.iter().find(|(_, v)| v.is_some()) {
                    return Err(Error::input(file, format!("{f}.{n}"), "applies only to a frame actuator"));
                }
                positive(file, &format!("{f}.m_t"), self.m_t())?;
            }
            ActuatorType::Frame => {
                if self.m_t.is_some() {
                    return Err(Error::input(
                        file,
                        format!("{f}.m_t"),
                        "applies only to an inertial actuator (a frame has m_b, j_b)",
                    ));
                }
                positive(file, &format!("{f}.m_b"), self.m_b())?;
                positive(file, &format!("{f}.j_b"), self.j_b())?;
                positive(file, &format!("{f}.a"), self.a())?;
                if !self.e().is_finite() || self.e().abs() >= self.a() {
                    return Err(Error::input(
                        file,
                        format!("{f}.e"),
                        format!(
                            "the stack offset must lie between the legs, |e| < a = {} m, got {}",
                            self.a(),
                            self.e()
                        ),
                    ));
                }
                let (l, r) = self.legs();
                positive(file, &format!("{f}.k_l"), l.0)?;
                non_negative(file, &format!("{f}.c_l"), l.1)?;
                positive(file, &format!("{f}.k_l_right"), r.0)?;
                non_negative(file, &format!("{f}.c_l_right"), r.1)?;
            }
        }
        if base == BaseKind::Beam {
            on_beam(file, &format!("{f}.x_e"), self.x_e, length)?;
            if self.kind == ActuatorType::Frame {
                let xc = self.x_e - self.e();
                for (leg, x) in [("left leg", xc - self.a()), ("right leg", xc + self.a())] {
                    if !(0.0..=length).contains(&x) {
                        return Err(Error::input(
                            file,
                            format!("{f}.x_e"),
                            format!("the {leg} would stand at x = {x} m, outside the beam [0, {length}] m"),
                        ));
                    }
                }
            }
        }
        let s = &self.stack;
        positive(file, &format!("{f}.stack.k_p"), s.k_p)?;
        non_negative(file, &format!("{f}.stack.c_p"), s.c_p)?;
        positive(file, &format!("{f}.stack.m_p"), s.m_p)?;
        if !s.h0.is_finite() {
            return Err(Error::input(file, format!("{f}.stack.h0"), "must be finite"));
        }
        s.bouc_wen().validate().map_err(|e| e.in_table(file, &format!("{f}.stack")))?;
        self.voltage.validate(file, &format!("{f}.voltage"))?;
        Ok(())
    }

    pub fn m_t(&self) -> f64 {
        self.m_t.unwrap_or(0.1)
    }
    pub fn m_b(&self) -> f64 {
        self.m_b.unwrap_or(0.2)
    }
    pub fn j_b(&self) -> f64 {
        self.j_b.unwrap_or(1.6667e-4)
    }
    pub fn a(&self) -> f64 {
        self.a.unwrap_or(0.040)
    }
    pub fn e(&self) -> f64 {
        self.e.unwrap_or(0.001)
    }
    /// ((k_l, c_l) left, (k_l, c_l) right).
    pub fn legs(&self) -> ((f64, f64), (f64, f64)) {
        let k = self.k_l.unwrap_or(1.5e9);
        let c = self.c_l.unwrap_or(100.0);
        ((k, c), (self.k_l_right.unwrap_or(k), self.c_l_right.unwrap_or(c)))
    }
}
