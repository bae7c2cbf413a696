//! Steady harmonic response: (K − ω²M + iωC)·Q = F, convention q(t) = Re(Q·e^{iωt}).

use crate::error::Result;
use crate::linalg::{Csr, Skyline, SkylineLdlt};
use num_complex::Complex64;

/// The dynamic stiffness of a system, refactorised per frequency in fixed storage.
pub struct DynamicStiffness {
    k: Skyline<f64>,
    m: Skyline<f64>,
    c: Skyline<f64>,
    work: Skyline<Complex64>,
    factor: Option<SkylineLdlt<Complex64>>,
    omega: f64,
}

impl DynamicStiffness {
    pub fn new(k: &Csr, m: &Csr, c: &Csr, envelope: &[usize]) -> Self {
        let to_sky = |a: &Csr| {
            let mut s = Skyline::<f64>::zeros(envelope.to_vec());
            a.add_into_skyline(1.0, &mut s);
            s
        };
        DynamicStiffness {
            k: to_sky(k),
            m: to_sky(m),
            c: to_sky(c),
            work: Skyline::zeros(envelope.to_vec()),
            factor: None,
            omega: f64::NAN,
        }
    }

    pub fn dim(&self) -> usize {
        self.k.dim()
    }

    /// Factorises K − ω²M + iωC for circular frequency ω (rad/s).
    pub fn factorize(&mut self, omega: f64) -> Result<()> {
        self.work.set_combination(&[
            (Complex64::new(1.0, 0.0), &self.k),
            (Complex64::new(-omega * omega, 0.0), &self.m),
            (Complex64::new(0.0, omega), &self.c),
        ]);
        match &mut self.factor {
            Some(f) => f.refactor_from(&self.work)?,
            None => self.factor = Some(self.work.factorize()?),
        }
        self.omega = omega;
        Ok(())
    }

    /// Solves for the complex amplitudes Q at the last factorised frequency (in place).
    pub fn solve_in_place(&self, rhs: &mut [Complex64]) {
        self.factor.as_ref().expect("factorize before solve").solve_in_place(rhs);
    }

    pub fn omega(&self) -> f64 {
        self.omega
    }
}

/// Time-averaged power dissipated by a viscous matrix C in harmonic motion Q at ω:
/// ½·ω²·Qᴴ·C·Q (W).
pub fn dissipated_power(c: &Csr, q: &[Complex64], omega: f64) -> f64 {
    0.5 * omega * omega * c.hermitian_form(q)
}

/// Time-averaged power ½·Re(F·conj(V)) (W) of force and velocity amplitudes.
pub fn mean_power(f: Complex64, v: Complex64) -> f64 {
    0.5 * (f * v.conj()).re
}
