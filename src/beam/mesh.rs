//! Beam meshes: nodes on the x axis and the elements between consecutive nodes.
//!
//! A force must act exactly at a node — snapping it to the nearest node would shift the
//! power flow by an amount that depends on the mesh — so generated meshes insert a node at
//! every named point, and a mesh read from a file must already have one there.
//!
//! Mesh file format (TOML, in `meshes/`):
//! ```toml
//! format = "beamflow-mesh-1"
//! nodes = [0.0, 0.1, 0.2]          # x of each node (m), strictly increasing, first = 0
//! [[material]]                      # optional; else the case's beam material
//! name = "steel"
//! youngs_modulus = 210e9            # Pa
//! density = 7850.0                  # kg/m³
//! [[section]]                       # optional; else the case's beam section
//! name = "bar"
//! width = 0.05                      # m
//! thickness = 0.005                 # m
//! [[region]]                        # optional; assigns properties to elements in [from, to]
//! from = 0.0
//! to = 0.2
//! material = "steel"
//! section = "bar"
//! ```

use super::section::{Material, Section};
use crate::error::{Error, Result};
use serde::Deserialize;
use std::path::Path;

/// One element between nodes `nodes[0]` and `nodes[1]` (= nodes[0] + 1).
#[derive(Clone, Debug, PartialEq)]
pub struct MeshElement {
    pub nodes: [usize; 2],
    /// Element length (m).
    pub length: f64,
    /// Bending stiffness EI (N·m²).
    pub ei: f64,
    /// Mass per length ρA (kg/m).
    pub rho_a: f64,
}

/// Nodes and elements of a beam on [0, L].
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    /// Node coordinates (m), strictly increasing.
    pub x: Vec<f64>,
    pub elements: Vec<MeshElement>,
}

/// A named point that must coincide with a node (attachment point, sensor, support).
#[derive(Clone, Debug)]
pub struct RequiredPoint {
    pub x: f64,
    /// Which input asked for it, e.g. `actuator[0].x_e`, for error messages.
    pub name: String,
}

impl Mesh {
    /// Beam length (m).
    pub fn length(&self) -> f64 {
        *self.x.last().unwrap_or(&0.0)
    }

    pub fn n_nodes(&self) -> usize {
        self.x.len()
    }

    /// Tolerance within which a point counts as lying on a node.
    pub fn tolerance(&self) -> f64 {
        1e-9 * self.length().max(1e-12)
    }

    /// The node at x, if there is one within the tolerance.
    pub fn node_at(&self, x: f64) -> Option<usize> {
        let tol = self.tolerance();
        let i = self.x.partition_point(|&xi| xi < x - tol);
        (i < self.x.len() && (self.x[i] - x).abs() <= tol).then_some(i)
    }

    /// A near-uniform mesh of exactly `n_elements` elements with a node at every required
    /// point (more only when there are more segments than elements: each segment needs
    /// one). The points split the beam into segments; each segment gets a share of the
    /// elements proportional to its length ([`segment_counts`]) and is divided uniformly,
    /// so element sizes stay within a factor of about two of L/n.
    pub fn uniform(
        length: f64,
        n_elements: usize,
        points: &[RequiredPoint],
        section: Section,
        material: Material,
    ) -> Mesh {
        let cuts: Vec<f64> = points.iter().map(|p| p.x).collect();
        let (x, lengths) = grid_line(length, n_elements, &cuts);
        let (ei, rho_a) = section.properties(&material);
        let elements = lengths
            .into_iter()
            .enumerate()
            .map(|(i, length)| MeshElement { nodes: [i, i + 1], length, ei, rho_a })
            .collect();
        Mesh { x, elements }
    }

    /// Elements between consecutive nodes with properties from `props(element midpoint)`.
    pub fn from_nodes(x: Vec<f64>, props: impl Fn(f64) -> (f64, f64)) -> Mesh {
        let elements = x
            .windows(2)
            .enumerate()
            .map(|(i, w)| {
                let (ei, rho_a) = props(0.5 * (w[0] + w[1]));
                MeshElement { nodes: [i, i + 1], length: w[1] - w[0], ei, rho_a }
            })
            .collect();
        Mesh { x, elements }
    }

