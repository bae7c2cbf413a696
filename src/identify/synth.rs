//! Synthetic measurements made by the simulator itself (`beamflow synth`), for round trips
//! and demos.
//!
//! The records come from the models of a case's actuator (physics spec §4–§6):
//!
//! | kind | model | columns |
//! |---|---|---|
//! | [`SynthKind::Stroke`] | the stack's Bouc–Wen periodic state under the actuator's voltage ([`BoucWen::periodic_cycle`]), `periods` periods of `samples_per_period` samples | time, voltage, displacement (free stroke δ) |
//! | [`SynthKind::BlockedForce`] | the same, force = k_p·δ | time, voltage, force |
//! | [`SynthKind::DpPair`] | two stroke records, the second with the voltage offset by ΔV and starting `lag` samples later in the cycle | two files of time, voltage, displacement |
//! | [`SynthKind::Impact`] | an impact test of a single-DOF system (stack on a mass, or one frame leg on a mass): `hits` half-sine hammer pulses, exact sampled response ([`frf::impact_response`]) | time, force, acceleration |
//!
//! **Impact tests.** [`ImpactElement::Stack`]: the stack (k_p, c_p) carrying the moving mass
//! of the inertial actuator `m_t + m_p/2` (a frame's stack: `m_b + m_p/2`, the top beam on
//! the stack alone). [`ImpactElement::Leg`] / [`ImpactElement::LegRight`]: one frame leg
//! (k_l, c_l) carrying half the top beam, `m_b/2`. `mass` overrides either. The sampling rate
//! is 16·f_n rounded up to two significant digits; each hit gets a segment of at least 30
//! decay time constants 1/(ζω_n) (at least 1024 samples, a multiple of 256); the hammer pulse
//! lasts 0.3/f_n (its spectrum's first zero is at 5·f_n) with a peak of 100–120 N.
//!
//! **Noise.** Gaussian, seeded ([`Rng`]), with standard deviation `noise` × the RMS of each
//! measured response column (displacement, force, acceleration — the hammer force too) and
//! `voltage_noise` × the RMS of the voltage column. The voltage is by default clean: it stands
//! for the commanded voltage (noise on a measured voltage adds spurious minor loops, see
//! `docs/identification.md`).
//!
//! The true parameters are returned in [`Truth`] and written as comment lines at the top of
//! the CSV file.

use crate::actuator::bouc_wen::BoucWen;
use crate::actuator::Actuator;
use crate::case::LoadedCase;
use crate::error::{Error, Result};
use crate::identify::frf;
use crate::identify::modal_fit::IdentifiedElement;
use crate::identify::pso::Rng;
use crate::identify::toml_float;
use crate::io::measurement::{Measurement, Quantity};
use crate::signal::voltage::VoltageInput;

/// What to synthesise.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SynthKind {
    /// Free stroke cycle: time, voltage, displacement.
    Stroke,
    /// Blocked force k_p·stroke: time, voltage, force.
    BlockedForce,
    /// Impact test: time, force, acceleration.
    Impact,
    /// Two stroke records whose voltages differ by a constant offset (for `identify dp`).
    DpPair,
}

/// The element an impact test excites (it is also the element `identify modal` names).
pub type ImpactElement = IdentifiedElement;

/// Settings of [`synthesize`].
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SynthOptions {
    pub kind: SynthKind,
    /// Actuator name (as in the results file: the `name` field, else `inertial`, `frame`,
    /// `inertial_0`, ...); None: the case's first actuator.
    pub actuator: Option<String>,
    /// Noise standard deviation as a fraction of each response column's RMS (default 0.01).
    pub noise: f64,
    /// Noise on the voltage column as a fraction of its RMS (default 0: commanded voltage).
    pub voltage_noise: f64,
    /// Seed of the noise (and hammer jitter) stream (default 1).
    pub seed: u64,
    /// Periods per stroke record (default 3).
    pub periods: usize,
    /// Samples per period of a stroke record (default 200).
    pub samples_per_period: usize,
    /// Voltage offset ΔV of the second record of a d_p pair (V); None: a quarter of the
    /// voltage's half range (12 V for a 48 V sine).
    pub offset: Option<f64>,
    /// Samples by which the second record of a pair starts later in the cycle (default 37).
    pub lag: usize,
    /// Impact test: which element (default the stack).
    pub element: ImpactElement,
    /// Impact test: the moving mass (kg); None: see the module docs.
    pub mass: Option<f64>,
    /// Impact test: number of hammer hits (default 8).
    pub hits: usize,
    /// What the records may take (`--max-memory`, `--max-steps`).
    #[serde(skip)]
    pub budget: crate::analysis::budget::Budget,
}

