//! Frame-type actuator: a rigid top beam (m_b, J_b) on two legs at x_c ∓ a, with the stack
//! at x_E = x_c + e between the top beam and the base.

use super::{Component, FootBase, Link, Stack};
use crate::structure::Location;
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
    /// Base of the feet: `Some(x_E)` on the structure (stack foot at x_E, legs at
    /// x_c ∓ a·d with x_c = x_E − e·d, spec §15); `None` on the rigid ground.
    pub at: Option<Location>,
    /// The frame's in-plane direction ψ (rad from +x), d = (cos ψ, sin ψ); 0 on a beam.
    pub direction: f64,
    /// Where the legs stand when given by themselves (an imported model's nodes), in place
    /// of the positions `at`, `e`, `a` and ψ imply.
    pub legs: Option<[Location; 2]>,
}

/// A frame's feet from its stack foot `at` (spec §15): the stack at x_c + e·d and the legs
/// at x_c ∓ a·d, with the top beam's centre x_c = x_E − e·d and d the in-plane direction ψ
/// (rad). Each is written from x_c so that a beam gets x_E − e + offset exactly.
pub fn feet(at: Location, e: f64, a: f64, psi: f64) -> [Location; 3] {
    let c = at.offset(-e, psi);
    [c.offset(e, psi), c.offset(-a, psi), c.offset(a, psi)]
}

impl Frame {
    /// Its links, in the order of its component: the stack, then the legs.
    pub const LINKS: [&'static str; 3] = ["stack", "left_leg", "right_leg"];

    /// DOFs (y, φ); the stack's half mass rides rigidly on the top beam at offset e, so it
    /// adds m_p/2·[1, e]ᵀ[1, e] to the body mass matrix.
    pub fn component(&self) -> Component {
        let s = &self.stack;
        let half = 0.5 * s.m_p;
        let e = self.e;
        let mass = DMatrix::from_row_slice(2, 2, &[self.m_b + half, half * e, half * e, self.j_b + half * e * e]);
        let feet = self.at.map(|at| match self.legs {
            Some([left, right]) => [at, left, right],
            None => feet(at, e, self.a, self.direction),
        });
        let foot = |i: usize| feet.map_or(FootBase::Ground, |f| FootBase::On(f[i]));
        Component {
            dof_names: vec!["y", "phi"],
            mass,
            links: vec![
                Link {
                    name: Frame::LINKS[0].into(),
                    k: s.k_p,
                    c: s.c_p,
                    top: vec![(0, 1.0), (1, e)],
                    foot: foot(0),
                    foot_mass: half,
                    active: true,
                },
                Link {
                    name: Frame::LINKS[1].into(),
                    k: self.left.k_l,
                    c: self.left.c_l,
                    top: vec![(0, 1.0), (1, -self.a)],
                    foot: foot(1),
                    foot_mass: 0.0,
                    active: false,
                },
                Link {
                    name: Frame::LINKS[2].into(),
                    k: self.right.k_l,
                    c: self.right.c_l,
                    top: vec![(0, 1.0), (1, self.a)],
                    foot: foot(2),
                    foot_mass: 0.0,
                    active: false,
                },
            ],
        }
    }
}
