//! Points on a structure, where actuator feet, loads, sensors and attachments act.

use std::fmt;

/// A point on a structure (spec §15): x along a beam, (x, y) in a plate's mid-plane (m),
/// or a node of an imported model and the component an attachment acts along. On a beam
/// and a plate each attachment acts on the normal displacement w there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Location {
    Beam {
        x: f64,
    },
    Plate {
        x: f64,
        y: f64,
    },
    /// Node `node` (its id in the source model) of an imported model, acting along
    /// component `component` (index into [`crate::imported::COMPONENTS`]) with `sign` ±1;
    /// `xyz` is where the node is (m), filled in when the point is resolved on the model.
    Node {
        node: i64,
        component: u8,
        sign: i8,
        xyz: [f64; 3],
    },
}

impl Location {
    /// Node `node` of an imported model along `component` (`uz`, `-uz`, …), its position
    /// not yet known (NaN until [`crate::structure::Structure::resolve`]). Errors with the
    /// reason if the component is not one.
    pub fn node(node: i64, component: &str) -> std::result::Result<Location, String> {
        let (component, sign) = crate::imported::dof_map::parse_component(component)?;
        Ok(Location::Node { node, component, sign, xyz: [f64::NAN; 3] })
    }

    /// The x coordinate (m).
    pub fn x(&self) -> f64 {
        match *self {
            Location::Beam { x } | Location::Plate { x, .. } => x,
            Location::Node { xyz, .. } => xyz[0],
        }
    }

    /// The y coordinate (m) on a two-dimensional structure.
    pub fn y(&self) -> Option<f64> {
        match *self {
            Location::Beam { .. } => None,
            Location::Plate { y, .. } => Some(y),
            Location::Node { xyz, .. } => Some(xyz[1]),
        }
    }

    /// The point `along` (m) from this one in the in-plane direction `psi` (rad from +x; a
    /// beam has only ψ = 0). Written as (x + along) on a beam so that it reproduces the
    /// beam's own arithmetic exactly.
    pub fn offset(&self, along: f64, psi: f64) -> Location {
        match *self {
            Location::Beam { x } => Location::Beam { x: x + along },
            Location::Plate { x, y } => Location::Plate { x: x + along * psi.cos(), y: y + along * psi.sin() },
            node @ Location::Node { .. } => node,
        }
    }

    /// The case-file field that holds a point of this kind: `x` on a beam, `at` on a plate,
    /// `node` on an imported model.
    pub fn field(&self) -> &'static str {
        match self {
            Location::Beam { .. } => "x",
            Location::Plate { .. } => "at",
            Location::Node { .. } => "node",
        }
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Location::Beam { x } => write!(f, "x = {x} m"),
            Location::Plate { x, y } => write!(f, "(x, y) = ({x}, {y}) m"),
            Location::Node { node, component, sign, .. } => {
                let c = crate::imported::COMPONENTS.get(component as usize).unwrap_or(&"?");
                write!(f, "node {node} {}{c}", if sign < 0 { "−" } else { "" })
            }
        }
    }
}
