//! A plate's mesh file (`[plate.mesh] file = "…"`): graded grid lines, and regions of
//! other thickness or material (spec §16: section and material may vary by region).
//!
//! ```toml
//! format = "beamflow-plate-mesh-1"
//! x = [0.0, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5]   # grid lines (m), strictly increasing, 0 to plate.length_x
//! y = [0.0, 0.1, 0.2, 0.3, 0.4]              # 0 to plate.length_y
//! [[material]]                                # optional, named for regions
//! name = "steel"
//! youngs_modulus = 210e9                      # Pa
//! poisson_ratio = 0.3
//! density = 7850.0                            # kg/m³
//! [[region]]                                  # a box of whole elements, its sides on grid lines
//! x = [0.1, 0.3]
//! y = [0.1, 0.2]
//! thickness = 0.004                           # m; and/or
//! material = "steel"
//! ```
//!
//! The plate's lengths are the case's (`plate.length_x`, `plate.length_y`); the lines must
//! end there. Later regions override earlier ones; elements outside every region take the
//! `[plate]` thickness and material, as does whatever a region leaves out. Every problem
//! is refused before anything is built, naming the mesh file, the field and, where the
//! text has it, its line.

use super::ranges::{self, DENSITY, DIMENSION, YOUNGS_MODULUS};
use super::schema::{thin, PlateSpec};
use crate::error::{Error, Result};
use crate::plate::{Grid, Sheet};
use serde::Deserialize;
use std::path::Path;

/// The format string a plate mesh file starts with.
pub const FORMAT: &str = "beamflow-plate-mesh-1";

/// Most regions (and most materials) a mesh file may name: regions are parts of a plate (a
/// patch, a doubler, a strip), and painting each onto the grid costs its elements.
pub const MAX_REGIONS: usize = 1000;

