//! Actuators as physics: bodies with mass, and spring–damper links from a top point on a
//! body to a foot that stands on the base (a beam node or the rigid ground).
//!
//! Each actuator type reduces to one [`Component`] description: its body DOFs and mass
//! matrix, its links (stack, legs) with the top-point kinematics, and where its feet stand.
//! Assembly and the solvers only ever see that description, so a new actuator type is a
//! new `component()` — no solver changes.

pub mod bouc_wen;
pub mod frame;
pub mod inertial;
pub mod stack;

pub use frame::{Frame, Leg};
pub use inertial::Inertial;
pub use stack::Stack;

use nalgebra::DMatrix;

/// A link's identifier in results, tables and figures: the actuator's name and the link's
/// (`frame_left_leg`, `inertial_stack`). The one format every output uses.
pub fn link_id(actuator: &str, link: &str) -> String {
    format!("{actuator}_{link}")
}

/// An actuator of either type.
#[derive(Clone, Debug)]
pub enum Actuator {
    Inertial(Inertial),
    Frame(Frame),
}

impl Actuator {
    pub fn name(&self) -> &str {
        match self {
            Actuator::Inertial(a) => &a.name,
            Actuator::Frame(a) => &a.name,
        }
    }

    pub fn stack(&self) -> &Stack {
        match self {
            Actuator::Inertial(a) => &a.stack,
            Actuator::Frame(a) => &a.stack,
        }
    }

    /// The stack, to change its drive: a sweep over drive frequencies keeps one model per
    /// placement and sets each case's voltage on it.
    pub fn stack_mut(&mut self) -> &mut Stack {
        match self {
            Actuator::Inertial(a) => &mut a.stack,
            Actuator::Frame(a) => &mut a.stack,
        }
    }

    /// Short type name, as in case files.
    pub fn kind(&self) -> &'static str {
        match self {
            Actuator::Inertial(_) => "inertial",
            Actuator::Frame(_) => "frame",
        }
    }

    /// The mechanical description the assembler consumes.
    pub fn component(&self) -> Component {
        match self {
            Actuator::Inertial(a) => a.component(),
            Actuator::Frame(a) => a.component(),
        }
    }
}

/// Where a link's foot stands.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FootBase {
    /// On the structure at a point: joined to its normal displacement w there.
    On(crate::structure::Location),
    /// On the rigid ground.
    Ground,
}

/// A spring–damper between a top point on the actuator's bodies and a foot on the base.
/// Its stretch is u = z_top − z_foot.
#[derive(Clone, Debug)]
pub struct Link {
    /// "stack", "left_leg", "right_leg".
    pub name: String,
    /// Spring stiffness (N/m).
    pub k: f64,
    /// Viscous damping (N·s/m).
    pub c: f64,
    /// Top point displacement as Σ coeff·(body DOF): e.g. y + e·φ.
    pub top: Vec<(usize, f64)>,
    pub foot: FootBase,
    /// Mass lumped at the foot point (kg): half the stack mass for a stack foot.
    pub foot_mass: f64,
    /// Whether the stack's active force F_p acts along this link.
    pub active: bool,
}

/// The mechanical description of an actuator.
#[derive(Clone, Debug)]
pub struct Component {
    /// Names of the body DOFs (m or rad), e.g. ["z_t"] or ["y", "phi"].
    pub dof_names: Vec<&'static str>,
    /// Mass matrix of the bodies over those DOFs (kg, kg·m, kg·m²).
    pub mass: DMatrix<f64>,
    pub links: Vec<Link>,
}