impl Default for SynthOptions {
    fn default() -> Self {
        SynthOptions {
            kind: SynthKind::Stroke,
            actuator: None,
            noise: 0.01,
            voltage_noise: 0.0,
            seed: 1,
            periods: 3,
            samples_per_period: 200,
            offset: None,
            lag: 37,
            element: IdentifiedElement::Stack,
            mass: None,
            hits: 8,
            budget: Default::default(),
        }
    }
}

/// The parameters the synthetic records were made with.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Truth {
    /// Case file and actuator.
    pub case: String,
    pub actuator: String,
    pub kind: String,
    /// Stack hysteresis (stroke, blocked force, d_p pair).
    pub bouc_wen: Option<BoucWen>,
    /// k_p (blocked force).
    pub k_p: Option<f64>,
    /// Voltage period (s) and offset ΔV of a pair (V).
    pub period: Option<f64>,
    pub delta_v: Option<f64>,
    /// Impact test: element, mass (kg), k (N/m), c (N·s/m), f_n (Hz), ζ.
    pub element: Option<IdentifiedElement>,
    pub mass: Option<f64>,
    pub k: Option<f64>,
    pub c: Option<f64>,
    pub f_n: Option<f64>,
    pub zeta: Option<f64>,
    /// Noise levels.
    pub noise: f64,
    pub voltage_noise: f64,
    pub seed: u64,
}

impl Truth {
    /// `# `-comment lines describing the truth (written at the top of the CSV files).
    pub fn comments(&self) -> Vec<String> {
        let mut c = vec![format!(
            "beamflow synth: {} of actuator `{}` from {}; noise {} x RMS on the responses, {} x RMS on the voltage, seed {}",
            self.kind,
            self.actuator,
            self.case,
            toml_float(self.noise),
            toml_float(self.voltage_noise),
            self.seed
        )];
        if let Some(b) = &self.bouc_wen {
            c.push(format!(
                "true stack: d_p = {} m/V, alpha = {}, beta = {} 1/V, gamma = {} 1/V",
                toml_float(b.d_p),
                toml_float(b.alpha),
                toml_float(b.beta),
                toml_float(b.gamma)
            ));
        }
        if let Some(k) = self.k_p {
            c.push(format!("true k_p = {} N/m (force = k_p x stroke)", toml_float(k)));
        }
        if let Some(p) = self.period {
            c.push(format!("voltage period {} s", toml_float(p)));
        }
        if let Some(dv) = self.delta_v {
            c.push(format!("second record: voltage offset by {} V", toml_float(dv)));
        }
        if let (Some(e), Some(m), Some(k), Some(cc), Some(f), Some(z)) =
            (self.element, self.mass, self.k, self.c, self.f_n, self.zeta)
        {
            c.push(format!(
                "impact test of the {}: mass {} kg, k = {} N/m, c = {} N s/m, f_n = {} Hz, zeta = {}",
                element_name(e),
                toml_float(m),
                toml_float(k),
                toml_float(cc),
                toml_float(f),
                toml_float(z)
            ));
        }
        c
    }
}

/// Human name of an element.
pub fn element_name(e: IdentifiedElement) -> &'static str {
    match e {
        IdentifiedElement::Stack => "stack",
        IdentifiedElement::Leg => "frame leg (left)",
        IdentifiedElement::LegRight => "frame leg (right)",
    }
}

/// Synthetic records (one, or two for a d_p pair) and the truth they were made with.
#[derive(Clone, Debug)]
pub struct Synthetic {
    pub records: Vec<Measurement>,
    pub truth: Truth,
}