    /// Checks that every required point has a node; the error names the point and the
    /// nearest node, so the user can fix the mesh file.
    pub fn require_nodes(&self, points: &[RequiredPoint], file: &str) -> Result<()> {
        for p in points {
            if self.node_at(p.x).is_none() {
                let nearest = self
                    .x
                    .iter()
                    .min_by(|a, b| (*a - p.x).abs().partial_cmp(&(*b - p.x).abs()).unwrap())
                    .copied()
                    .unwrap_or(f64::NAN);
                return Err(Error::input(
                    file,
                    "nodes",
                    format!("the mesh has no node at x = {} m required by `{}` (nearest node at {} m); add one — forces are never moved to the nearest node", p.x, p.name, nearest),
                ));
            }
        }
        Ok(())
    }

    /// Reads a mesh file. Properties not given in the file come from `section`/`material`.
    pub fn read(path: &Path, section: Section, material: Material) -> Result<Mesh> {
        let text = crate::input_file::read_text(path)?;
        Mesh::parse(&text, &path.display().to_string(), section, material)
    }

    /// At least how many elements a mesh file's text describes, counted from its `nodes`
    /// array without parsing it ([`crate::toml_input::values_at_least`]).
    pub fn elements_at_least(text: &str) -> usize {
        crate::toml_input::values_at_least(text, "nodes").saturating_sub(1)
    }