/// A plate mesh file as read and checked: its grid, and each element's sheet.
#[derive(Clone, Debug)]
pub struct PlateMesh {
    pub grid: Grid,
    /// The regions' distinct sheets; `element_sheet` indexes them from 1 (0: the plate's own).
    pub sheets: Vec<Sheet>,
    /// Each element's sheet, element (i, j) at i + j·n_x; empty when no region is given.
    pub element_sheet: Vec<u32>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MeshFile {
    format: String,
    x: Vec<f64>,
    y: Vec<f64>,
    #[serde(default)]
    material: Vec<NamedMaterial>,
    #[serde(default)]
    region: Vec<Region>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct NamedMaterial {
    name: String,
    youngs_modulus: f64,
    poisson_ratio: f64,
    density: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Region {
    x: [f64; 2],
    y: [f64; 2],
    thickness: Option<f64>,
    material: Option<String>,
}

/// Grid-line counts along x and y a mesh file's text gives, counted without parsing it
/// (see [`crate::toml_input::values_at_least`]): its size before it is read.
pub fn lines_at_least(text: &str) -> [usize; 2] {
    ["x", "y"].map(|k| crate::toml_input::values_at_least(text, k))
}

/// Reads and checks the mesh file at `path` for the plate `p` (its lengths, and the
/// thickness and material of what no region covers).
pub fn read(path: &Path, p: &PlateSpec) -> Result<PlateMesh> {
    let text = crate::input_file::read_text(path)?;
    parse(&text, &path.display().to_string(), p)
}

/// [`read`] on text already in memory; `file` names it in messages.
pub fn parse(text: &str, file: &str, p: &PlateSpec) -> Result<PlateMesh> {
    let raw: MeshFile = crate::toml_input::parse(text, file, crate::toml_input::Kind::PlateMesh)?;
    if raw.format != FORMAT {
        let reason = format!("unknown plate mesh format `{}`; expected `{FORMAT}`", raw.format);
        return Err(with_line(Error::input(file, "format", reason), key_line(text, "format")));
    }
    for (name, lines, length) in [("x", &raw.x, p.length_x), ("y", &raw.y, p.length_y)] {
        grid_lines(file, name, lines, length).map_err(|e| with_line(e, key_line(text, name)))?;
    }
    if raw.material.len() > MAX_REGIONS || raw.region.len() > MAX_REGIONS {
        let reason = format!("more than {MAX_REGIONS} materials or regions; merge regions of the same sheet");
        return Err(Error::input(file, "region", reason));
    }
    // Lines are looked up only for a message: a scan of the text each.
    for (i, m) in raw.material.iter().enumerate() {
        let f = |name: &str| format!("material[{i}].{name}");
        let check = || -> Result<()> {
            ranges::within(file, &f("youngs_modulus"), m.youngs_modulus, YOUNGS_MODULUS, "Pa")?;
            ranges::poisson_ratio(file, &f("poisson_ratio"), m.poisson_ratio)?;
            ranges::within(file, &f("density"), m.density, DENSITY, "kg/m³")
        };
        check().map_err(|e| with_line(e, header_line(text, "material", i)))?;
    }
    let grid = Grid::from_lines(raw.x, raw.y);
    let own = Sheet {
        thickness: p.thickness,
        youngs_modulus: p.youngs_modulus,
        poisson_ratio: p.poisson_ratio,
        density: p.density,
    };
    let mut sheets: Vec<Sheet> = Vec::new();
    let mut element_sheet = Vec::new();
    for (i, r) in raw.region.iter().enumerate() {
        let (sheet, boxed) =
            region(file, i, r, &raw.material, &grid, own).map_err(|e| with_line(e, header_line(text, "region", i)))?;
        // Index 0 is the plate's own sheet; a region's equal to it stays uniform.
        let k = match sheets.iter().position(|s| *s == sheet) {
            _ if sheet == own => 0,
            Some(k) => k + 1,
            None => {
                sheets.push(sheet);
                sheets.len()
            }
        };
        if element_sheet.is_empty() {
            element_sheet = vec![0u32; grid.nx() * grid.ny()];
        }
        for j in boxed[1].clone() {
            for e in boxed[0].clone() {
                element_sheet[e + j * grid.nx()] = k as u32;
            }
        }
    }
    Ok(PlateMesh { grid, sheets, element_sheet })
}

/// Checks one array of grid lines (`name`, m): at least two, finite, strictly increasing,
/// from 0 to the plate's `length` (to 1e-9 of it), no element far shorter than the rest.
fn grid_lines(file: &str, name: &str, v: &[f64], length: f64) -> Result<()> {
    if v.len() < 2 {
        return Err(Error::input(file, name, "a grid needs at least two lines along each side"));
    }
    if let Some(k) = v.iter().position(|t| !t.is_finite()) {
        return Err(Error::input(file, format!("{name}[{k}]"), format!("{}: grid lines must be finite", v[k])));
    }
    if v[0] != 0.0 {
        return Err(Error::input(file, format!("{name}[0]"), format!("the first line must be at 0, found {}", v[0])));
    }
    if let Some(k) = v.windows(2).position(|w| !(w[1] > w[0])) {
        return Err(Error::input(
            file,
            format!("{name}[{}]", k + 1),
            format!("grid lines must be strictly increasing ({} after {})", v[k + 1], v[k]),
        ));
    }
    let last = v[v.len() - 1];
    if (last - length).abs() > 1e-9 * length {
        return Err(Error::input(
            file,
            format!("{name}[{}]", v.len() - 1),
            format!(
                "the lines end at {name} = {last} m but plate.length_{name} is {length} m: the lines must span the \
                 plate"
            ),
        ));
    }
    ranges::mesh_lines(file, name, v)
}

/// Region `i`'s sheet (what it gives over the plate's own) and its elements along x and y.
fn region(
    file: &str,
    i: usize,
    r: &Region,
    materials: &[NamedMaterial],
    grid: &Grid,
    own: Sheet,
) -> Result<(Sheet, [std::ops::Range<usize>; 2])> {
    let f = |name: &str| format!("region[{i}].{name}");
    if r.thickness.is_none() && r.material.is_none() {
        return Err(Error::input(file, format!("region[{i}]"), "give `thickness` and/or `material`"));
    }
    let mut sheet = own;
    if let Some(h) = r.thickness {
        let (lx, ly) = grid.lengths();
        ranges::within(file, &f("thickness"), h, DIMENSION, "m")?;
        thin(file, &f("thickness"), h, lx, ly)?;
        sheet.thickness = h;
    }
    if let Some(name) = &r.material {
        let m = materials.iter().find(|m| &m.name == name).ok_or_else(|| {
            let known: Vec<&str> = materials.iter().map(|m| m.name.as_str()).collect();
            Error::input(file, f("material"), format!("no material named `{name}` (the file names {known:?})"))
        })?;
        (sheet.youngs_modulus, sheet.poisson_ratio, sheet.density) = (m.youngs_modulus, m.poisson_ratio, m.density);
    }
    let x = span(file, &f("x"), r.x, &grid.x)?;
    let y = span(file, &f("y"), r.y, &grid.y)?;
    Ok((sheet, [x, y]))
}

/// The elements between two grid lines `[a, b]` (m) of `lines`, refused (naming `field`)
/// unless both are lines and a < b.
fn span(file: &str, field: &str, [a, b]: [f64; 2], lines: &[f64]) -> Result<std::ops::Range<usize>> {
    let end = lines[lines.len() - 1];
    if !(a >= 0.0 && b <= end && a < b) {
        return Err(Error::input(
            file,
            field,
            format!("[{a}, {b}] m is outside the plate's [0, {end}] m or empty: give [from, to], from < to"),
        ));
    }
    let tol = 1e-9 * end;
    let line = |c: f64| {
        let k = lines.partition_point(|&t| t < c - tol);
        match lines.get(k) {
            Some(t) if (t - c).abs() <= tol => Ok(k),
            _ => {
                let near = lines.iter().min_by(|s, t| (*s - c).abs().total_cmp(&(*t - c).abs())).copied();
                Err(Error::input(
                    file,
                    field,
                    format!(
                        "{c} m is not a grid line (the nearest is {} m): a region's sides lie on grid lines",
                        near.unwrap_or(0.0)
                    ),
                ))
            }
        }
    };
    Ok(line(a)?..line(b)?)
}

/// The error with `line` (1-based) put in front of its reason.
fn with_line(e: Error, line: Option<usize>) -> Error {
    match (e, line) {
        (Error::Input { file, field, reason }, Some(l)) => {
            Error::Input { file, field, reason: format!("line {l}: {reason}") }
        }
        (e, _) => e,
    }
}

/// The line (1-based) of the top-level `key = …`.
fn key_line(text: &str, key: &str) -> Option<usize> {
    text.lines()
        .take_while(|l| !l.trim_start().starts_with('['))
        .position(|l| l.trim_start().strip_prefix(key).is_some_and(|r| r.trim_start().starts_with('=')))
        .map(|k| k + 1)
}

/// The line (1-based) of the `i`-th `[[table]]` header.
fn header_line(text: &str, table: &str, i: usize) -> Option<usize> {
    let header = format!("[[{table}]]");
    text.lines()
        .enumerate()
        .filter(|(_, l)| l.split('#').next().unwrap_or("").trim() == header)
        .nth(i)
        .map(|(k, _)| k + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plate() -> PlateSpec {
        let text = "length_x = 0.5\nlength_y = 0.4\nthickness = 0.003\nyoungs_modulus = 70e9\npoisson_ratio = 0.33\n\
                    density = 2700.0\n[edges]\nx0 = \"free\"\nx1 = \"free\"\ny0 = \"free\"\ny1 = \"free\"\n";
        toml::from_str(text).unwrap()
    }

    const LINES: &str = "format = \"beamflow-plate-mesh-1\"\nx = [0.0, 0.1, 0.25, 0.5]\ny = [0.0, 0.2, 0.4]\n";

    #[test]
    fn later_regions_override_earlier_ones_and_the_rest_is_the_plates() {
        let text = format!(
            "{LINES}[[material]]\nname = \"steel\"\nyoungs_modulus = 210e9\npoisson_ratio = 0.3\ndensity = 7850.0\n\
             [[region]]\nx = [0.0, 0.25]\ny = [0.0, 0.4]\nthickness = 0.004\n\
             [[region]]\nx = [0.1, 0.5]\ny = [0.2, 0.4]\nmaterial = \"steel\"\n"
        );
        let m = parse(&text, "m.toml", &plate()).unwrap();
        assert_eq!((m.grid.nx(), m.grid.ny()), (3, 2));
        let sheet = |i: usize, j: usize| match m.element_sheet[i + 3 * j] {
            0 => None,
            k => Some(m.sheets[k as usize - 1]),
        };
        assert_eq!(sheet(0, 0).unwrap().thickness, 0.004);
        assert_eq!(sheet(0, 0).unwrap().density, 2700.0);
        assert_eq!(sheet(2, 0), None);
        // The second region's material on the plate's own thickness, over the first's.
        let s = sheet(1, 1).unwrap();
        assert_eq!((s.thickness, s.density, s.poisson_ratio), (0.003, 7850.0, 0.3));
        assert_eq!(sheet(0, 1).unwrap().thickness, 0.004);
    }

    #[test]
    fn mistakes_are_named_by_field_and_line() {
        let bad = |tail: &str, lines: &str| {
            let text = format!("{lines}{tail}");
            parse(&text, "m.toml", &plate()).unwrap_err().to_string()
        };
        let e = bad("", &LINES.replace("0.1, 0.25", "0.25, 0.1"));
        assert!(e.contains("m.toml") && e.contains("`x[2]`") && e.contains("line 2"), "{e}");
        let e = bad("", &LINES.replace("0.4]", "0.3]"));
        assert!(e.contains("`y[2]`") && e.contains("plate.length_y is 0.4"), "{e}");
        let e = bad("[[region]]\nx = [0.13, 0.25]\ny = [0.0, 0.4]\nthickness = 0.004\n", LINES);
        assert!(e.contains("`region[0].x`") && e.contains("line 4") && e.contains("nearest is 0.1"), "{e}");
        let e = bad("[[region]]\nx = [0.1, 0.25]\ny = [0.0, 0.4]\nmaterial = \"oak\"\n", LINES);
        assert!(e.contains("`region[0].material`") && e.contains("no material named `oak`"), "{e}");
    }
}
