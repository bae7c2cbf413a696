//! Modal parameters from a measured FRF, and the dynamic parameters k, c they give.
//!
//! Both fits work on the **receptance** α(ω) = H1(ω)/(iω)² (m/N), computed from the
//! accelerance of [`Frf`]; the DC bin is skipped.
//!
//! * [`fit_rfp`]: rational-fraction polynomial over a band,
//!   `α(s) ≈ N(s)/D(s)` with s = iω/ω_s (ω_s: the band's top), D monic of degree 2n
//!   (n modes), N of degree 2n (so a constant upper residual is allowed). The linearised
//!   least-squares problem `N(s_j) − α_j·D(s_j) = 0` (Levy) is re-weighted by 1/|D_prev(s_j)|
//!   and re-solved (Sanathanan–Koerner iterations, default 12), which removes Levy's bias
//!   towards high frequencies. The poles are the roots of D (Aberth–Ehrlich); those with
//!   Im p > 0, Re p < 0 and ω_n within the band (±10 %) are the modes, ω_n = |p|,
//!   ζ = −Re p/|p|. With the poles fixed, a second linear least squares gives the residues
//!   of `α(ω) = Σ_r [R_r/(iω − p_r) + R̄_r/(iω − p̄_r)] + UR − LR/ω²` (upper and lower
//!   residuals UR, LR real).
//! * [`fit_sdof`]: a single-mode fit near a peak: the highest |H1| (accelerance) in a search
//!   range, the half-power width Δf around it (|H1| falls below peak/√2), and the same fit with n = 1 over
//!   `f_peak ± half_bandwidths·Δf` (at least 6 bins each side).
//!
//! An exponential window (recorded in [`Frf::exp_decay`] = 1/τ) shifted every pole by
//! −1/τ; the fits add 1/τ back to the real part of each pole before reporting ω_n and ζ.
//! Residues are unchanged by the window.
//!
//! Finally `k = m·ω_n²`, `c = 2ζ·m·ω_n` for a known mass m ([`dynamic_parameters`]).

use num_complex::Complex64;

use crate::error::{Error, Result};
use crate::identify::frf::Frf;
use crate::identify::toml_float;

/// One identified mode.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Mode {
    /// Undamped natural frequency ω_n (rad/s).
    pub omega_n: f64,
    /// Damping ratio ζ.
    pub zeta: f64,
    /// Receptance residue R of the pole p (m/(N·s); serialised as `[re, im]`).
    #[serde(serialize_with = "crate::identify::complex_serde::one")]
    pub residue: Complex64,
}

impl Mode {
    /// Natural frequency in Hz.
    pub fn freq_hz(&self) -> f64 {
        self.omega_n / (2.0 * std::f64::consts::PI)
    }
    /// The pole p = −ζω_n + iω_n√(1−ζ²).
    pub fn pole(&self) -> Complex64 {
        Complex64::new(-self.zeta * self.omega_n, self.omega_n * (1.0 - self.zeta * self.zeta).max(0.0).sqrt())
    }
    /// Modal mass seen at the measured point (driving-point FRF): m_r = Re(1/(2i·ω_d·R)).
    /// For a single-DOF system on a measured mass it is that mass.
    pub fn modal_mass(&self) -> f64 {
        let wd = self.pole().im;
        (Complex64::new(1.0, 0.0) / (Complex64::new(0.0, 2.0 * wd) * self.residue)).re
    }
}

/// Result of a modal fit.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ModalFit {
    /// Modes in increasing ω_n.
    pub modes: Vec<Mode>,
    /// Upper residual UR (m/N).
    pub upper_residual: f64,
    /// Lower residual LR (m·s⁻²/N... in `−LR/ω²`, N⁻¹·s⁻²·m).
    pub lower_residual: f64,
    /// Band used, Hz.
    pub band: (f64, f64),
    /// Frequency bins used.
    pub points: usize,
    /// Normalised RMS misfit √(Σ|α − α̂|²/Σ|α|²) over the band (windowed data).
    pub fit_error: f64,
    /// Pole shift added back for an exponential window (1/s).
    pub exp_decay_removed: f64,
}

impl ModalFit {
    /// The fitted receptance of the (window-corrected) model at ω (rad/s).
    pub fn receptance(&self, omega: f64) -> Complex64 {
        self.receptance_at(Complex64::new(0.0, omega), omega)
    }

