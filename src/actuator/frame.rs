//! Frame-type actuator: a rigid top beam (m_b, J_b) on two legs at x_c ∓ a, with the stack
//! at x_E = x_c + e between the top beam and the base.

use super::{Component, FootBase, Link, Stack};
use nalgebra::DMatrix;

/// A leg: spring k_l (N/m) and damper c_l (N·s/m) from the top beam to its foot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Leg {
    pub k_l: f64,
    pub c_l: f64,
}

#[derive(Clone, Debug)]
pub struct Frame {
    pub name: String,
    pub stack: Stack,
    /// Top beam mass m_b (kg) and moment of inertia about its centre J_b (kg·m²).
    pub m_b: f64,
    pub j_b: f64,
    /// Half distance between the legs a (m) and stack offset from the centre e (m).
    pub a: f64,
    pub e: f64,
    pub left: Leg,
    pub right: Leg,
    /// Base of the feet: `Some(x_E)` on the beam (stack foot at x_E, legs at x_E − e ∓ a);
    /// `None` on the rigid ground.
    pub x_e: Option<f64>,
}

impl Frame {
    /// Its links, in the order of its component: the stack, then the legs.
    pub const LINKS: [&'static str; 3] = ["stack", "left_leg", "right_leg"];

    /// Centre of the top beam x_c = x_E − e (m).
    pub fn x_c(&self) -> Option<f64> {
        self.x_e.map(|x| x - self.e)
    }

    /// DOFs (y, φ); the stack's half mass rides rigidly on the top beam at offset e, so it
    /// adds m_p/2·[1, e]ᵀ[1, e] to the body mass matrix.
    pub fn component(&self) -> Component {
        let s = &self.stack;
        let half = 0.5 * s.m_p;
        let e = self.e;
        let mass = DMatrix::from_row_slice(2, 2, &[self.m_b + half, half * e, half * e, self.j_b + half * e * e]);
        let foot = |offset: f64| match self.x_e {
            Some(x) => FootBase::Beam { x: x - e + offset },
            None => FootBase::Ground,
        };
        Component {
            dof_names: vec!["y", "phi"],
            mass,
            links: vec![
                Link {
                    name: Frame::LINKS[0].into(),
                    k: s.k_p,
                    c: s.c_p,
                    top: vec![(0, 1.0), (1, e)],
                    foot: foot(e),
                    foot_mass: half,
                    active: true,
                },
                Link {
                    name: Frame::LINKS[1].into(),
                    k: self.left.k_l,
                    c: self.left.c_l,
                    top: vec![(0, 1.0), (1, -self.a)],
                    foot: foot(-self.a),
                    foot_mass: 0.0,
                    active: false,
                },
                Link {
                    name: Frame::LINKS[2].into(),
                    k: self.right.k_l,
                    c: self.right.c_l,
                    top: vec![(0, 1.0), (1, self.a)],
                    foot: foot(self.a),
                    foot_mass: 0.0,
                    active: false,
                },
            ],
        }
    }
}
