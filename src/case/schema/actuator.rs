//! Actuators and their stacks as a case file writes them.

use super::analysis::{at_length, PointSpec};
use super::d_true;
use super::signal::SignalSpec;
use super::{imported_tolerance, non_negative, on_beam, positive, Extent};
use crate::actuator::bouc_wen::BoucWen;
use crate::error::{Error, Result};
use crate::structure::Location;
use serde::{Deserialize, Serialize};

/// An actuator as a case file writes it: the common fields, the stack, the drive and
/// the body its type adds. Fields of the other type are refused when the file is read.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(try_from = "ActuatorToml", into = "ActuatorToml")]
pub struct ActuatorSpec {
    pub name: Option<String>,
    /// Stack foot position on a beam x_E (m).
    pub x_e: f64,
    /// Stack foot position (x, y) on a plate, or (x, y, z) of its node on an imported model
    /// (m), in place of `x_e`.
    pub at: Option<Vec<f64>>,
    /// The stack foot's node on an imported model and the component the stack pushes along
    /// (`uz`, or `-uz` for an actuator on the other side), in place of `x_e`.
    pub node: Option<i64>,
    pub component: Option<String>,
    /// How far (m) a foot found by position on an imported model (`at`, or a frame's legs
    /// along `direction`) may lie from its node (default: 1 % of the node spacing).
    pub tolerance: Option<f64>,
    /// A frame's left and right leg nodes on an imported model.
    pub legs: Option<[i64; 2]>,
    /// A frame's in-plane direction ψ (degrees from +x): its legs stand on the line through
    /// the stack foot along (cos ψ, sin ψ) (on an imported model (cos ψ, sin ψ, 0), each on
    /// the node nearest its position).
    pub direction: f64,
    pub body: BodySpec,
    pub stack: StackSpec,
    pub voltage: SignalSpec,
}

/// What an actuator's stack pushes against, by type, with every default resolved.
#[derive(Clone, Debug, PartialEq)]
pub enum BodySpec {
    /// An inertial actuator: a top mass on the stack.
    Inertial {
        /// Top mass m_t (kg).
        m_t: f64,
    },
    /// A frame actuator: a top beam on two legs standing on the beam.
    Frame(FrameSpec),
}

/// The frame of a frame actuator.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameSpec {
    /// Top beam mass m_b (kg).
    pub m_b: f64,
    /// Top beam moment of inertia J_b (kg·m²).
    pub j_b: f64,
    /// Half leg spacing a (m).
    pub a: f64,
    /// Stack offset from the frame's centre e (m).
    pub e: f64,
    pub left: LegSpec,
    pub right: LegSpec,
}

/// A frame leg: stiffness k_l (N/m) and damping c_l (N·s/m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LegSpec {
    pub k_l: f64,
    pub c_l: f64,
}

/// Defaults of the spec's actuators.
pub const DEFAULT_X_E: f64 = 0.150;
pub const DEFAULT_M_T: f64 = 0.1;
pub const DEFAULT_M_B: f64 = 0.2;
pub const DEFAULT_J_B: f64 = 1.6667e-4;
pub const DEFAULT_A: f64 = 0.040;
pub const DEFAULT_E: f64 = 0.001;
pub const DEFAULT_LEG: LegSpec = LegSpec { k_l: 1.5e9, c_l: 100.0 };

impl ActuatorSpec {
    /// `"inertial"` or `"frame"`, as the case file's `type`.
    pub fn type_name(&self) -> &'static str {
        match self.body {
            BodySpec::Inertial { .. } => "inertial",
            BodySpec::Frame(_) => "frame",
        }
    }

    /// The mass the actuator adds on top of its stack (kg): m_t or m_b.
    pub fn body_mass(&self) -> f64 {
        match &self.body {
            BodySpec::Inertial { m_t } => *m_t,
            BodySpec::Frame(f) => f.m_b,
        }
    }
}

impl FrameSpec {
    /// Leg positions (m), left and right: x_c ∓ a with the frame centre x_c = x_E − e.
    pub fn leg_positions(&self, x_e: f64) -> (f64, f64) {
        let [_, left, right] = crate::actuator::frame::feet(Location::Beam { x: x_e }, self.e, self.a, 0.0);
        (left.x(), right.x())
    }
}

