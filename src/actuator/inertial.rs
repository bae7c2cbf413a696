//! Inertial-type actuator: a top mass m_t on a stack whose foot stands on the base.

use super::{Component, FootBase, Link, Stack};
use nalgebra::DMatrix;

#[derive(Clone, Debug)]
pub struct Inertial {
    pub name: String,
    pub stack: Stack,
    /// Top mass m_t (kg).
    pub m_t: f64,
    /// Where the stack foot stands.
    pub foot: FootBase,
}

impl Inertial {
    /// Its one link: the stack.
    pub const LINKS: [&'static str; 1] = ["stack"];

    /// One DOF z_t carrying m_t + m_p/2; the stack joins z_t to the foot.
    pub fn component(&self) -> Component {
        let s = &self.stack;
        Component {
            dof_names: vec!["z_t"],
            mass: DMatrix::from_element(1, 1, self.m_t + 0.5 * s.m_p),
            links: vec![Link {
                name: Inertial::LINKS[0].into(),
                k: s.k_p,
                c: s.c_p,
                top: vec![(0, 1.0)],
                foot: self.foot,
                foot_mass: 0.5 * s.m_p,
                active: true,
            }],
        }
    }
}
