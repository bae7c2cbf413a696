//! Constraints on a candidate: where the actuators stand (feet on the beam and off its
//! supports, footprints apart), how hard the stacks are driven, and `quantity <= value` or
//! `quantity >= value` over the results. The placement constraints are checked on the case
//! before anything is solved; a candidate that breaks one is never solved.

use super::quantity::{Outcome, Quantity};
use crate::case::signal::SignalSpec;
use crate::case::{ActuatorSpec, BaseKind, BodySpec, Case, SupportKindSpec};

/// The placement and drive limits (from the `[constraints]` table).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Limits {
    /// Least distance (m) of every foot and leg from a support and from the beam's ends.
    pub support_clearance: f64,
    /// Least gap (m) between two actuators' footprints.
    pub clearance: f64,
    /// Largest peak drive voltage |V| of any stack (V), if limited.
    pub max_voltage: Option<f64>,
}

/// `quantity <= value` or `quantity >= value`.
#[derive(Clone, Debug, PartialEq)]
pub struct Bound {
    /// As written, for messages.
    pub text: String,
    pub quantity: Quantity,
    pub upper: bool,
    pub value: f64,
}

impl Bound {
    /// Parses `expression <= value` or `expression >= value`.
    pub fn parse(text: &str) -> std::result::Result<Bound, String> {
        let (lhs, rhs, upper) = if let Some((l, r)) = text.split_once("<=") {
            (l, r, true)
        } else if let Some((l, r)) = text.split_once(">=") {
            (l, r, false)
        } else {
            return Err(format!("`{text}`: write `expression <= value` or `expression >= value`"));
        };
        let value = rhs.trim().parse::<f64>().map_err(|_| format!("`{}` is not a number", rhs.trim()))?;
        if !value.is_finite() {
            return Err(format!("the bound {value} is not finite"));
        }
        let quantity = Quantity::parse(lhs)?;
        if upper && value < 0.0 && quantity.non_negative() {
            return Err(format!("`{text}` can never hold: `{}` is never negative", lhs.trim()));
        }
        Ok(Bound { text: text.trim().to_string(), quantity, upper, value })
    }

    /// How far the outcome is outside the bound (0 inside), relative to max(|value|, |q|).
    pub fn violation(&self, o: &Outcome) -> std::result::Result<f64, String> {
        let q = o.value(&self.quantity)?;
        let excess = if self.upper { q - self.value } else { self.value - q };
        let scale = self.value.abs().max(q.abs()).max(f64::MIN_POSITIVE);
        Ok(if excess > 0.0 { excess / scale } else { 0.0 })
    }
}

/// A placement or drive limit a candidate breaks: which, and by how much (m or V).
#[derive(Clone, Debug, PartialEq)]
pub struct Violation {
    /// The constraint, as the spec file names it (e.g. `constraints.clearance`).
    pub constraint: String,
    pub detail: String,
    pub amount: f64,
}

/// The interval [lo, hi] (m) a foot-print covers: the point x_E of an inertial actuator,
/// the legs' span x_c ± a of a frame (x_c = x_E − e).
pub fn footprint(a: &ActuatorSpec) -> (f64, f64) {
    match &a.body {
        BodySpec::Inertial { .. } => (a.x_e, a.x_e),
        BodySpec::Frame(f) => f.leg_positions(a.x_e),
    }
}

/// Where an actuator touches the beam: its stack foot, and a frame's legs.
pub fn feet(a: &ActuatorSpec) -> Vec<(&'static str, f64)> {
    match a.body {
        BodySpec::Inertial { .. } => vec![("foot", a.x_e)],
        BodySpec::Frame(_) => {
            let (l, r) = footprint(a);
            vec![("stack foot", a.x_e), ("left leg", l), ("right leg", r)]
        }
    }
}

/// Positions of the beam's supports (m): the listed ones that hold it (not `free`), or
/// both ends when none is listed (clamped–clamped).
pub fn supports(case: &Case) -> Vec<f64> {
    if case.beam.support.is_empty() {
        return vec![0.0, case.beam.length];
    }
    case.beam.support.iter().filter(|s| s.kind != SupportKindSpec::Free).map(|s| s.x).collect()
}

/// An upper bound of |V(t)| (V) of a case's drive: exact for one sine, the sum of the
/// amplitudes for several. A series is unbounded here: its values are in a file the
/// optimiser's periodic analyses cannot drive with anyway.
pub fn peak_voltage(v: &SignalSpec) -> f64 {
    match v {
        SignalSpec::Sine { amplitude, offset, .. } | SignalSpec::Chirp { amplitude, offset, .. } => {
            offset.abs() + amplitude.abs()
        }
        SignalSpec::Sines { offset, components } => {
            offset.abs() + components.iter().map(|c| c.amplitude.abs()).sum::<f64>()
        }
        SignalSpec::Step { from, to, .. } => from.abs().max(to.abs()),
        SignalSpec::Series { .. } => f64::INFINITY,
    }
}