/// Adds Gaussian noise with standard deviation `level` × RMS of `x`.
pub fn add_noise(x: &mut [f64], level: f64, rng: &mut Rng) {
    if level == 0.0 || x.is_empty() {
        return;
    }
    let rms = (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt();
    for v in x.iter_mut() {
        *v += level * rms * rng.normal();
    }
}

fn cli_err(field: &str, reason: impl Into<String>) -> Error {
    Error::input("<cli>", field, reason)
}

impl SynthOptions {
    fn validate(&self) -> Result<()> {
        for (name, v) in [("--noise", self.noise), ("--voltage-noise", self.voltage_noise)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(cli_err(name, format!("must be a fraction ≥ 0 of the signal's RMS, got {v}")));
            }
        }
        if self.periods < 1 {
            return Err(cli_err("--periods", "must be at least 1"));
        }
        if self.samples_per_period < 8 {
            return Err(cli_err("--samples-per-period", "must be at least 8"));
        }
        if self.hits < 1 {
            return Err(cli_err("--hits", "must be at least 1"));
        }
        if let Some(m) = self.mass {
            if !(m > 0.0 && m.is_finite()) {
                return Err(cli_err("--mass", format!("must be positive, got {m}")));
            }
        }
        if let Some(dv) = self.offset {
            if !(dv.is_finite() && dv != 0.0) {
                return Err(cli_err("--offset", format!("must be a non-zero voltage, got {dv}")));
            }
        }
        use crate::analysis::{budget, cost};
        let samples = budget::product(&[budget::count(self.periods), budget::count(self.samples_per_period), 2]);
        let c = cost::of_arguments(
            "this synthetic measurement",
            (samples.and_then(|n| cost::record_bytes(n, 3)), samples),
            "samples",
            format!("{} periods × {} samples per period, two records at most", self.periods, self.samples_per_period),
            if self.periods >= self.samples_per_period { "--periods" } else { "--samples-per-period" },
            "ask for fewer periods or samples per period",
        );
        self.budget.admit(&c).map_err(|e| e.in_file("<cli>"))
    }
}

/// Makes the synthetic records of `opts.kind` from a loaded case.
pub fn synthesize(lc: &LoadedCase, opts: &SynthOptions) -> Result<Synthetic> {
    opts.validate()?;
    let built = crate::case::build_model(lc)?;
    let actuators = &built.actuators;
    if actuators.is_empty() {
        return Err(Error::input(&lc.file, "actuator", "the case has no actuator to make measurements of"));
    }
    let act = match &opts.actuator {
        None => &actuators[0],
        Some(name) => actuators.iter().find(|a| a.name() == name).ok_or_else(|| {
            let names: Vec<&str> = actuators.iter().map(|a| a.name()).collect();
            Error::input(
                &lc.file,
                "actuator",
                format!("no actuator named `{name}`; the case has: {}", names.join(", ")),
            )
        })?,
    };
    let mut truth = Truth {
        case: lc.file.clone(),
        actuator: act.name().to_string(),
        kind: match opts.kind {
            SynthKind::Stroke => "free stroke",
            SynthKind::BlockedForce => "blocked force",
            SynthKind::Impact => "impact test",
            SynthKind::DpPair => "d_p pair",
        }
        .to_string(),
        noise: opts.noise,
        voltage_noise: opts.voltage_noise,
        seed: opts.seed,
        ..Default::default()
    };
    let mut rng = Rng::new(opts.seed);
    let label = format!("<synth {} {}>", lc.file, act.name());
    let records = match opts.kind {
        SynthKind::Stroke | SynthKind::BlockedForce => {
            let stack = act.stack();
            let StrokeRecord { t, mut v, x, period } = stroke_record(lc, act, &stack.voltage, opts, 0)?;
            truth.bouc_wen = Some(stack.hysteresis);
            truth.period = Some(period);
            add_noise(&mut v, opts.voltage_noise, &mut rng);
            let (q, mut y) = if opts.kind == SynthKind::Stroke {
                (Quantity::Displacement, x)
            } else {
                truth.k_p = Some(stack.k_p);
                (Quantity::Force, x.iter().map(|x| stack.k_p * x).collect())
            };
            add_noise(&mut y, opts.noise, &mut rng);
            vec![Measurement::new(label, t, vec![(Quantity::Voltage, v), (q, y)])?]
        }
        SynthKind::DpPair => {
            let stack = act.stack();
            let input = &stack.voltage;
            let dv = match opts.offset {
                Some(dv) => dv,
                None => {
                    let period = periodic(lc, act, input)?;
                    let vs: Vec<f64> = (0..256).map(|i| input.value(period * i as f64 / 256.0)).collect();
                    let (lo, hi) =
                        vs.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(*v), b.max(*v)));
                    if hi <= lo {
                        return Err(Error::input(&lc.file, "voltage", "the voltage is constant: no stroke cycle"));
                    }
                    0.25 * 0.5 * (hi - lo)
                }
            };
            let shifted = with_offset(&lc.file, act.name(), input, dv)?;
            truth.bouc_wen = Some(stack.hysteresis);
            truth.delta_v = Some(dv);
            let mut out = Vec::new();
            for (k, inp) in [input, &shifted].into_iter().enumerate() {
                let lag = if k == 0 { 0 } else { opts.lag % opts.samples_per_period };
                let StrokeRecord { t, mut v, mut x, period } = stroke_record(lc, act, inp, opts, lag)?;
                truth.period = Some(period);
                add_noise(&mut v, opts.voltage_noise, &mut rng);
                add_noise(&mut x, opts.noise, &mut rng);
                let name = format!("<synth {} {} record {}>", lc.file, act.name(), k + 1);
                out.push(Measurement::new(name, t, vec![(Quantity::Voltage, v), (Quantity::Displacement, x)])?);
            }
            out
        }
        SynthKind::Impact => {
            let (m, k, c) = impact_system(lc, act, opts)?;
            let wn = (k / m).sqrt();
            let zeta = c / (2.0 * (k * m).sqrt());
            let f_n = wn / (2.0 * std::f64::consts::PI);
            truth.element = Some(opts.element);
            truth.mass = Some(m);
            truth.k = Some(k);
            truth.c = Some(c);
            truth.f_n = Some(f_n);
            truth.zeta = Some(zeta);
            let (t, mut f, mut a) = impact_record(m, k, c, opts.hits, &mut rng)?;
            add_noise(&mut f, opts.noise, &mut rng);
            add_noise(&mut a, opts.noise, &mut rng);
            vec![Measurement::new(label, t, vec![(Quantity::Force, f), (Quantity::Acceleration, a)])?]
        }
    };
    Ok(Synthetic { records, truth })
}

