//! Result quantities an objective or a constraint names, written as short expressions
//! (`net_power`, `net_power[1]@1`, `modal_power[1,3]`, `modal_band[40,300]`,
//! `sensor.tip.velocity`, `dissipation`), and their values from a solved steady state
//! ([`Outcome`]). The formulas are in docs/optimize.md.

use num_complex::Complex64;

/// Which response a sensor quantity reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Response {
    Displacement,
    Velocity,
    Acceleration,
}

/// The bare-beam modes a modal quantity sums over.
#[derive(Clone, Debug, PartialEq)]
pub enum ModeSet {
    /// Mode numbers, 1-based.
    List(Vec<usize>),
    /// Every mode whose natural frequency lies in [lo, hi] Hz.
    Band(f64, f64),
}

/// A number computed from one steady state.
#[derive(Clone, Debug, PartialEq)]
pub enum Quantity {
    /// Net mean power into the beam (W) of one actuator or of all, summed over the
    /// harmonics or at one harmonic k (k = 1: the drive frequency).
    NetPower { actuator: Option<usize>, harmonic: Option<usize> },
    /// Power the actuators put into the chosen bare-beam modes (W), summed over harmonics.
    ModalPower(ModeSet),
    /// Amplitude of a sensor's response at harmonic k (default 1): |W_k|·(kω₀)^p with p = 0,
    /// 1, 2 for displacement (m), velocity (m/s), acceleration (m/s²).
    Sensor { name: String, response: Response, harmonic: usize },
    /// Power the beam dissipates (W).
    Dissipation,
}

impl Quantity {
    /// Parses an expression; the error is the reason, for the caller to place.
    pub fn parse(text: &str) -> std::result::Result<Quantity, String> {
        let t = text.trim();
        let (body, harmonic) = match t.split_once('@') {
            Some((b, h)) => {
                let k = h.trim().parse::<usize>().map_err(|_| format!("`@{h}`: a harmonic is a whole number ≥ 0"))?;
                (b.trim(), Some(k))
            }
            None => (t, None),
        };
        let (name, index) = match body.split_once('[') {
            Some((n, rest)) => {
                let inner =
                    rest.strip_suffix(']').ok_or_else(|| format!("`{body}`: an index is written `name[...]`"))?;
                (n.trim(), Some(inner))
            }
            None => (body, None),
        };
        let numbers = |inner: &str| -> std::result::Result<Vec<f64>, String> {
            inner
                .split(',')
                .map(|s| s.trim().parse::<f64>().map_err(|_| format!("`{body}`: `{}` is not a number", s.trim())))
                .collect()
        };
        let no_harmonic = |q: Quantity| {
            if harmonic.is_some() {
                Err(format!("`{t}`: `@k` applies only to net_power and sensor quantities"))
            } else {
                Ok(q)
            }
        };
        match (name, index) {
            ("net_power", None) => Ok(Quantity::NetPower { actuator: None, harmonic }),
            ("net_power", Some(i)) => {
                let a =
                    i.trim().parse::<usize>().map_err(|_| format!("`{body}`: the actuator index is a whole number"))?;
                Ok(Quantity::NetPower { actuator: Some(a), harmonic })
            }
            ("modal_power", Some(i)) => {
                let v = numbers(i)?;
                if v.iter().any(|&m| !(m >= 1.0 && m.fract() == 0.0)) {
                    return Err(format!("`{body}`: mode numbers are whole numbers from 1"));
                }
                no_harmonic(Quantity::ModalPower(ModeSet::List(v.iter().map(|&m| m as usize).collect())))
            }
            ("modal_band", Some(i)) => match numbers(i)?.as_slice() {
                &[lo, hi] if lo >= 0.0 && hi > lo && hi.is_finite() => {
                    no_harmonic(Quantity::ModalPower(ModeSet::Band(lo, hi)))
                }
                _ => Err(format!("`{body}`: a band is `modal_band[lo, hi]` in Hz with 0 ≤ lo < hi")),
            },
            ("dissipation", None) => no_harmonic(Quantity::Dissipation),
            (s, None) if s.starts_with("sensor.") => {
                let parts: Vec<&str> = s.split('.').collect();
                let response = match parts.as_slice() {
                    [_, _, "displacement"] => Response::Displacement,
                    [_, _, "velocity"] => Response::Velocity,
                    [_, _, "acceleration"] => Response::Acceleration,
                    _ => {
                        return Err(format!("`{s}`: write `sensor.NAME.displacement`, `.velocity` or `.acceleration`"))
                    }
                };
                Ok(Quantity::Sensor { name: parts[1].to_string(), response, harmonic: harmonic.unwrap_or(1) })
            }
            _ => Err(format!(
                "`{t}` names no result: use net_power, net_power[a], modal_power[r,...], modal_band[lo,hi], \
                 sensor.NAME.displacement|velocity|acceleration or dissipation (optionally `@k` for one harmonic)"
            )),
        }
    }