    /// The fitted accelerance at ω (rad/s), −ω²·receptance, with the exponential window's
    /// pole shift put back so that it compares with the (windowed) measured H1.
    pub fn windowed_accelerance(&self, omega: f64) -> Complex64 {
        -omega * omega * self.receptance_at(Complex64::new(self.exp_decay_removed, omega), omega)
    }

    /// The modal sum Σ R/(s − p) + R*/(s − p*) at s, with the residuals at ω.
    fn receptance_at(&self, s: Complex64, omega: f64) -> Complex64 {
        let mut h = Complex64::new(self.upper_residual - self.lower_residual / (omega * omega), 0.0);
        for m in &self.modes {
            let p = m.pole();
            h += m.residue / (s - p) + m.residue.conj() / (s - p.conj());
        }
        h
    }

    /// k and c of `element` from mode `index` with the known `mass`.
    pub fn dynamic_parameters(&self, element: IdentifiedElement, mass: f64, index: usize) -> Result<DynamicParameters> {
        let m = self.modes.get(index).ok_or_else(|| {
            Error::input("<modal fit>", "mode", format!("mode {index} requested but {} identified", self.modes.len()))
        })?;
        DynamicParameters::new(element, mass, m.omega_n, m.zeta)
    }
}

/// Settings of [`fit_rfp`].
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RfpOptions {
    /// Number of modes n in the band.
    pub modes: usize,
    /// Band (Hz), lower > 0.
    pub band: (f64, f64),
    /// Sanathanan–Koerner iterations (default 12).
    #[serde(default = "default_iterations")]
    pub iterations: usize,
    /// Bins with coherence below this are left out (default 0: none).
    #[serde(default)]
    pub min_coherence: f64,
}

fn default_iterations() -> usize {
    12
}

impl RfpOptions {
    /// n modes in `band` (Hz), default iterations, all bins used.
    pub fn new(modes: usize, band: (f64, f64)) -> Self {
        RfpOptions { modes, band, iterations: default_iterations(), min_coherence: 0.0 }
    }
}

/// Settings of [`fit_sdof`].
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SdofOptions {
    /// Range (Hz) in which the peak is searched (None: all bins above 0).
    pub search: Option<(f64, f64)>,
    /// Half-width of the fitted band in half-power widths (default 2).
    pub half_bandwidths: f64,
    /// Sanathanan–Koerner iterations (default 12).
    pub iterations: usize,
    /// Bins with coherence below this are left out (default 0: none).
    pub min_coherence: f64,
}

impl Default for SdofOptions {
    fn default() -> Self {
        SdofOptions { search: None, half_bandwidths: 2.0, iterations: default_iterations(), min_coherence: 0.0 }
    }
}

/// Single-mode fit around the highest receptance peak (see the module docs).
pub fn fit_sdof(frf: &Frf, opts: &SdofOptions) -> Result<ModalFit> {
    let nb = frf.freq.len();
    if nb < 8 {
        return Err(Error::argument("frf", "too few frequency bins for a modal fit"));
    }
    let (lo, hi) = opts.search.unwrap_or((0.0, f64::INFINITY));
    // Peak picking on the accelerance: the receptance's 1/ω² would lift low-frequency noise.
    let mag: Vec<f64> = frf.h1.iter().map(|h| h.norm()).collect();
    let mut kp = None;
    for k in 1..nb {
        if frf.freq[k] >= lo && frf.freq[k] <= hi && mag[k].is_finite() && kp.is_none_or(|p: usize| mag[k] > mag[p]) {
            kp = Some(k);
        }
    }
    let kp = kp.ok_or_else(|| Error::argument("search", "no frequency bin in the search range"))?;
    let half = mag[kp] / std::f64::consts::SQRT_2;
    let cross = |mut k: usize, step: isize| -> f64 {
        // Walk until |α| < peak/√2 and interpolate linearly between the two bins.
        loop {
            let next = k as isize + step;
            if next < 1 || next as usize >= nb {
                return frf.freq[k];
            }
            let n = next as usize;
            if mag[n] < half {
                let t = (mag[k] - half) / (mag[k] - mag[n]);
                return frf.freq[k] + t * (frf.freq[n] - frf.freq[k]);
            }
            k = n;
        }
    };
    let width = (cross(kp, 1) - cross(kp, -1)).max(frf.freq[1]);
    let df = frf.freq[1];
    let halfband = (opts.half_bandwidths * width).max(6.0 * df);
    let band = ((frf.freq[kp] - halfband).max(df), frf.freq[kp] + halfband);
    fit_rfp(frf, &RfpOptions { modes: 1, band, iterations: opts.iterations, min_coherence: opts.min_coherence })
}

