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
    /// A point of an imported model given by position: the node nearest `xyz` (m) that
    /// carries `component` (with `sign`), within `tolerance` (m; `None`: the model's default,
    /// see [`crate::imported::Imported::node_near`]). Becomes a [`Location::Node`] when
    /// resolved on the model, or is refused: never silently moved farther.
    Near {
        xyz: [f64; 3],
        component: u8,
        sign: i8,
        tolerance: Option<f64>,
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

    /// The node of an imported model nearest `xyz` (m) along `component`, within
    /// `tolerance` (see [`Location::Near`]). Errors with the reason if the component is
    /// not one.
    pub fn near(xyz: [f64; 3], component: &str, tolerance: Option<f64>) -> std::result::Result<Location, String> {
        let (component, sign) = crate::imported::dof_map::parse_component(component)?;
        Ok(Location::Near { xyz, component, sign, tolerance })
    }

    /// The x coordinate (m).
    pub fn x(&self) -> f64 {
        match *self {
            Location::Beam { x } | Location::Plate { x, .. } => x,
            Location::Node { xyz, .. } | Location::Near { xyz, .. } => xyz[0],
        }
    }

    /// The y coordinate (m) on a two-dimensional structure.
    pub fn y(&self) -> Option<f64> {
        match *self {
            Location::Beam { .. } => None,
            Location::Plate { y, .. } => Some(y),
            Location::Node { xyz, .. } | Location::Near { xyz, .. } => Some(xyz[1]),
        }
    }

    /// The z coordinate (m) of a point of an imported model; None on a beam and a plate.
    pub fn z(&self) -> Option<f64> {
        match *self {
            Location::Beam { .. } | Location::Plate { .. } => None,
            Location::Node { xyz, .. } | Location::Near { xyz, .. } => Some(xyz[2]),
        }
    }

    /// The node id (as the source model numbers it) and the signed component (`uz`, `-uz`,
    /// as a case file writes it) of a resolved point of an imported model; None elsewhere.
    pub fn node_component(&self) -> Option<(i64, String)> {
        match *self {
            Location::Node { node, component, sign, .. } => {
                let c = crate::imported::COMPONENTS.get(component as usize).unwrap_or(&"?");
                Some((node, format!("{}{c}", if sign < 0 { "-" } else { "" })))
            }
            _ => None,
        }
    }

    /// The point `along` (m) from this one in the in-plane direction `psi` (rad from +x; a
    /// beam has only ψ = 0). Written as (x + along) on a beam so that it reproduces the
    /// beam's own arithmetic exactly. On an imported model the direction is
    /// (cos ψ, sin ψ, 0) and the point there is the node nearest it (a [`Location::Near`]
    /// along the same component; a node's own position must be resolved first).
    pub fn offset(&self, along: f64, psi: f64) -> Location {
        let (cos, sin) = axis_exact(psi);
        let moved = |xyz: [f64; 3]| [xyz[0] + along * cos, xyz[1] + along * sin, xyz[2]];
        match *self {
            Location::Beam { x } => Location::Beam { x: x + along },
            Location::Plate { x, y } => Location::Plate { x: x + along * cos, y: y + along * sin },
            Location::Node { component, sign, xyz, .. } => {
                Location::Near { xyz: moved(xyz), component, sign, tolerance: None }
            }
            Location::Near { xyz, component, sign, tolerance } => {
                Location::Near { xyz: moved(xyz), component, sign, tolerance }
            }
        }
    }

    /// The same point found within `tolerance` (m) if it is one found by position.
    pub fn within(self, tolerance: Option<f64>) -> Location {
        match self {
            Location::Near { xyz, component, sign, .. } => Location::Near { xyz, component, sign, tolerance },
            at => at,
        }
    }

    /// The case-file field that holds a point of this kind: `x` on a beam, `at` on a plate,
    /// `node` (or `at`, by position) on an imported model.
    pub fn field(&self) -> &'static str {
        match self {
            Location::Beam { .. } => "x",
            Location::Plate { .. } | Location::Near { .. } => "at",
            Location::Node { .. } => "node",
        }
    }
}

/// Refuses a point given by coordinates (m) that are not all finite, saying what to write.
pub fn finite_point(xyz: &[f64; 3]) -> std::result::Result<(), String> {
    match xyz.iter().all(|v| v.is_finite()) {
        true => Ok(()),
        false => Err(format!("{xyz:?} is not a finite point: give its x, y, z in metres")),
    }
}

/// (cos ψ, sin ψ) with the round-off of a direction along an axis removed: ψ = 90° in
/// radians is not π/2 exactly, and cos ψ ≈ 6e-17 would put a foot written to stand on an
/// edge a hair outside it.
fn axis_exact(psi: f64) -> (f64, f64) {
    let snap = |v: f64| if v.abs() < 1e-15 { 0.0 } else { v };
    let (cos, sin) = (snap(psi.cos()), snap(psi.sin()));
    match (cos == 0.0, sin == 0.0) {
        (true, false) => (0.0, sin.signum()),
        (false, true) => (cos.signum(), 0.0),
        _ => (cos, sin),
    }
}

/// A coordinate (m) as written in messages: as given, or in three digits where it is a
/// round-off-sized excursion from zero.
struct Coordinate(f64);

impl fmt::Display for Coordinate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            v if v != 0.0 && v.abs() < 1e-9 => write!(f, "{v:.3e}"),
            v => write!(f, "{v}"),
        }
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Location::Beam { x } => write!(f, "x = {} m", Coordinate(x)),
            Location::Plate { x, y } => write!(f, "(x, y) = ({}, {}) m", Coordinate(x), Coordinate(y)),
            Location::Node { node, component, sign, .. } => {
                let c = crate::imported::COMPONENTS.get(component as usize).unwrap_or(&"?");
                write!(f, "node {node} {}{c}", if sign < 0 { "−" } else { "" })
            }
            Location::Near { xyz: [x, y, z], component, sign, .. } => {
                let c = crate::imported::COMPONENTS.get(component as usize).unwrap_or(&"?");
                let [x, y, z] = [x, y, z].map(Coordinate);
                write!(f, "(x, y, z) = ({x}, {y}, {z}) m {}{c}", if sign < 0 { "−" } else { "" })
            }
        }
    }
}