    /// Whether the quantity is never negative (amplitudes, dissipation, the power of one
    /// actuator alone is not, so only these).
    pub fn non_negative(&self) -> bool {
        matches!(self, Quantity::Sensor { .. } | Quantity::Dissipation)
    }

    /// The highest mode number a modal quantity needs, if any (a band needs the modes up to
    /// its upper frequency, found when the modes are computed).
    pub fn modes_needed(&self) -> Option<usize> {
        match self {
            Quantity::ModalPower(ModeSet::List(m)) => m.iter().copied().max(),
            Quantity::ModalPower(ModeSet::Band(..)) => Some(0),
            _ => None,
        }
    }

    /// The unit of the value.
    pub fn unit(&self) -> &'static str {
        match self {
            Quantity::NetPower { .. } | Quantity::ModalPower(_) | Quantity::Dissipation => "W",
            Quantity::Sensor { response: Response::Displacement, .. } => "m",
            Quantity::Sensor { response: Response::Velocity, .. } => "m/s",
            Quantity::Sensor { response: Response::Acceleration, .. } => "m/s^2",
        }
    }
}

/// What one evaluated candidate gives the quantities.
#[derive(Clone, Debug, Default)]
pub struct Outcome {
    /// Net power per actuator per harmonic (W), [a][k], k = 0..=harmonics.
    pub net_power_harmonic: Vec<Vec<f64>>,
    /// Net power per actuator (W), all harmonics.
    pub net_power: Vec<f64>,
    pub dissipation: f64,
    pub balance_error: f64,
    /// Drive fundamental ω₀ (rad/s).
    pub omega0: f64,
    /// Sensor displacement amplitudes W_k (m) by sensor name, k = 0..=harmonics.
    pub sensors: Vec<(String, Vec<Complex64>)>,
    /// Power into each bare-beam mode (W), summed over links and harmonics, and the modes'
    /// natural frequencies (Hz); empty when no quantity needs them.
    pub modal_power: Vec<f64>,
    pub mode_frequency_hz: Vec<f64>,
    /// Σ_a V̂_a² (V²) and the actuators' mass Σ_a (m_p + m_t or m_b) (kg).
    pub volt2: f64,
    pub mass: f64,
}