/// Multi-mode rational-fraction polynomial fit over a band (see the module docs).
pub fn fit_rfp(frf: &Frf, opts: &RfpOptions) -> Result<ModalFit> {
    let (f_lo, f_hi) = opts.band;
    if !(f_lo > 0.0 && f_hi > f_lo && f_hi.is_finite()) {
        return Err(Error::argument("band", format!("need 0 < lower < upper, got ({f_lo}, {f_hi})")));
    }
    let mut omega = Vec::new();
    let mut alpha = Vec::new();
    for k in 1..frf.freq.len() {
        let f = frf.freq[k];
        if f >= f_lo && f <= f_hi && frf.coherence[k] >= opts.min_coherence {
            let a = frf.receptance(k);
            if a.re.is_finite() && a.im.is_finite() {
                omega.push(2.0 * std::f64::consts::PI * f);
                alpha.push(a);
            }
        }
    }
    let mut fit = fit_receptance(&omega, &alpha, opts.modes, opts.iterations, frf.exp_decay)?;
    fit.band = opts.band;
    Ok(fit)
}

/// The RFP core on raw data: receptance samples `alpha` at `omega` (rad/s), `modes` modes,
/// `iterations` Sanathanan–Koerner passes, `exp_decay` the window's pole shift to remove.
pub fn fit_receptance(
    omega: &[f64],
    alpha: &[Complex64],
    modes: usize,
    iterations: usize,
    exp_decay: f64,
) -> Result<ModalFit> {
    if modes == 0 {
        return Err(Error::argument("modes", "at least one mode must be fitted"));
    }
    let nd = 2 * modes; // denominator degree
    let nn = 2 * modes; // numerator degree
    let unknowns = nn + 1 + nd;
    if omega.len() != alpha.len() || 2 * omega.len() < unknowns + 4 {
        return Err(Error::argument(
            "band",
            format!("{} usable bins are too few to fit {modes} mode(s); widen the band", omega.len()),
        ));
    }
    let ws = omega.iter().fold(0.0f64, |m, w| m.max(w.abs()));
    let s: Vec<Complex64> = omega.iter().map(|w| Complex64::new(0.0, w / ws)).collect();
    let mut weight = vec![1.0; omega.len()];
    let mut den = vec![0.0; nd + 1];
    for _ in 0..iterations.max(1) {
        let mut cols: Vec<Vec<f64>> = vec![Vec::with_capacity(2 * omega.len()); unknowns];
        let mut rhs = Vec::with_capacity(2 * omega.len());
        for j in 0..omega.len() {
            let w = weight[j];
            let mut pw = Complex64::new(1.0, 0.0);
            let mut pows = Vec::with_capacity(nd + 1);
            for _ in 0..=nd.max(nn) {
                pows.push(pw);
                pw *= s[j];
            }
            for re_im in 0..2 {
                let pick = |z: Complex64| if re_im == 0 { z.re } else { z.im };
                for (k, col) in cols.iter_mut().enumerate().take(nn + 1) {
                    col.push(pick(pows[k] * w));
                }
                for k in 0..nd {
                    cols[nn + 1 + k].push(pick(-alpha[j] * pows[k] * w));
                }
                rhs.push(pick(alpha[j] * pows[nd] * w));
            }
        }
        let x = lstsq(cols, rhs).ok_or_else(|| Error::Numerical("modal fit: rank-deficient RFP system".into()))?;
        den[..nd].copy_from_slice(&x[nn + 1..]);
        den[nd] = 1.0;
        for j in 0..omega.len() {
            let d = polyval(&den, s[j]).norm();
            weight[j] = if d > 0.0 { 1.0 / d } else { 1.0 };
        }
    }
    let roots = poly_roots(&den);
    let (wlo, whi) = (omega.iter().cloned().fold(f64::INFINITY, f64::min), ws);
    let mut poles: Vec<Complex64> = roots
        .into_iter()
        .map(|r| r * ws)
        .filter(|p| p.im > 0.0 && p.re < 0.0 && p.norm() >= 0.9 * wlo && p.norm() <= 1.1 * whi)
        .collect();
    poles.sort_by(|a, b| a.norm().total_cmp(&b.norm()));
    if poles.is_empty() {
        return Err(Error::Numerical("modal fit: no stable complex pole in the band".into()));
    }
    // Residues with the (windowed) poles fixed.
    let np = poles.len();
    let mut cols: Vec<Vec<f64>> = vec![Vec::with_capacity(2 * omega.len()); 2 * np + 2];
    let mut rhs = Vec::with_capacity(2 * omega.len());
    let basis = |w: f64| -> Vec<Complex64> {
        let sj = Complex64::new(0.0, w);
        let mut b = Vec::with_capacity(2 * np + 2);
        for p in &poles {
            let (u, v) = (1.0 / (sj - p), 1.0 / (sj - p.conj()));
            b.push(u + v);
            b.push(Complex64::new(0.0, 1.0) * (u - v));
        }
        b.push(Complex64::new(1.0, 0.0));
        b.push(Complex64::new(-1.0 / (w * w), 0.0));
        b
    };
    for j in 0..omega.len() {
        let b = basis(omega[j]);
        for re_im in 0..2 {
            let pick = |z: Complex64| if re_im == 0 { z.re } else { z.im };
            for (c, bc) in cols.iter_mut().zip(&b) {
                c.push(pick(*bc));
            }
            rhs.push(pick(alpha[j]));
        }
    }
    let x = lstsq(cols, rhs).ok_or_else(|| Error::Numerical("modal fit: rank-deficient residue system".into()))?;
    let mut num = 0.0;
    let mut dnm = 0.0;
    for j in 0..omega.len() {
        let b = basis(omega[j]);
        let fit: Complex64 = b.iter().zip(&x).map(|(bc, xc)| bc * xc).sum();
        num += (alpha[j] - fit).norm_sqr();
        dnm += alpha[j].norm_sqr();
    }
    let modes: Vec<Mode> = poles
        .iter()
        .enumerate()
        .map(|(r, p)| {
            let pc = p + exp_decay;
            let wn = pc.norm();
            Mode { omega_n: wn, zeta: -pc.re / wn, residue: Complex64::new(x[2 * r], x[2 * r + 1]) }
        })
        .collect();
    Ok(ModalFit {
        modes,
        upper_residual: x[2 * np],
        lower_residual: x[2 * np + 1],
        band: (wlo / (2.0 * std::f64::consts::PI), whi / (2.0 * std::f64::consts::PI)),
        points: omega.len(),
        fit_error: (num / dnm).sqrt(),
        exp_decay_removed: exp_decay,
    })
}