fn periodic(lc: &LoadedCase, act: &Actuator, input: &VoltageInput) -> Result<f64> {
    input.period().ok_or_else(|| {
        Error::input(
            &lc.file,
            format!("actuator `{}`.voltage", act.name()),
            "a synthetic stroke cycle needs a periodic voltage (kind = \"sine\", or \"sines\" with commensurate frequencies)",
        )
    })
}

/// A stroke record: time (s), voltage (V), free stroke δ (m), and the period (s).
struct StrokeRecord {
    t: Vec<f64>,
    v: Vec<f64>,
    x: Vec<f64>,
    period: f64,
}

/// `periods` periods of the periodic free stroke, the record starting `lag` samples into
/// the cycle.
fn stroke_record(
    lc: &LoadedCase,
    act: &Actuator,
    input: &VoltageInput,
    opts: &SynthOptions,
    lag: usize,
) -> Result<StrokeRecord> {
    let period = periodic(lc, act, input)?;
    let stack = act.stack();
    let spp = opts.samples_per_period;
    let (v1, x1): (Vec<f64>, Vec<f64>) = if stack.hysteresis_on {
        let cyc = stack.hysteresis.periodic_cycle(input, spp, 1e-13, 5000)?;
        if !cyc.converged {
            return Err(Error::Numerical(format!(
                "{}: the Bouc-Wen periodic state of actuator `{}` did not converge in {} periods",
                lc.file,
                act.name(),
                cyc.periods
            )));
        }
        (cyc.v[..spp].to_vec(), cyc.stroke[..spp].to_vec())
    } else {
        let v: Vec<f64> = (0..spp).map(|i| input.value(period * i as f64 / spp as f64)).collect();
        let x = v.iter().map(|v| stack.hysteresis.d_p * v).collect();
        (v, x)
    };
    let n = opts.periods * spp;
    let dt = period / spp as f64;
    let t: Vec<f64> = (0..n).map(|i| i as f64 * dt).collect();
    let v: Vec<f64> = (0..n).map(|i| v1[(i + lag) % spp]).collect();
    let x: Vec<f64> = (0..n).map(|i| x1[(i + lag) % spp]).collect();
    Ok(StrokeRecord { t, v, x, period })
}