    /// [`Mesh::read`] on text already in memory; `file` names it in messages.
    pub fn parse(text: &str, file: &str, section: Section, material: Material) -> Result<Mesh> {
        let raw: MeshFile = crate::toml_input::parse(text, file, crate::toml_input::Kind::Mesh)?;
        raw.into_mesh(file, section, material)
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MeshFile {
    format: String,
    nodes: Vec<f64>,
    #[serde(default)]
    material: Vec<NamedMaterial>,
    #[serde(default)]
    section: Vec<NamedSection>,
    #[serde(default)]
    region: Vec<Region>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct NamedMaterial {
    name: String,
    youngs_modulus: f64,
    density: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct NamedSection {
    name: String,
    width: f64,
    thickness: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Region {
    from: f64,
    to: f64,
    material: Option<String>,
    section: Option<String>,
}

impl MeshFile {
    fn into_mesh(self, file: &str, section: Section, material: Material) -> Result<Mesh> {
        if self.format != "beamflow-mesh-1" {
            return Err(Error::input(
                file,
                "format",
                format!("unknown mesh format `{}`; expected `beamflow-mesh-1`", self.format),
            ));
        }
        if self.nodes.len() < 2 {
            return Err(Error::input(file, "nodes", "a mesh needs at least two nodes"));
        }
        if self.nodes[0] != 0.0 {
            return Err(Error::input(
                file,
                "nodes",
                format!("the first node must be at x = 0, found {}", self.nodes[0]),
            ));
        }
        for (i, w) in self.nodes.windows(2).enumerate() {
            if !(w[1] > w[0]) || !w[1].is_finite() {
                return Err(Error::input(
                    file,
                    format!("nodes[{}]", i + 1),
                    format!("node coordinates must be finite and strictly increasing ({} after {})", w[1], w[0]),
                ));
            }
        }
        for (i, m) in self.material.iter().enumerate() {
            positive(file, &format!("material[{i}].youngs_modulus"), m.youngs_modulus)?;
            positive(file, &format!("material[{i}].density"), m.density)?;
        }
        for (i, s) in self.section.iter().enumerate() {
            positive(file, &format!("section[{i}].width"), s.width)?;
            positive(file, &format!("section[{i}].thickness"), s.thickness)?;
        }
        let mut regions = Vec::new();
        for (i, r) in self.region.iter().enumerate() {
            let mat = match &r.material {
                None => material,
                Some(n) => self
                    .material
                    .iter()
                    .find(|m| &m.name == n)
                    .map(|m| Material { youngs_modulus: m.youngs_modulus, density: m.density })
                    .ok_or_else(|| {
                        Error::input(file, format!("region[{i}].material"), format!("no material named `{n}`"))
                    })?,
            };
            let sec = match &r.section {
                None => section,
                Some(n) => self
                    .section
                    .iter()
                    .find(|s| &s.name == n)
                    .map(|s| Section { width: s.width, thickness: s.thickness })
                    .ok_or_else(|| {
                        Error::input(file, format!("region[{i}].section"), format!("no section named `{n}`"))
                    })?,
            };
            if !(r.to > r.from) {
                return Err(Error::input(file, format!("region[{i}]"), "`to` must exceed `from`"));
            }
            regions.push((r.from, r.to, sec.properties(&mat)));
        }
        let default = match (self.section.as_slice(), self.material.as_slice()) {
            ([s], [m]) if regions.is_empty() => Section { width: s.width, thickness: s.thickness }
                .properties(&Material { youngs_modulus: m.youngs_modulus, density: m.density }),
            _ => section.properties(&material),
        };
        Ok(Mesh::from_nodes(self.nodes, |xm| {
            regions.iter().rev().find(|(a, b, _)| xm >= *a && xm <= *b).map_or(default, |r| r.2)
        }))
    }
}

fn positive(file: &str, field: &str, v: f64) -> Result<()> {
    if v > 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(Error::input(file, field, format!("must be positive and finite, got {v}")))
    }
}
/// Nodes on [0, `length`] for about `n_elements` elements with a node at every cut (the
/// beam's mesh, a plate's grid lines): the cuts split the line into segments, each gets a
/// share of the elements proportional to its length ([`segment_counts`]) and is divided
/// uniformly. Returns the node coordinates and each element's length.
pub fn grid_line(length: f64, n_elements: usize, cuts: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let mut all: Vec<f64> = vec![0.0, length];
    all.extend_from_slice(cuts);
    all.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let tol = 1e-9 * length;
    all.dedup_by(|a, b| (*a - *b).abs() <= tol);
    let segments: Vec<f64> = all.windows(2).map(|w| w[1] - w[0]).collect();
    let counts = segment_counts(&segments, n_elements);
    let mut x = vec![0.0];
    let mut lengths = Vec::new();
    for (w, &n) in all.windows(2).zip(&counts) {
        let seg = w[1] - w[0];
        // Every element of a segment gets the segment's nominal length seg/n, not the
        // difference of two rounded node coordinates (which is off by up to an ulp of x,
        // ≈ 1e-14 of h): more accurate, and it makes the segment's element matrices, and so
        // its rows of M, C, K, bitwise periodic, which the transient step exploits.
        let le = seg / n as f64;
        for k in 1..=n {
            x.push(if k == n { w[1] } else { w[0] + seg * k as f64 / n as f64 });
            lengths.push(le);
        }
    }
    (x, lengths)
}

/// How many elements each segment of the given lengths gets so that they sum to `total`
/// (or to the number of segments, if that is more): each its share of `total` by length,
/// at least one, rounded, then one more at a time to the segment whose elements are
/// longest (ties to the first), or one less from the one whose are shortest.
fn segment_counts(segments: &[f64], total: usize) -> Vec<usize> {
    let length: f64 = segments.iter().sum();
    let mut counts: Vec<usize> =
        segments.iter().map(|s| ((s / length * total as f64).round() as usize).max(1)).collect();
    let size = |i: usize, c: &[usize]| segments[i] / c[i] as f64;
    while counts.iter().sum::<usize>() < total {
        let i = (0..counts.len()).fold(0, |b, i| if size(i, &counts) > size(b, &counts) { i } else { b });
        counts[i] += 1;
    }
    while counts.iter().sum::<usize>() > total.max(segments.len()) {
        let i = (0..counts.len())
            .filter(|&i| counts[i] > 1)
            .fold(None, |b: Option<usize>, i| match b {
                Some(b) if size(b, &counts) <= size(i, &counts) => Some(b),
                _ => Some(i),
            })
            .expect("more elements than segments");
        counts[i] -= 1;
    }
    counts
}

#[cfg(test)]
mod tests {
    use super::*;

    fn steel() -> (Section, Material) {
        (Section { width: 0.05, thickness: 0.005 }, Material { youngs_modulus: 210e9, density: 7850.0 })
    }

    #[test]
    fn uniform_mesh_has_nodes_at_required_points() {
        let (s, m) = steel();
        let pts = vec![RequiredPoint { x: 0.15, name: "a".into() }, RequiredPoint { x: 0.109, name: "b".into() }];
        let mesh = Mesh::uniform(0.73, 200, &pts, s, m);
        assert!(mesh.node_at(0.15).is_some() && mesh.node_at(0.109).is_some());
        assert_eq!(mesh.elements.len(), 200);
        // Each element's length is its segment's nominal length: its node span up to the
        // rounding of the coordinates, and equal to the bit within a segment (three segments
        // here, cut at 0.109 and 0.15).
        for e in &mesh.elements {
            let span = mesh.x[e.nodes[1]] - mesh.x[e.nodes[0]];
            assert!((e.length - span).abs() <= 4.0 * f64::EPSILON * 0.73, "{} vs {span}", e.length);
        }
        let mut lengths: Vec<u64> = mesh.elements.iter().map(|e| e.length.to_bits()).collect();
        lengths.dedup();
        assert_eq!(lengths.len(), 3);
        let total: f64 = mesh.elements.iter().map(|e| e.length).sum();
        assert!((total - 0.73).abs() < 1e-13);
        let h = 0.73 / 200.0;
        assert!(mesh.elements.iter().all(|e| e.length > 0.5 * h && e.length < 2.0 * h));
    }

    #[test]
    fn a_mesh_has_the_elements_asked_for_unless_the_points_need_more() {
        let (s, m) = steel();
        // The frame's feet and stack: five segments.
        let pts: Vec<RequiredPoint> =
            [0.109, 0.149, 0.15, 0.189].iter().map(|&x| RequiredPoint { x, name: "p".into() }).collect();
        for n in [5, 7, 200, 500, 501, 1000, 20_000] {
            let mesh = Mesh::uniform(0.73, n, &pts, s, m);
            assert_eq!(mesh.elements.len(), n);
            assert!(pts.iter().all(|p| mesh.node_at(p.x).is_some()));
        }
        // Fewer elements than segments: one per segment.
        assert_eq!(Mesh::uniform(0.73, 3, &pts, s, m).elements.len(), 5);
    }

    #[test]
    fn missing_node_is_an_error_naming_the_point() {
        let (s, m) = steel();
        let mesh = Mesh::uniform(0.73, 10, &[], s, m);
        let err = mesh
            .require_nodes(&[RequiredPoint { x: 0.15, name: "actuator[0].x_e".into() }], "m.toml")
            .unwrap_err()
            .to_string();
        assert!(err.contains("m.toml") && err.contains("actuator[0].x_e") && err.contains("0.15"), "{err}");
    }

    #[test]
    fn elements_are_counted_from_the_nodes_array_without_parsing() {
        let text = "format = \"beamflow-mesh-1\"\n# a, b, c\nnodes = [0.0, 0.1, # x, y\n 0.2,\n 0.3]\n[[section]]\nx = [1, 2, 3]\n";
        assert_eq!(Mesh::elements_at_least(text), 3);
        assert_eq!(Mesh::elements_at_least("nodes = [0.0, 0.1, 0.2,]\n"), 2, "a trailing comma adds no value");
        assert_eq!(Mesh::elements_at_least("format = 1\n"), 0);
    }
}