impl Limits {
    /// Every placement and drive limit `case` breaks (empty: it satisfies them all).
    pub fn violations(&self, case: &Case) -> Vec<Violation> {
        let mut out = Vec::new();
        if let Some(p) = &case.plate {
            out.extend(self.plate_violations(case, p));
        } else if case.base == BaseKind::Beam && case.imported.is_none() {
            let length = case.beam.length;
            let sup = supports(case);
            let c = self.support_clearance;
            for (i, a) in case.actuator.iter().enumerate() {
                for (what, x) in feet(a) {
                    let off = (c - x).max(x - (length - c)).max(0.0);
                    if off > 0.0 {
                        out.push(Violation {
                            constraint: "constraints.support_clearance".into(),
                            detail: format!(
                                "actuator[{i}]'s {what} at x = {x:.4} m is not on the beam ({c} m from its ends)"
                            ),
                            amount: off,
                        });
                    }
                    if let Some(&s) = sup.iter().find(|&&s| (x - s).abs() < c || x == s) {
                        out.push(Violation {
                            constraint: "constraints.support_clearance".into(),
                            detail: format!(
                                "actuator[{i}]'s {what} at x = {x:.4} m is within {c} m of the support at {s} m"
                            ),
                            amount: (c - (x - s).abs()).max(f64::MIN_POSITIVE),
                        });
                    }
                }
            }
            out.extend(self.clearance_violations(case, |a, b| {
                let (pa, pb) = (footprint(a), footprint(b));
                (pb.0 - pa.1).max(pa.0 - pb.1)
            }));
        }
        if let Some(vmax) = self.max_voltage {
            for (i, a) in case.actuator.iter().enumerate() {
                let v = peak_voltage(&a.voltage);
                if v > vmax {
                    out.push(Violation {
                        constraint: "constraints.max_voltage".into(),
                        detail: format!("actuator[{i}] is driven up to {v} V, above {vmax} V"),
                        amount: v - vmax,
                    });
                }
            }
        }
        out
    }
}

/// Distance (m) from point p to the segment [a, b] in the plane.
fn point_segment(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 { (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0) } else { 0.0 };
    (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dy)
}

/// Least distance (m) between the segments [a, b] and [c, d] (0 where they cross).
fn segment_gap(a: (f64, f64), b: (f64, f64), c: (f64, f64), d: (f64, f64)) -> f64 {
    let side = |p: (f64, f64), q: (f64, f64), r: (f64, f64)| (q.0 - p.0) * (r.1 - p.1) - (q.1 - p.1) * (r.0 - p.0);
    let crosses = side(a, b, c) * side(a, b, d) < 0.0 && side(c, d, a) * side(c, d, b) < 0.0;
    if crosses {
        return 0.0;
    }
    point_segment(a, c, d).min(point_segment(b, c, d)).min(point_segment(c, a, b)).min(point_segment(d, a, b))
}

/// An actuator's footprint on a plate: the segment between a frame's legs, or an inertial
/// actuator's one foot.
fn plate_footprint(a: &ActuatorSpec) -> ((f64, f64), (f64, f64)) {
    let xy = |l: &crate::structure::Location| (l.x(), l.y().unwrap_or(0.0));
    // `feet` lists the stack foot, then a frame's left and right legs.
    let feet = a.feet();
    match a.body {
        BodySpec::Inertial { .. } => (xy(&feet[0].1), xy(&feet[0].1)),
        BodySpec::Frame(_) => (xy(&feet[1].1), xy(&feet[2].1)),
    }
}