/// The `[[actuator]]` table as written: one flat table, type-specific fields optional.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct ActuatorToml {
    #[serde(rename = "type")]
    kind: ActuatorType,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    name: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    x_e: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    at: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    node: Option<i64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    component: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    tolerance: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    legs: Option<[i64; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    direction: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    m_t: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    m_b: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    j_b: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    a: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    e: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    k_l: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    c_l: Option<f64>,
    /// Right-leg values where the legs differ (default: as the left).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    k_l_right: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    c_l_right: Option<f64>,
    #[serde(default)]
    stack: StackSpec,
    voltage: SignalSpec,
}

#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
enum ActuatorType {
    Inertial,
    Frame,
}

impl TryFrom<ActuatorToml> for ActuatorSpec {
    type Error = String;

    fn try_from(t: ActuatorToml) -> std::result::Result<ActuatorSpec, String> {
        let frame_only = [
            ("m_b", t.m_b),
            ("j_b", t.j_b),
            ("a", t.a),
            ("e", t.e),
            ("k_l", t.k_l),
            ("c_l", t.c_l),
            ("k_l_right", t.k_l_right),
            ("c_l_right", t.c_l_right),
        ];
        let body = match t.kind {
            ActuatorType::Inertial => {
                if let Some((n, _)) = frame_only.iter().find(|(_, v)| v.is_some()) {
                    return Err(format!(
                        "actuator field `{n}` applies only to a frame actuator, and this one is inertial"
                    ));
                }
                BodySpec::Inertial { m_t: t.m_t.unwrap_or(DEFAULT_M_T) }
            }
            ActuatorType::Frame => {
                if t.m_t.is_some() {
                    return Err(
                        "actuator field `m_t` applies only to an inertial actuator (a frame has m_b, j_b)".into()
                    );
                }
                let left = LegSpec { k_l: t.k_l.unwrap_or(DEFAULT_LEG.k_l), c_l: t.c_l.unwrap_or(DEFAULT_LEG.c_l) };
                let right = LegSpec { k_l: t.k_l_right.unwrap_or(left.k_l), c_l: t.c_l_right.unwrap_or(left.c_l) };
                BodySpec::Frame(FrameSpec {
                    m_b: t.m_b.unwrap_or(DEFAULT_M_B),
                    j_b: t.j_b.unwrap_or(DEFAULT_J_B),
                    a: t.a.unwrap_or(DEFAULT_A),
                    e: t.e.unwrap_or(DEFAULT_E),
                    left,
                    right,
                })
            }
        };
        if t.at.is_some() && t.x_e.is_some() {
            return Err("give the stack foot as `x_e` on a beam or as `at = [x, y]` on a plate, not both".into());
        }
        if t.direction.is_some() && t.at.is_none() && t.node.is_none() {
            let beam =
                if t.x_e.is_some() { "; a beam's frame stands along it, at `x_e`, with no direction" } else { "" };
            return Err(format!(
                "`direction` turns a frame about its stack foot: it needs `at` (plate) or `node` or `at` \
                 (imported model){beam}"
            ));
        }
        if t.direction.is_some() && t.legs.is_some() {
            return Err("`direction` places a frame's legs and `legs` names their nodes: give one, not both".into());
        }
        if t.node.is_some() && (t.at.is_some() || t.x_e.is_some()) {
            return Err(
                "give the stack foot as `x_e` (beam), `at` (plate) or `node` (imported model), not several".into()
            );
        }
        if t.legs.is_some() && !matches!(body, BodySpec::Frame(_)) {
            return Err("actuator field `legs` applies only to a frame actuator, and this one is inertial".into());
        }
        if (t.legs.is_some() || t.component.is_some()) && t.node.is_none() && t.at.is_none() {
            return Err(
                "`component` and `legs` go with `node` or `at = [x, y, z]`, the stack foot on an imported model".into(),
            );
        }
        Ok(ActuatorSpec {
            name: t.name,
            x_e: t.x_e.unwrap_or(DEFAULT_X_E),
            at: t.at,
            node: t.node,
            component: t.component,
            tolerance: t.tolerance,
            legs: t.legs,
            direction: t.direction.unwrap_or(0.0),
            body,
            stack: t.stack,
            voltage: t.voltage,
        })
    }
}