/// `k = m·ω_n²` and `c = 2ζ·m·ω_n`.
pub fn dynamic_parameters(mass: f64, omega_n: f64, zeta: f64) -> (f64, f64) {
    (mass * omega_n * omega_n, 2.0 * zeta * mass * omega_n)
}

/// Which element the impact test identified: it decides the case-file fields.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum IdentifiedElement {
    /// The stack (`k_p`, `c_p` in `[actuator.stack]`).
    Stack,
    /// A frame leg, or both when they are alike (`k_l`, `c_l`: fields of the frame's
    /// `[[actuator]]` table itself).
    Leg,
    /// The right leg where the legs differ (`k_l_right`, `c_l_right`, fields of the frame's
    /// `[[actuator]]` table).
    LegRight,
}

/// k and c from a mode and a known mass.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct DynamicParameters {
    pub element: IdentifiedElement,
    /// Known moving mass (kg).
    pub mass: f64,
    pub omega_n: f64,
    pub zeta: f64,
    /// Stiffness k = m·ω_n² (N/m).
    pub k: f64,
    /// Damping c = 2ζ·m·ω_n (N·s/m).
    pub c: f64,
}

impl DynamicParameters {
    /// Checks m > 0, ω_n > 0, 0 < ζ < 1 and derives k, c.
    pub fn new(element: IdentifiedElement, mass: f64, omega_n: f64, zeta: f64) -> Result<Self> {
        if !(mass > 0.0 && mass.is_finite()) {
            return Err(Error::argument("mass", format!("must be positive, got {mass}")));
        }
        if !(omega_n > 0.0 && omega_n.is_finite()) {
            return Err(Error::argument("omega_n", format!("must be positive, got {omega_n}")));
        }
        if !(zeta > 0.0 && zeta < 1.0) {
            return Err(Error::argument(
                "zeta",
                format!("identified damping ratio {zeta} is outside (0, 1): not an underdamped mode"),
            ));
        }
        let (k, c) = dynamic_parameters(mass, omega_n, zeta);
        Ok(DynamicParameters { element, mass, omega_n, zeta, k, c })
    }