impl Limits {
    /// The placement limits on a plate: every foot inside the plate and at least
    /// `support_clearance` from each held edge (clamped or simply supported) and from each
    /// point support; footprints at least `clearance` apart.
    fn plate_violations(&self, case: &Case, p: &crate::case::PlateSpec) -> Vec<Violation> {
        use crate::case::EdgeSpec;
        let mut out = Vec::new();
        let c = self.support_clearance;
        let (lx, ly) = (p.length_x, p.length_y);
        let e = p.edges;
        // Each held edge as (name, distance of (x, y) to it).
        let edges: [(&str, EdgeSpec, Box<dyn Fn(f64, f64) -> f64>); 4] = [
            ("x = 0", e.x0, Box::new(|x, _| x)),
            ("x = L_x", e.x1, Box::new(move |x, _| lx - x)),
            ("y = 0", e.y0, Box::new(|_, y| y)),
            ("y = L_y", e.y1, Box::new(move |_, y| ly - y)),
        ];
        for (i, a) in case.actuator.iter().enumerate() {
            for (what, at) in a.feet() {
                let (x, y) = (at.x(), at.y().unwrap_or(0.0));
                for (name, kind, dist) in &edges {
                    let d = dist(x, y);
                    let limit = if *kind == EdgeSpec::Free { 0.0 } else { c };
                    if d < limit || d < 0.0 {
                        out.push(Violation {
                            constraint: "constraints.support_clearance".into(),
                            detail: format!(
                                "actuator[{i}]'s {what} foot at (x, y) = ({x:.4}, {y:.4}) m is {d:.4} m from the edge \
                                 {name}, less than {limit} m"
                            ),
                            amount: (limit - d).max(f64::MIN_POSITIVE),
                        });
                    }
                }
                for s in &p.support {
                    let d = (x - s.at[0]).hypot(y - s.at[1]);
                    if d < c {
                        out.push(Violation {
                            constraint: "constraints.support_clearance".into(),
                            detail: format!(
                                "actuator[{i}]'s {what} foot is {d:.4} m from the point support at ({}, {}) m",
                                s.at[0], s.at[1]
                            ),
                            amount: (c - d).max(f64::MIN_POSITIVE),
                        });
                    }
                }
            }
        }
        out.extend(self.clearance_violations(case, |a, b| {
            let ((a0, a1), (b0, b1)) = (plate_footprint(a), plate_footprint(b));
            segment_gap(a0, a1, b0, b1)
        }));
        out
    }

    /// Every pair of actuators whose footprints stand less than `clearance` apart, by the
    /// structure's `gap` (m) between two actuators' footprints.
    fn clearance_violations(&self, case: &Case, gap: impl Fn(&ActuatorSpec, &ActuatorSpec) -> f64) -> Vec<Violation> {
        let mut out = Vec::new();
        for (i, a) in case.actuator.iter().enumerate() {
            for (j, b) in case.actuator.iter().enumerate().skip(i + 1) {
                let gap = gap(a, b);
                if gap < self.clearance {
                    out.push(Violation {
                        constraint: "constraints.clearance".into(),
                        detail: format!(
                            "actuator[{i}] and actuator[{j}] stand {gap:.4} m apart, less than {} m",
                            self.clearance
                        ),
                        amount: self.clearance - gap,
                    });
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case(text: &str) -> Case {
        toml::from_str(text).unwrap()
    }

    const TWO: &str = "[[actuator]]\ntype = \"frame\"\nx_e = 0.2\n[actuator.voltage]\nkind = \"sine\"\n\
                       amplitude = 12.0\nfrequency = 60.0\n[[actuator]]\ntype = \"inertial\"\nx_e = XB\n\
                       [actuator.voltage]\nkind = \"sine\"\namplitude = 200.0\nfrequency = 60.0\n";

    #[test]
    fn placement_and_voltage_limits() {
        let lim = Limits { support_clearance: 0.01, clearance: 0.02, max_voltage: Some(150.0) };
        // Frame legs at 0.199 ± 0.04 = [0.159, 0.239]; inertial at 0.25: gap 0.011 < 0.02.
        let v = lim.violations(&case(&TWO.replace("XB", "0.25")));
        let names: Vec<&str> = v.iter().map(|v| v.constraint.as_str()).collect();
        assert_eq!(names, ["constraints.clearance", "constraints.max_voltage"], "{v:?}");
        assert!((v[0].amount - 0.009).abs() < 1e-12);
        // Inertial 5 mm from the clamped end at 0.73 m.
        let v = lim.violations(&case(&TWO.replace("XB", "0.725")));
        assert!(v.iter().any(|v| v.constraint == "constraints.support_clearance" && v.detail.contains("0.7250")));
        let ok = Limits { max_voltage: Some(250.0), ..lim };
        assert!(ok.violations(&case(&TWO.replace("XB", "0.4"))).is_empty());
    }

    #[test]
    fn bounds_parse_and_measure() {
        let b = Bound::parse("net_power[0] >= 0.5").unwrap();
        let o = Outcome { net_power: vec![0.25], net_power_harmonic: vec![vec![0.0, 0.25]], ..Default::default() };
        assert_eq!(b.violation(&o).unwrap(), 0.5);
        let b = Bound::parse("net_power <= 0.5").unwrap();
        assert_eq!(b.violation(&o).unwrap(), 0.0);
        assert!(Bound::parse("dissipation <= -1").unwrap_err().contains("never"));
        assert!(Bound::parse("net_power < 1").is_err());
    }
}