impl From<ActuatorSpec> for ActuatorToml {
    /// Every value written out, defaults included: a serialised case states what ran.
    fn from(a: ActuatorSpec) -> ActuatorToml {
        let mut t = ActuatorToml {
            kind: ActuatorType::Inertial,
            name: a.name,
            x_e: (a.at.is_none() && a.node.is_none()).then_some(a.x_e),
            direction: ((a.at.is_some() || a.node.is_some())
                && a.legs.is_none()
                && matches!(a.body, BodySpec::Frame(_)))
            .then_some(a.direction),
            at: a.at,
            node: a.node,
            component: a.component,
            tolerance: a.tolerance,
            legs: a.legs,
            m_t: None,
            m_b: None,
            j_b: None,
            a: None,
            e: None,
            k_l: None,
            c_l: None,
            k_l_right: None,
            c_l_right: None,
            stack: a.stack,
            voltage: a.voltage,
        };
        match a.body {
            BodySpec::Inertial { m_t } => t.m_t = Some(m_t),
            BodySpec::Frame(f) => {
                t.kind = ActuatorType::Frame;
                (t.m_b, t.j_b, t.a, t.e) = (Some(f.m_b), Some(f.j_b), Some(f.a), Some(f.e));
                (t.k_l, t.c_l) = (Some(f.left.k_l), Some(f.left.c_l));
                if f.right != f.left {
                    (t.k_l_right, t.c_l_right) = (Some(f.right.k_l), Some(f.right.c_l));
                }
            }
        }
        t
    }
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
            let kind = self.type_name();
            if count > 1 {
                format!("{kind}_{index}")
            } else {
                kind.to_string()
            }
        })
    }

    /// Where the stack foot stands (on whichever structure the case has; a node without a
    /// valid component, which validation refuses, reads as NaN).
    pub fn location(&self) -> Location {
        self.point().location().unwrap_or(Location::Beam { x: f64::NAN })
    }

    /// The stack foot as a point is written.
    pub fn point(&self) -> PointSpec {
        PointSpec {
            x: Some(self.x_e),
            at: self.at.clone(),
            node: self.node,
            component: self.component.clone(),
            tolerance: self.tolerance,
        }
    }

    /// Node `n` along this actuator's component.
    fn node_location(&self, n: i64) -> std::result::Result<Location, String> {
        let c = self.component.as_deref().ok_or_else(|| format!("node {n} needs a `component` (e.g. \"uz\")"))?;
        Location::node(n, c)
    }

    /// The feet of the actuator: the stack's, then a frame's left and right legs.
    pub fn feet(&self) -> Vec<(&'static str, Location)> {
        let stack = self.location();
        match &self.body {
            BodySpec::Inertial { .. } => vec![("stack", stack)],
            BodySpec::Frame(_) if self.legs.is_some() => {
                let legs = self.legs.unwrap_or_default().map(|n| self.node_location(n).unwrap_or(stack));
                vec![("stack", stack), ("left leg", legs[0]), ("right leg", legs[1])]
            }
            BodySpec::Frame(fr) => {
                let [at, left, right] = crate::actuator::frame::feet(stack, fr.e, fr.a, self.direction.to_radians());
                // A node stays the node named; a beam's or plate's foot is written from x_c.
                let stack = if matches!(stack, Location::Node { .. } | Location::Near { .. }) { stack } else { at };
                vec![("stack", stack), ("left leg", left), ("right leg", right)]
            }
        }
    }

    pub(super) fn validate(&self, file: &str, f: &str, extent: Extent) -> Result<()> {
        match &self.body {
            BodySpec::Inertial { m_t } => positive(file, &format!("{f}.m_t"), *m_t)?,
            BodySpec::Frame(fr) => {
                positive(file, &format!("{f}.m_b"), fr.m_b)?;
                positive(file, &format!("{f}.j_b"), fr.j_b)?;
                positive(file, &format!("{f}.a"), fr.a)?;
                if !fr.e.is_finite() || fr.e.abs() >= fr.a {
                    return Err(Error::input(
                        file,
                        format!("{f}.e"),
                        format!("the stack offset must lie between the legs, |e| < a = {} m, got {}", fr.a, fr.e),
                    ));
                }
                positive(file, &format!("{f}.k_l"), fr.left.k_l)?;
                non_negative(file, &format!("{f}.c_l"), fr.left.c_l)?;
                positive(file, &format!("{f}.k_l_right"), fr.right.k_l)?;
                non_negative(file, &format!("{f}.c_l_right"), fr.right.c_l)?;
            }
        }
        if let Extent::Beam { length } = extent {
            if self.at.is_some() {
                return Err(Error::input(file, format!("{f}.at"), "a beam takes the stack foot as `x_e` (m)"));
            }
            on_beam(file, &format!("{f}.x_e"), self.x_e, length)?;
            if let BodySpec::Frame(fr) = &self.body {
                let (left, right) = fr.leg_positions(self.x_e);
                for (leg, x) in [("left leg", left), ("right leg", right)] {
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
        let imported = extent == Extent::Imported;
        let legs_by_position = matches!(self.body, BodySpec::Frame(_)) && self.legs.is_none();
        imported_tolerance(
            file,
            f,
            self.tolerance,
            imported && (self.at.is_some() || legs_by_position),
            "`at = [x, y, z]` or a frame's legs along `direction`",
        )?;
        if let Some(at) = &self.at {
            at_length(at, extent).map_err(|why| Error::input(file, format!("{f}.at"), why))?;
        }
        if imported {
            if self.node.is_none() && self.at.is_none() {
                return Err(Error::input(
                    file,
                    format!("{f}.node"),
                    "an imported model takes the stack foot as `node` or `at = [x, y, z]`, with `component`",
                ));
            }
            self.point().location().map_err(|why| Error::input(file, format!("{f}.component"), why))?;
            direction(file, f, self.direction)?;
        } else if self.node.is_some() {
            return Err(Error::input(
                file,
                format!("{f}.node"),
                "`node` names a point of an imported model, and this case has none",
            ));
        } else if self.component.is_some() {
            return Err(Error::input(
                file,
                format!("{f}.component"),
                "a component goes with `node` or `at = [x, y, z]` (an imported model)",
            ));
        }
        if let Extent::Plate { .. } = extent {
            if self.at.is_none() {
                return Err(Error::input(file, format!("{f}.at"), "a plate takes the stack foot as `at = [x, y]` (m)"));
            }
            direction(file, f, self.direction)?;
            for (foot, at) in self.feet() {
                if let Err(why) = extent.holds(&at) {
                    let field = if foot == "stack" { format!("{f}.at") } else { format!("{f}.direction") };
                    return Err(Error::input(file, field, format!("the {foot} foot: {why}")));
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
}

/// A frame's in-plane direction (degrees from +x) within one turn either way: beyond it
/// the angle's sine and cosine keep no digits of what was meant (10³⁰⁰ degrees).
fn direction(file: &str, f: &str, degrees: f64) -> Result<()> {
    if !(-360.0..=360.0).contains(&degrees) {
        return Err(Error::input(
            file,
            format!("{f}.direction"),
            format!(
                "{} is not an angle within −360 to 360 degrees from +x",
                if degrees.abs() < 1e6 { format!("{degrees}") } else { format!("{degrees:e}") }
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const SINE: &str = "[voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n";

    fn parse(text: &str) -> std::result::Result<ActuatorSpec, String> {
        toml::from_str(&format!("{text}{SINE}")).map_err(|e| e.to_string())
    }

    #[test]
    fn defaults_are_resolved_when_read() {
        let a = parse("type = \"frame\"\nk_l_right = 2e9\n").unwrap();
        let BodySpec::Frame(f) = &a.body else { panic!("{a:?}") };
        assert_eq!((f.m_b, f.j_b, f.a, f.e), (DEFAULT_M_B, DEFAULT_J_B, DEFAULT_A, DEFAULT_E));
        assert_eq!(f.left, DEFAULT_LEG);
        assert_eq!(f.right, LegSpec { k_l: 2e9, c_l: DEFAULT_LEG.c_l }, "the right leg takes the left's other values");
        assert_eq!(a.x_e, DEFAULT_X_E);
        let a = parse("type = \"inertial\"\n").unwrap();
        assert_eq!(a.body, BodySpec::Inertial { m_t: DEFAULT_M_T });
        assert_eq!(a.body_mass(), DEFAULT_M_T);
    }

    #[test]
    fn written_out_it_reads_back_the_same() {
        for text in [
            "type = \"frame\"\nc_l_right = 50.0\ne = -0.002\n",
            "type = \"frame\"\n",
            "type = \"inertial\"\nm_t = 0.3\n",
        ] {
            let a = parse(text).unwrap();
            let back: ActuatorSpec = toml::from_str(&toml::to_string(&a).unwrap()).unwrap();
            assert_eq!((back.body, back.x_e), (a.body, a.x_e), "{text}");
        }
    }

    #[test]
    fn fields_of_the_other_type_are_refused() {
        let e = parse("type = \"inertial\"\nj_b = 1e-4\n").unwrap_err();
        assert!(e.contains("`j_b` applies only to a frame"), "{e}");
        let e = parse("type = \"frame\"\nm_t = 0.1\n").unwrap_err();
        assert!(e.contains("`m_t` applies only to an inertial"), "{e}");
    }
}
