//! Cross-sections and materials.

/// A linear elastic material. Units: E in Pa, ρ in kg/m³.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    pub youngs_modulus: f64,
    pub density: f64,
}

/// A solid rectangular section, bending about the width axis. Units: m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Section {
    pub width: f64,
    pub thickness: f64,
}

impl Section {
    /// Area A = b·t (m²).
    pub fn area(&self) -> f64 {
        self.width * self.thickness
    }

    /// Second moment of area I = b·t³/12 (m⁴) for bending in the thickness direction.
    pub fn second_moment(&self) -> f64 {
        self.width * self.thickness.powi(3) / 12.0
    }

    /// Bending stiffness EI (N·m²) and mass per length ρA (kg/m) with a material.
    pub fn properties(&self, m: &Material) -> (f64, f64) {
        (m.youngs_modulus * self.second_moment(), m.density * self.area())
    }
}
