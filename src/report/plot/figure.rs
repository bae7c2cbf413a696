//! What the report layers hand figures over as: the [`Figure`] trait (render to a path, or
//! give the drawing itself), where figures go ([`Dest`]) and [`save`].

use super::{BarChart, LinePlot, MultiPanel};
use crate::error::Result;
use std::cell::RefCell;
use std::path::{Path, PathBuf};

/// Something that can be rendered to a path, and handed over as what it draws.
pub trait Figure {
    fn render_to(&self, path: &Path) -> Result<()>;
    fn drawing(&self) -> Drawing;
}

/// What a figure draws, owned: the Python package draws it again with matplotlib.
#[derive(Clone, Debug)]
pub enum Drawing {
    Lines(LinePlot),
    Panels(MultiPanel),
    Bars(BarChart),
    Map(super::HeatMap),
    Maps(super::MapGrid),
}

impl Figure for LinePlot {
    fn render_to(&self, path: &Path) -> Result<()> {
        self.render(path)
    }
    fn drawing(&self) -> Drawing {
        Drawing::Lines(self.clone())
    }
}
impl Figure for MultiPanel {
    fn render_to(&self, path: &Path) -> Result<()> {
        self.render(path)
    }
    fn drawing(&self) -> Drawing {
        Drawing::Panels(self.clone())
    }
}
impl Figure for BarChart {
    fn render_to(&self, path: &Path) -> Result<()> {
        self.render(path)
    }
    fn drawing(&self) -> Drawing {
        Drawing::Bars(self.clone())
    }
}

/// Named drawings kept instead of written.
pub type Drawings = RefCell<Vec<(String, Drawing)>>;

/// Where figures go: files in a folder, or drawings kept by name.
#[derive(Clone, Copy)]
pub enum Dest<'a> {
    Folder(&'a Path),
    Keep(&'a Drawings),
}

impl<'a> From<&'a Path> for Dest<'a> {
    fn from(dir: &'a Path) -> Self {
        Dest::Folder(dir)
    }
}

impl<'a> From<&'a PathBuf> for Dest<'a> {
    fn from(dir: &'a PathBuf) -> Self {
        Dest::Folder(dir)
    }
}
impl Figure for super::HeatMap {
    fn render_to(&self, path: &Path) -> Result<()> {
        self.render(path)
    }
    fn drawing(&self) -> Drawing {
        Drawing::Map(self.clone())
    }
}
impl Figure for super::MapGrid {
    fn render_to(&self, path: &Path) -> Result<()> {
        self.render(path)
    }
    fn drawing(&self) -> Drawing {
        Drawing::Maps(self.clone())
    }
}

/// Writes `dir/name.<ext>` in each figure format (PNG and SVG unless `--formats` says
/// otherwise) and returns the paths; or keeps the drawing as `name` (no paths).
pub fn save<'a>(fig: &dyn Figure, to: impl Into<Dest<'a>>, name: &str) -> Result<Vec<PathBuf>> {
    if !super::wanted(name.trim_start_matches('_')) {
        return Ok(Vec::new());
    }
    let dir = match to.into() {
        Dest::Folder(dir) => dir,
        Dest::Keep(kept) => {
            kept.borrow_mut().push((name.to_string(), fig.drawing()));
            return Ok(Vec::new());
        }
    };
    let mut out = Vec::new();
    for format in super::figure_formats() {
        let p = crate::io::paths::output_file(dir, &format!("{name}.{}", format.ext()))?;
        fig.render_to(&p)?;
        out.push(p);
    }
    Ok(out)
}