fn with_offset(file: &str, name: &str, input: &VoltageInput, dv: f64) -> Result<VoltageInput> {
    let mut out = input.clone();
    match &mut out {
        VoltageInput::Sine { offset, .. } | VoltageInput::Sines { offset, .. } => *offset += dv,
        _ => {
            return Err(Error::input(
                file,
                format!("actuator `{name}`.voltage"),
                "a d_p pair needs a periodic voltage (kind = \"sine\" or \"sines\")",
            ))
        }
    }
    Ok(out)
}

/// (mass, k, c) of the single-DOF impact test.
fn impact_system(lc: &LoadedCase, act: &Actuator, opts: &SynthOptions) -> Result<(f64, f64, f64)> {
    let s = act.stack();
    match (opts.element, act) {
        (IdentifiedElement::Stack, Actuator::Inertial(a)) => {
            Ok((opts.mass.unwrap_or(a.m_t + 0.5 * s.m_p), s.k_p, s.c_p))
        }
        (IdentifiedElement::Stack, Actuator::Frame(f)) => Ok((opts.mass.unwrap_or(f.m_b + 0.5 * s.m_p), s.k_p, s.c_p)),
        (IdentifiedElement::Leg, Actuator::Frame(f)) => Ok((opts.mass.unwrap_or(0.5 * f.m_b), f.left.k_l, f.left.c_l)),
        (IdentifiedElement::LegRight, Actuator::Frame(f)) => {
            Ok((opts.mass.unwrap_or(0.5 * f.m_b), f.right.k_l, f.right.c_l))
        }
        (_, a) => Err(Error::input(
            &lc.file,
            "actuator",
            format!("actuator `{}` is inertial and has no frame legs; use --element stack", a.name()),
        )),
    }
}

/// Rounds up to two significant digits.
fn round_up_2(x: f64) -> f64 {
    let p = 10f64.powf(x.log10().floor() - 1.0);
    (x / p).ceil() * p
}

