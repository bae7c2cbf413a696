//! Points on a structure, where actuator feet, loads, sensors and attachments act.

use std::fmt;

/// A point on a structure (spec §15): x along a beam, (x, y) in a plate's mid-plane (m).
/// Each attachment at a point acts on the structure's normal displacement w there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Location {
    Beam { x: f64 },
    Plate { x: f64, y: f64 },
}

impl Location {
    /// The x coordinate (m).
    pub fn x(&self) -> f64 {
        match *self {
            Location::Beam { x } | Location::Plate { x, .. } => x,
        }
    }

    /// The y coordinate (m) on a two-dimensional structure.
    pub fn y(&self) -> Option<f64> {
        match *self {
            Location::Beam { .. } => None,
            Location::Plate { y, .. } => Some(y),
        }
    }

    /// The point `along` (m) from this one in the in-plane direction `psi` (rad from +x; a
    /// beam has only ψ = 0). Written as (x + along) on a beam so that it reproduces the
    /// beam's own arithmetic exactly.
    pub fn offset(&self, along: f64, psi: f64) -> Location {
        match *self {
            Location::Beam { x } => Location::Beam { x: x + along },
            Location::Plate { x, y } => Location::Plate { x: x + along * psi.cos(), y: y + along * psi.sin() },
        }
    }

    /// The case-file field that holds a point of this kind: `x` on a beam, `at` on a plate.
    pub fn field(&self) -> &'static str {
        match self {
            Location::Beam { .. } => "x",
            Location::Plate { .. } => "at",
        }
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Location::Beam { x } => write!(f, "x = {x} m"),
            Location::Plate { x, y } => write!(f, "(x, y) = ({x}, {y}) m"),
        }
    }
}
