//! The read-outs a run asks the integrator for: after every step the integrator evaluates
//! each row g as (gᵀu, gᵀv, gᵀa). [`Readout`] lays the rows out — each link's stretch and
//! foot, each drive, each sensor, each body DOF, each point load, in that order — and says where each
//! quantity sits, so that nothing else counts offsets.

use crate::analysis::series::{body_dofs, BodyDof};
use crate::assembly::{Model, System};
use crate::error::Result;

/// The rows of a run's read-outs and where each quantity sits among them.
pub(super) struct Readout {
    rows: Vec<Vec<(usize, f64)>>,
    links: usize,
    drives: usize,
    sensors: usize,
    loads: usize,
    /// The body DOFs, in the order of their rows.
    pub bodies: Vec<BodyDof>,
}

impl Readout {
    pub fn new(model: &Model, sys: &System) -> Result<Self> {
        let sensor_rows: Vec<Vec<(usize, f64)>> =
            model.sensors.iter().map(|se| sys.w_at(model, &se.at, "sensor")).collect::<Result<_>>()?;
        let bodies = body_dofs(model, sys);
        let mut rows: Vec<Vec<(usize, f64)>> = Vec::new();
        for lk in &sys.links {
            rows.push(lk.stretch.clone());
            rows.push(lk.foot.clone());
        }
        rows.extend(sys.drives.iter().cloned());
        let sensors = sensor_rows.len();
        rows.extend(sensor_rows);
        rows.extend(bodies.iter().map(|b| vec![(b.dof, 1.0)]));
        rows.extend(sys.loads.iter().cloned());
        Ok(Readout { rows, links: sys.links.len(), drives: sys.drives.len(), sensors, loads: sys.loads.len(), bodies })
    }

    /// Every row, for the integrator's `set_observations`.
    pub fn rows(&self) -> &[Vec<(usize, f64)>] {
        &self.rows
    }

    pub fn len(&self) -> usize {
        self.rows.len()
    }

    pub fn links(&self) -> usize {
        self.links
    }

    pub fn drives(&self) -> usize {
        self.drives
    }

    pub fn sensors(&self) -> usize {
        self.sensors
    }

    pub fn loads(&self) -> usize {
        self.loads
    }

    /// Row of link l's stretch u = z_top − z_foot (value, rate, acceleration).
    pub fn stretch(&self, l: usize) -> usize {
        2 * l
    }

    /// Row of the base displacement w at link l's foot.
    pub fn foot(&self, l: usize) -> usize {
        2 * l + 1
    }

    /// Row of drive a's load pattern bᵀq (its rate is the velocity the stack works on).
    pub fn drive(&self, a: usize) -> usize {
        2 * self.links + a
    }

    /// Row of the beam's w at sensor s.
    pub fn sensor(&self, s: usize) -> usize {
        2 * self.links + self.drives + s
    }

    /// Row of body DOF b (the order of [`Readout::bodies`]).
    pub fn body(&self, b: usize) -> usize {
        2 * self.links + self.drives + self.sensors + b
    }

    /// Row of the beam's w at point load j.
    pub fn load(&self, j: usize) -> usize {
        2 * self.links + self.drives + self.sensors + self.bodies.len() + j
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::plan::calibrated_model;
    use crate::case::LoadedCase;
    use std::path::PathBuf;

    /// Every named row holds the pattern it names, on a model with every kind of row: two
    /// actuators (a frame's three links and two body DOFs, an inertial's one and one), two
    /// sensors.
    #[test]
    fn each_named_row_holds_its_pattern() {
        let sine = "[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n";
        let text = format!(
            "[beam.mesh]\nelements = 40\n[[actuator]]\ntype = \"frame\"\nx_e = 0.2\n{sine}\
             [[actuator]]\ntype = \"inertial\"\nx_e = 0.5\n{sine}\
             [[sensor]]\nname = \"a\"\nx = 0.365\n[[sensor]]\nname = \"b\"\nx = 0.6\n"
        );
        let cases = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases");
        let model = calibrated_model(&LoadedCase::from_str(&text, "r.toml", cases).unwrap()).unwrap();
        let sys = System::assemble(&model).unwrap();
        let r = Readout::new(&model, &sys).unwrap();
        let rows = r.rows();
        assert_eq!((r.links(), r.drives(), r.sensors(), r.bodies.len()), (4, 2, 2, 3));
        assert_eq!(r.len(), 2 * 4 + 2 + 2 + 3);
        for (l, lk) in sys.links.iter().enumerate() {
            assert_eq!(rows[r.stretch(l)], lk.stretch, "stretch of link {l}");
            assert_eq!(rows[r.foot(l)], lk.foot, "foot of link {l}");
        }
        for (a, b) in sys.drives.iter().enumerate() {
            assert_eq!(&rows[r.drive(a)], b, "drive {a}");
        }
        for (s, se) in model.sensors.iter().enumerate() {
            assert_eq!(rows[r.sensor(s)], sys.w_at(&model, &se.at, "sensor").unwrap(), "sensor {s}");
        }
        for (b, dof) in r.bodies.iter().enumerate() {
            assert_eq!(rows[r.body(b)], vec![(dof.dof, 1.0)], "body DOF {b}");
        }
        let names: Vec<_> = r.bodies.iter().map(|b| (b.actuator, b.name)).collect();
        assert_eq!(names, [(0, "y"), (0, "phi"), (1, "z_t")]);
    }
}