/// Hammer force and exact acceleration of `m·ẍ + c·ẋ + k·x = f` (noise-free): (t, f, a).
fn impact_record(m: f64, k: f64, c: f64, hits: usize, rng: &mut Rng) -> Result<(Vec<f64>, Vec<f64>, Vec<f64>)> {
    let wn = (k / m).sqrt();
    let zeta = c / (2.0 * (k * m).sqrt());
    if !(wn.is_finite() && zeta > 0.0 && zeta < 1.0) {
        return Err(Error::argument(
            "impact",
            format!("the element is not an underdamped oscillator (zeta = {zeta}); an impact test needs 0 < zeta < 1"),
        ));
    }
    let f_n = wn / (2.0 * std::f64::consts::PI);
    let fs = round_up_2(16.0 * f_n);
    let dt = 1.0 / fs;
    let tau = 1.0 / (zeta * wn);
    let len = ((30.0 * tau * fs).max(1024.0) / 256.0).ceil() as usize * 256;
    if len * hits > 20_000_000 {
        return Err(Error::argument(
            "impact",
            format!("{} samples per hit (zeta = {zeta:.2e} decays slowly) are too many; use fewer --hits", len),
        ));
    }
    let n = len * hits;
    let mut f = vec![0.0; n];
    for h in 0..hits {
        let start = (h * len + len / 40) as f64 * dt + rng.uniform() * dt;
        frf::add_hammer_pulse(&mut f, dt, start, 0.3 / f_n, 100.0 * (1.0 + 0.2 * rng.uniform()));
    }
    let a = frf::impact_response(&[vec![m]], &[vec![c]], &[vec![k]], 0, 0, &f, dt)?;
    let t: Vec<f64> = (0..n).map(|i| i as f64 * dt).collect();
    Ok((t, f, a))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn case(text: &str) -> LoadedCase {
        LoadedCase::from_str(text, "synth.toml", PathBuf::from(".")).unwrap()
    }

    const INERTIAL: &str = "base = \"rigid\"\n[[actuator]]\ntype = \"inertial\"\nname = \"shaker\"\n\
                            [actuator.voltage]\nkind = \"sine\"\namplitude = 48.0\nfrequency = 30.0\n";

    #[test]
    fn stroke_record_is_the_periodic_bouc_wen_state() {
        let lc = case(INERTIAL);
        let s = synthesize(&lc, &SynthOptions { noise: 0.0, ..Default::default() }).unwrap();
        let m = &s.records[0];
        assert_eq!(m.len(), 600);
        assert!((m.dt - 1.0 / 6000.0).abs() < 1e-15);
        let x = m.displacement.as_ref().unwrap();
        // Periodic, and δ = d_p·V − h with |h| within the class-I bound.
        assert!((x[0] - x[200]).abs() < 1e-12 * 1e-5);
        let bw = BoucWen::default();
        let v = m.voltage.as_ref().unwrap();
        for i in 0..600 {
            assert!((bw.d_p * v[i] - x[i]).abs() <= bw.bound(0.0) * (1.0 + 1e-12));
        }
        assert_eq!(s.truth.actuator, "shaker");
        assert!(s.truth.comments().iter().any(|c| c.contains("alpha = 0.3")));
    }

    #[test]
    fn noise_is_seeded_and_scaled_to_the_rms() {
        let lc = case(INERTIAL);
        let clean =
            synthesize(&lc, &SynthOptions { noise: 0.0, kind: SynthKind::BlockedForce, ..Default::default() }).unwrap();
        let o = SynthOptions { noise: 0.01, kind: SynthKind::BlockedForce, seed: 9, ..Default::default() };
        let a = synthesize(&lc, &o).unwrap();
        let b = synthesize(&lc, &o).unwrap();
        assert_eq!(a.records[0], b.records[0]);
        let c = synthesize(&lc, &SynthOptions { seed: 10, ..o.clone() }).unwrap();
        assert_ne!(a.records[0].force, c.records[0].force);
        let f0 = clean.records[0].force.as_ref().unwrap();
        let f1 = a.records[0].force.as_ref().unwrap();
        let rms = (f0.iter().map(|v| v * v).sum::<f64>() / f0.len() as f64).sqrt();
        let d: Vec<f64> = f0.iter().zip(f1).map(|(x, y)| y - x).collect();
        let sd = (d.iter().map(|v| v * v).sum::<f64>() / d.len() as f64).sqrt();
        assert!((sd / (0.01 * rms) - 1.0).abs() < 0.15, "{}", sd / (0.01 * rms));
        // The voltage stays clean by default.
        assert_eq!(a.records[0].voltage, clean.records[0].voltage);
    }

    #[test]
    fn pair_and_impact_and_errors() {
        let lc = case(INERTIAL);
        let p = synthesize(&lc, &SynthOptions { kind: SynthKind::DpPair, noise: 0.0, ..Default::default() }).unwrap();
        assert_eq!(p.records.len(), 2);
        assert_eq!(p.truth.delta_v, Some(12.0));
        let (v1, v2) = (p.records[0].voltage.as_ref().unwrap(), p.records[1].voltage.as_ref().unwrap());
        assert!((v2[0] - v1[37] - 12.0).abs() < 1e-9);
        let i = synthesize(&lc, &SynthOptions { kind: SynthKind::Impact, hits: 2, ..Default::default() }).unwrap();
        let t = &i.truth;
        assert!((t.mass.unwrap() - 0.115).abs() < 1e-12 && t.k == Some(3.0e7) && t.c == Some(200.0));
        assert!(i.records[0].force.is_some() && i.records[0].acceleration.is_some());
        let e = synthesize(
            &lc,
            &SynthOptions { kind: SynthKind::Impact, element: IdentifiedElement::Leg, ..Default::default() },
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("synth.toml") && e.contains("no frame legs"), "{e}");
        let e = synthesize(&lc, &SynthOptions { actuator: Some("nope".into()), ..Default::default() })
            .unwrap_err()
            .to_string();
        assert!(e.contains("nope") && e.contains("shaker"), "{e}");
        let chirp = INERTIAL.replace(
            "kind = \"sine\"\namplitude = 48.0\nfrequency = 30.0",
            "kind = \"chirp\"\namplitude = 48.0\nf_start = 10.0\nf_end = 100.0\nduration = 1.0",
        );
        let e = synthesize(&case(&chirp), &SynthOptions::default()).unwrap_err().to_string();
        assert!(e.contains("periodic voltage"), "{e}");
    }
}