    /// Case-file fragment. The stack: a `[actuator.stack]` table with `k_p`, `c_p`, to paste
    /// below the actuator's `[[actuator]]` header (or whose keys go into its existing
    /// `[actuator.stack]`). A leg: the bare keys `k_l`, `c_l` (or `k_l_right`, `c_l_right`),
    /// fields of the frame's `[[actuator]]` table itself, to paste right below its
    /// `[[actuator]]` header, above its sub-tables.
    pub fn to_case_fragment(&self) -> String {
        let head = format!(
            "# impact test: f_n = {} Hz, zeta = {}, mass = {} kg\n",
            toml_float(self.omega_n / (2.0 * std::f64::consts::PI)),
            toml_float(self.zeta),
            toml_float(self.mass),
        );
        let (k, c) = (toml_float(self.k), toml_float(self.c));
        match self.element {
            IdentifiedElement::Stack => format!("{head}[{}]\nk_p = {k}\nc_p = {c}\n", crate::identify::STACK_TABLE),
            IdentifiedElement::Leg | IdentifiedElement::LegRight => {
                let (kf, cf) =
                    if self.element == IdentifiedElement::Leg { ("k_l", "c_l") } else { ("k_l_right", "c_l_right") };
                format!(
                    "{head}# fields of the frame's [[actuator]] table: paste right below its [[actuator]] line,\n\
                     # above its [actuator.stack] and [actuator.voltage] sub-tables\n{kf} = {k}\n{cf} = {c}\n"
                )
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// Numerical kernels
// ---------------------------------------------------------------------------------------

/// Horner evaluation of Σ c_k z^k (ascending coefficients).
pub(crate) fn polyval(c: &[f64], z: Complex64) -> Complex64 {
    c.iter().rev().fold(Complex64::new(0.0, 0.0), |acc, &ck| acc * z + ck)
}

/// All roots of the real polynomial Σ c_k z^k (ascending, leading coefficient non-zero),
/// by Aberth–Ehrlich simultaneous iteration followed by Newton polishing.
pub(crate) fn poly_roots(c: &[f64]) -> Vec<Complex64> {
    let n = c.len() - 1;
    if n == 0 {
        return Vec::new();
    }
    let lead = c[n];
    let a: Vec<f64> = c.iter().map(|v| v / lead).collect();
    let da: Vec<f64> = (1..=n).map(|k| k as f64 * a[k]).collect();
    // Cauchy-style radius for the starting circle.
    let r = (0..n).map(|k| a[k].abs().powf(1.0 / (n - k) as f64)).fold(0.0f64, f64::max).max(1e-12);
    let mut z: Vec<Complex64> =
        (0..n).map(|k| Complex64::from_polar(r, 2.0 * std::f64::consts::PI * k as f64 / n as f64 + 0.4)).collect();
    for _ in 0..500 {
        let mut max_step = 0.0f64;
        for k in 0..n {
            let p = polyval(&a, z[k]);
            let dp = polyval(&da, z[k]);
            if p.norm() == 0.0 {
                continue;
            }
            let ratio = p / dp;
            let sum: Complex64 = (0..n).filter(|&j| j != k).map(|j| 1.0 / (z[k] - z[j])).sum();
            let step = ratio / (1.0 - ratio * sum);
            if step.re.is_finite() && step.im.is_finite() {
                z[k] -= step;
                max_step = max_step.max(step.norm() / z[k].norm().max(1e-300));
            }
        }
        if max_step < 1e-15 {
            break;
        }
    }
    for zk in z.iter_mut() {
        for _ in 0..3 {
            let dp = polyval(&da, *zk);
            if dp.norm() > 0.0 {
                let step = polyval(&a, *zk) / dp;
                if step.re.is_finite() && step.im.is_finite() {
                    *zk -= step;
                }
            }
        }
    }
    z
}

/// Least squares min‖A·x − b‖ with A given by columns, by Householder QR after scaling
/// every column to unit norm. None when A is (numerically) rank deficient.
pub(crate) fn lstsq(mut cols: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let n = cols.len();
    let m = b.len();
    if n == 0 || m < n || cols.iter().any(|c| c.len() != m) {
        return None;
    }
    let mut scale = vec![1.0; n];
    for (c, s) in cols.iter_mut().zip(scale.iter_mut()) {
        let norm = c.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm == 0.0 || !norm.is_finite() {
            return None;
        }
        *s = norm;
        c.iter_mut().for_each(|v| *v /= norm);
    }
    let mut diag = vec![0.0; n];
    for k in 0..n {
        let norm = cols[k][k..].iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm < 1e-13 {
            return None;
        }
        let alpha = if cols[k][k] > 0.0 { -norm } else { norm };
        let mut v: Vec<f64> = cols[k][k..].to_vec();
        v[0] -= alpha;
        let vnorm2: f64 = v.iter().map(|x| x * x).sum();
        diag[k] = alpha;
        if vnorm2 > 0.0 {
            for col in cols.iter_mut().skip(k + 1) {
                let d: f64 = v.iter().zip(&col[k..]).map(|(a, b)| a * b).sum::<f64>() * 2.0 / vnorm2;
                for (ci, vi) in col[k..].iter_mut().zip(&v) {
                    *ci -= d * vi;
                }
            }
            let d: f64 = v.iter().zip(&b[k..]).map(|(a, b)| a * b).sum::<f64>() * 2.0 / vnorm2;
            for (bi, vi) in b[k..].iter_mut().zip(&v) {
                *bi -= d * vi;
            }
        }
    }
    let mut x = vec![0.0; n];
    for k in (0..n).rev() {
        let mut s = b[k];
        for j in k + 1..n {
            s -= cols[j][k] * x[j];
        }
        x[k] = s / diag[k];
    }
    Some(x.iter().zip(&scale).map(|(v, s)| v / s).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::identify::frf::tests::{add_noise, sdof_impact};
    use crate::identify::frf::{add_hammer_pulse, h1, impact_response, FrfOptions};
    use crate::identify::pso::Rng;
    use std::f64::consts::PI;

    #[test]
    fn lstsq_and_roots_kernels() {
        // Overdetermined consistent system.
        let cols = vec![vec![1.0, 1.0, 1.0, 1.0], vec![0.0, 1.0, 2.0, 3.0]];
        let b = vec![1.0, 3.0, 5.0, 7.0];
        let x = lstsq(cols, b).unwrap();
        assert!((x[0] - 1.0).abs() < 1e-12 && (x[1] - 2.0).abs() < 1e-12);
        assert!(lstsq(vec![vec![1.0, 2.0], vec![2.0, 4.0]], vec![1.0, 1.0]).is_none());
        // (z² + 2z + 5)(z − 3) = z³ − z² − z − 15: roots −1 ± 2i, 3.
        let mut r = poly_roots(&[-15.0, -1.0, -1.0, 1.0]);
        r.sort_by(|a, b| a.im.total_cmp(&b.im));
        assert!((r[0] - Complex64::new(-1.0, -2.0)).norm() < 1e-12);
        assert!((r[1] - Complex64::new(3.0, 0.0)).norm() < 1e-12);
        assert!((r[2] - Complex64::new(-1.0, 2.0)).norm() < 1e-12);
    }

    #[test]
    fn rfp_recovers_exact_two_mode_receptance() {
        let modes = [
            (2.0 * PI * 100.0, 0.02, Complex64::new(0.0, -1e-4)),
            (2.0 * PI * 260.0, 0.01, Complex64::new(1e-6, -5e-5)),
        ];
        let omega: Vec<f64> = (40..400).map(|f| 2.0 * PI * f as f64).collect();
        let alpha: Vec<Complex64> = omega
            .iter()
            .map(|&w| {
                let s = Complex64::new(0.0, w);
                modes
                    .iter()
                    .map(|&(wn, z, r)| {
                        let p = Complex64::new(-z * wn, wn * (1.0f64 - z * z).sqrt());
                        r / (s - p) + r.conj() / (s - p.conj())
                    })
                    .sum::<Complex64>()
                    + 1e-9
            })
            .collect();
        let fit = fit_receptance(&omega, &alpha, 2, 8, 0.0).unwrap();
        assert_eq!(fit.modes.len(), 2);
        for (m, &(wn, z, r)) in fit.modes.iter().zip(&modes) {
            assert!((m.omega_n / wn - 1.0).abs() < 1e-8, "{} {}", m.omega_n, wn);
            assert!((m.zeta / z - 1.0).abs() < 1e-6);
            assert!((m.residue - r).norm() / r.norm() < 1e-6);
        }
        assert!((fit.upper_residual - 1e-9).abs() < 1e-13);
        assert!(fit.fit_error < 1e-8);
    }

    #[test]
    fn stack_on_mass_impact_test_round_trip() {
        // m = 0.33 kg, k = 3e7 N/m, c = 200 N·s/m; 8 hits, 1 % noise on force and acceleration.
        let (m, k, c): (f64, f64, f64) = (0.33, 3.0e7, 200.0);
        let dt = 1.0 / 25600.0;
        let (f, a) = sdof_impact(8, 4096, dt, 2024);
        let frf = h1("<synthetic>", &f, &a, dt, &FrfOptions::hits(4096)).unwrap();
        let fit = fit_sdof(&frf, &SdofOptions::default()).unwrap();
        assert_eq!(fit.modes.len(), 1);
        let mode = &fit.modes[0];
        let wn = (k / m).sqrt();
        let zeta = c / (2.0 * (k * m).sqrt());
        let ew = (mode.omega_n / wn - 1.0).abs();
        let ez = (mode.zeta / zeta - 1.0).abs();
        eprintln!("SDOF impact: omega_n error {ew:.2e}, zeta error {ez:.2e}, modal mass {}", mode.modal_mass());
        assert!(ew < 0.005, "omega_n {} vs {wn}", mode.omega_n);
        assert!(ez < 0.05, "zeta {} vs {zeta}", mode.zeta);
        assert!((mode.modal_mass() / m - 1.0).abs() < 0.05, "{}", mode.modal_mass());
        let dp = fit.dynamic_parameters(IdentifiedElement::Stack, m, 0).unwrap();
        assert!((dp.k / k - 1.0).abs() < 0.01, "k {}", dp.k);
        assert!((dp.c / c - 1.0).abs() < 0.06, "c {}", dp.c);
        eprintln!("k error {:.2e}, c error {:.2e}", dp.k / k - 1.0, dp.c / c - 1.0);
        let frag = dp.to_case_fragment();
        let t: toml::Table = toml::from_str(&frag).unwrap();
        let st = t["actuator"]["stack"].as_table().unwrap();
        assert!((st["k_p"].as_float().unwrap() / dp.k - 1.0).abs() < 1e-5);
        assert!((st["c_p"].as_float().unwrap() / dp.c - 1.0).abs() < 1e-5);
    }

    #[test]
    fn exponential_window_is_corrected() {
        // A short segment that cuts the decay: the window makes it usable and the fit
        // removes its damping again.
        let (m, k, c): (f64, f64, f64) = (0.33, 3.0e7, 50.0);
        let dt = 1.0 / 25600.0;
        let n = 1024;
        let mut f = vec![0.0; 4 * n];
        for h in 0..4 {
            add_hammer_pulse(&mut f, dt, (h * n + 30) as f64 * dt, 2e-4, 100.0);
        }
        let a = impact_response(&[vec![m]], &[vec![c]], &[vec![k]], 0, 0, &f, dt).unwrap();
        let opts = FrfOptions { exponential_window_end: Some(0.02), ..FrfOptions::hits(n) };
        let frf = h1("<synthetic>", &f, &a, dt, &opts).unwrap();
        assert!(frf.exp_decay > 0.0);
        let fit = fit_sdof(&frf, &SdofOptions::default()).unwrap();
        let zeta = c / (2.0 * (k * m).sqrt());
        let mode = &fit.modes[0];
        assert!((mode.omega_n / (k / m).sqrt() - 1.0).abs() < 0.005);
        assert!((mode.zeta / zeta - 1.0).abs() < 0.05, "{} vs {zeta}", mode.zeta);
    }

    #[test]
    fn two_dof_impact_test_recovers_both_modes() {
        // Chain: ground –k1– m1 –k2– m2, proportional damping C = a0·M + a1·K; hammer and
        // accelerometer on m2 (driving point). 6 hits, 1 % noise.
        let (m1, m2, k1, k2) = (1.0, 0.5, 4.0e5, 2.0e5);
        let mm = vec![vec![m1, 0.0], vec![0.0, m2]];
        let kk = vec![vec![k1 + k2, -k2], vec![-k2, k2]];
        let (a0, a1) = (8.0, 2.0e-5);
        let cc: Vec<Vec<f64>> = (0..2).map(|i| (0..2).map(|j| a0 * mm[i][j] + a1 * kk[i][j]).collect()).collect();
        // Exact modes: det(K − ω²M) = 0.
        let (a, b, cq) = (m1 * m2, -((k1 + k2) * m2 + k2 * m1), k1 * k2);
        let disc = (b * b - 4.0 * a * cq).sqrt();
        let w2 = [(-b - disc) / (2.0 * a), (-b + disc) / (2.0 * a)];
        let dt = 1.0 / 1024.0;
        let n = 2048;
        let hits = 6;
        let mut f = vec![0.0; hits * n];
        let mut rng = Rng::new(77);
        for h in 0..hits {
            add_hammer_pulse(&mut f, dt, (h * n + 40) as f64 * dt + rng.uniform() * dt, 2e-3, 50.0);
        }
        let mut acc = impact_response(&mm, &cc, &kk, 1, 1, &f, dt).unwrap();
        add_noise(&mut f, 0.01, &mut rng);
        add_noise(&mut acc, 0.01, &mut rng);
        let frf = h1("<synthetic>", &f, &acc, dt, &FrfOptions::hits(n)).unwrap();
        let fit = fit_rfp(&frf, &RfpOptions::new(2, (30.0, 300.0))).unwrap();
        assert_eq!(fit.modes.len(), 2, "{:?}", fit.modes);
        for (r, mode) in fit.modes.iter().enumerate() {
            let wn = w2[r].sqrt();
            let zeta = a0 / (2.0 * wn) + a1 * wn / 2.0;
            let ew = (mode.omega_n / wn - 1.0).abs();
            let ez = (mode.zeta / zeta - 1.0).abs();
            eprintln!("2-DOF mode {r}: f = {:.2} Hz, omega_n error {ew:.2e}, zeta error {ez:.2e}", wn / (2.0 * PI));
            assert!(ew < 0.005, "mode {r}: {} vs {wn}", mode.omega_n);
            assert!(ez < 0.05, "mode {r}: {} vs {zeta}", mode.zeta);
        }
        assert!(fit.fit_error < 0.1, "{}", fit.fit_error);
    }

    #[test]
    fn dynamic_parameters_and_fragments() {
        let (k, c) = dynamic_parameters(2.0, 10.0, 0.05);
        assert_eq!((k, c), (200.0, 2.0));
        let leg = DynamicParameters::new(IdentifiedElement::Leg, 0.2, 2.0 * PI * 13783.0, 0.01).unwrap();
        let t: toml::Table = toml::from_str(&leg.to_case_fragment()).unwrap();
        assert!(t["k_l"].as_float().is_some() && t["c_l"].as_float().is_some());
        let right = DynamicParameters { element: IdentifiedElement::LegRight, ..leg };
        let t: toml::Table = toml::from_str(&right.to_case_fragment()).unwrap();
        assert!(t.contains_key("k_l_right") && t.contains_key("c_l_right"));
        let e = DynamicParameters::new(IdentifiedElement::Leg, 0.2, 100.0, -0.01).unwrap_err().to_string();
        assert!(e.contains("zeta"), "{e}");
        let e = DynamicParameters::new(IdentifiedElement::Stack, 0.0, 100.0, 0.01).unwrap_err().to_string();
        assert!(e.contains("mass"), "{e}");
    }
}