impl Outcome {
    /// The value of `q`; the error says why it has none (e.g. an actuator index out of range).
    pub fn value(&self, q: &Quantity) -> std::result::Result<f64, String> {
        match q {
            Quantity::NetPower { actuator, harmonic } => {
                let per = |a: usize| -> std::result::Result<f64, String> {
                    match harmonic {
                        None => Ok(self.net_power[a]),
                        Some(k) => self.net_power_harmonic[a]
                            .get(*k)
                            .copied()
                            .ok_or_else(|| format!("harmonic {k} is above the {} solved", self.harmonics())),
                    }
                };
                match actuator {
                    Some(a) if *a >= self.net_power.len() => {
                        Err(format!("actuator {a} does not exist (the case has {})", self.net_power.len()))
                    }
                    Some(a) => per(*a),
                    None => (0..self.net_power.len()).map(per).sum(),
                }
            }
            Quantity::ModalPower(set) => {
                let modes: Vec<usize> = match set {
                    ModeSet::List(m) => m.iter().map(|r| r - 1).collect(),
                    ModeSet::Band(lo, hi) => (0..self.mode_frequency_hz.len())
                        .filter(|&r| (*lo..=*hi).contains(&self.mode_frequency_hz[r]))
                        .collect(),
                };
                modes
                    .iter()
                    .map(|&r| {
                        self.modal_power.get(r).copied().ok_or_else(|| format!("mode {} was not computed", r + 1))
                    })
                    .sum()
            }
            Quantity::Sensor { name, response, harmonic } => {
                let w = &self.sensors.iter().find(|(n, _)| n == name).ok_or_else(|| format!("no sensor `{name}`"))?.1;
                let x = w
                    .get(*harmonic)
                    .ok_or_else(|| format!("harmonic {harmonic} is above the {} solved", w.len() - 1))?;
                let wk = *harmonic as f64 * self.omega0;
                Ok(x.norm()
                    * match response {
                        Response::Displacement => 1.0,
                        Response::Velocity => wk,
                        Response::Acceleration => wk * wk,
                    })
            }
            Quantity::Dissipation => Ok(self.dissipation),
        }
    }

    fn harmonics(&self) -> usize {
        self.net_power_harmonic.first().map_or(0, |v| v.len().saturating_sub(1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expressions_parse() {
        assert_eq!(Quantity::parse("net_power").unwrap(), Quantity::NetPower { actuator: None, harmonic: None });
        assert_eq!(
            Quantity::parse(" net_power[1] @ 1").unwrap(),
            Quantity::NetPower { actuator: Some(1), harmonic: Some(1) }
        );
        assert_eq!(Quantity::parse("modal_power[1, 3]").unwrap(), Quantity::ModalPower(ModeSet::List(vec![1, 3])));
        assert_eq!(Quantity::parse("modal_band[40,300]").unwrap(), Quantity::ModalPower(ModeSet::Band(40.0, 300.0)));
        assert_eq!(
            Quantity::parse("sensor.tip.velocity@3").unwrap(),
            Quantity::Sensor { name: "tip".into(), response: Response::Velocity, harmonic: 3 }
        );
        for bad in ["power", "modal_power[0]", "modal_band[3,1]", "sensor.tip", "net_power[x]", "dissipation@2"] {
            assert!(Quantity::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn values_follow_the_definitions() {
        let o = Outcome {
            net_power_harmonic: vec![vec![0.0, 2.0, 0.0, 1.0], vec![0.0, 3.0, 0.0, 0.5]],
            net_power: vec![3.0, 3.5],
            modal_power: vec![1.0, 2.0, 4.0],
            mode_frequency_hz: vec![50.0, 137.0, 270.0],
            omega0: 10.0,
            sensors: vec![("tip".into(), vec![Complex64::new(0.0, 0.0), Complex64::new(3.0, 4.0)])],
            ..Default::default()
        };
        let v = |s: &str| o.value(&Quantity::parse(s).unwrap()).unwrap();
        assert_eq!(v("net_power"), 6.5);
        assert_eq!(v("net_power[1]"), 3.5);
        assert_eq!(v("net_power@1"), 5.0);
        assert_eq!(v("modal_power[1,3]"), 5.0);
        assert_eq!(v("modal_band[100,300]"), 6.0);
        assert_eq!(v("sensor.tip.displacement"), 5.0);
        assert_eq!(v("sensor.tip.velocity"), 50.0);
        assert_eq!(v("sensor.tip.acceleration"), 500.0);
        assert!(o.value(&Quantity::parse("net_power[2]").unwrap()).is_err());
    }
}
