//! What one request may take — memory and steps — and what it would take, estimated
//! before anything sized by user input is allocated or stepped.
//!
//! Every count an analysis takes from a case (mesh elements, modes, frequencies, samples,
//! time steps, periods, sweep cases) multiplies into a size. Each analysis states its
//! [`Cost`] from the case alone; [`Budget::admit`] refuses one above the budget with the
//! estimate, the limit and the field that drives it, so that a typo of a few orders of
//! magnitude is an error message, not an abort, a hang or a machine swapping for hours.
//! Sizes are multiplied with checked arithmetic: a product beyond 64 bits is refused as
//! such, never wrapped.

use crate::error::{Error, Result};

/// What one analysis (or one sweep, or one optimisation) may take.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Budget {
    /// Memory (bytes).
    pub memory: u64,
    /// Time steps (or samples) one analysis steps through; cases of a sweep or an
    /// optimisation.
    pub steps: u64,
}

/// Default step budget: about an hour of time stepping on the paper's 400-DOF beam
/// (≈ 4 µs a step), far beyond any shipped case (the longest takes 2.7e6 steps).
pub const DEFAULT_STEPS: u64 = 1_000_000_000;

/// Memory budget where the machine's available memory cannot be read.
pub const FALLBACK_MEMORY: u64 = 4 << 30;

impl Default for Budget {
    /// Half of the machine's available memory, [`DEFAULT_STEPS`].
    fn default() -> Self {
        Budget { memory: machine_memory(), steps: DEFAULT_STEPS }
    }
}

impl Budget {
    /// The default budget with the overrides given (`--max-memory`, `--max-steps`).
    pub fn with(memory: Option<u64>, steps: Option<u64>) -> Self {
        let d = Budget::default();
        Budget { memory: memory.unwrap_or(d.memory), steps: steps.unwrap_or(d.steps) }
    }

    /// Refuses `cost` when it exceeds this budget (or overflows 64 bits): an error of the
    /// setting `field` (see [`Cost::field`]) stating the estimate, the limit and how to
    /// raise it.
    pub fn admit(&self, cost: &Cost) -> Result<()> {
        let over = |need: Option<u64>, limit: u64| need.is_none_or(|n| n > limit);
        let (quantity, need, limit, flag) = if over(cost.bytes, self.memory) {
            ("memory", cost.bytes.map(bytes_text), bytes_text(self.memory), "--max-memory")
        } else if over(cost.steps, self.steps) {
            (cost.unit, cost.steps.map(count_text), count_text(self.steps), "--max-steps")
        } else {
            return Ok(());
        };
        let need = need.map_or_else(|| "more than 2⁶⁴".to_string(), |n| format!("≈ {n}"));
        let reason = format!(
            "{} needs {need} {quantity} ({}), above the budget of {limit} (`{flag}` raises it); {}",
            cost.what, cost.detail, cost.advice
        );
        Err(match cost.scope {
            CostScope::Analysis => Error::analysis_setting(&cost.field, reason),
            CostScope::Case => Error::case_field(&cost.field, reason),
            CostScope::Argument => Error::argument(&cost.field, reason),
        })
    }
}

/// Where a [`Cost`]'s field lives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CostScope {
    /// A field of the analysis table being planned.
    Analysis,
    /// A dotted path from the case's root.
    Case,
    /// An argument of a command (e.g. `--particles`).
    Argument,
}

/// The estimated memory and steps of a request, with the field that drives them.
#[derive(Clone, Debug)]
pub struct Cost {
    /// Bytes at the peak (None: beyond 64 bits).
    pub bytes: Option<u64>,
    /// Steps (None: beyond 64 bits).
    pub steps: Option<u64>,
    /// What the steps count, e.g. "time steps".
    pub unit: &'static str,
    /// What is estimated, e.g. "this transient".
    pub what: String,
    /// The factors of the estimate, e.g. "1e9 periods × 200 steps".
    pub detail: String,
    /// The field that drives the estimate, and where it lives.
    pub field: String,
    pub scope: CostScope,
    /// What to change.
    pub advice: String,
}

/// The product of `factors`, None if it does not fit 64 bits.
pub fn product(factors: &[u64]) -> Option<u64> {
    factors.iter().try_fold(1u64, |a, &b| a.checked_mul(b))
}

/// The sum of `terms`, None if any is None or the sum does not fit 64 bits.
pub fn sum(terms: &[Option<u64>]) -> Option<u64> {
    terms.iter().try_fold(0u64, |a, &b| a.checked_add(b?))
}

/// `n` as u64 (usize is at most 64 bits on every supported target).
pub fn count(n: usize) -> u64 {
    u64::try_from(n).unwrap_or(u64::MAX)
}

/// A non-negative real count (e.g. duration / Δt) as a whole number rounded up, None
/// when it is not finite or beyond 2⁶³ (where f64 no longer holds every integer near it
/// either).
pub fn whole(x: f64) -> Option<u64> {
    let c = x.ceil();
    (0.0..9.2e18).contains(&c).then_some(c as u64)
}

/// Bytes as text with a binary unit, e.g. "3.2 GiB".
pub fn bytes_text(b: u64) -> String {
    const UNITS: [&str; 7] = ["B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    let mut x = b as f64;
    let mut u = 0;
    while x >= 1024.0 && u + 1 < UNITS.len() {
        x /= 1024.0;
        u += 1;
    }
    if u == 0 {
        format!("{b} B")
    } else {
        format!("{x:.1} {}", UNITS[u])
    }
}

/// A count as text: exact below a million, else in scientific notation.
pub fn count_text(n: u64) -> String {
    if n < 1_000_000 {
        n.to_string()
    } else {
        format!("{:.2e}", n as f64)
    }
}

/// Half of `MemAvailable` in /proc/meminfo (the memory others leave free, halved so that
/// one run leaves room for the rest of the machine), else [`FALLBACK_MEMORY`].
pub fn machine_memory() -> u64 {
    std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|t| available_kib(&t))
        .and_then(|kib| kib.checked_mul(1024))
        .map_or(FALLBACK_MEMORY, |b| b / 2)
}

/// The `MemAvailable` line of /proc/meminfo text (KiB).
fn available_kib(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemAvailable:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// Parses a memory size: bytes, or a number with a binary suffix `K`, `M`, `G`, `T`
/// (optionally followed by `iB` or `B`, any case), e.g. `8G`, `512MiB`, `1.5T`.
pub fn parse_bytes(text: &str) -> std::result::Result<u64, String> {
    let t = text.trim();
    if t.starts_with('-') {
        return Err(format!("{text:?} is negative: give between 1 byte and 16 EiB, e.g. 8G or 512M"));
    }
    let split = t.find(|c: char| !(c.is_ascii_digit() || c == '.')).unwrap_or(t.len());
    let (number, unit) = t.split_at(split);
    let scale: u64 = match unit.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 1,
        "k" | "kb" | "kib" => 1 << 10,
        "m" | "mb" | "mib" => 1 << 20,
        "g" | "gb" | "gib" => 1 << 30,
        "t" | "tb" | "tib" => 1 << 40,
        u => return Err(format!("unknown unit {u:?} in {text:?}: give bytes or a size such as 8G or 512M")),
    };
    let x: f64 = number.parse().map_err(|_| format!("{text:?} is not a size: give e.g. 8G, 512M or 1000000"))?;
    let b = x * scale as f64;
    if !(1.0..1.8e19).contains(&b) {
        return Err(format!("{text:?} is out of range: give between 1 byte and 16 EiB"));
    }
    Ok(b as u64)
}

/// Parses a step budget: a positive whole number, e.g. `1000000000` or `1e9`.
pub fn parse_steps(text: &str) -> std::result::Result<u64, String> {
    let x: f64 = text.trim().parse().map_err(|_| format!("{text:?} is not a number of steps: give e.g. 1e9"))?;
    if !((1.0..1.8e19).contains(&x) && x.fract() == 0.0) {
        return Err(format!("{text:?}: give a whole number of steps between 1 and 1.8e19"));
    }
    Ok(x as u64)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cost(bytes: Option<u64>, steps: Option<u64>) -> Cost {
        Cost {
            bytes,
            steps,
            unit: "time steps",
            what: "this transient".into(),
            detail: "periods × steps".into(),
            field: "periods".into(),
            scope: CostScope::Analysis,
            advice: "run fewer periods".into(),
        }
    }

    #[test]
    fn a_cost_within_the_budget_is_admitted_and_one_beyond_it_is_refused_with_both_numbers() {
        let b = Budget { memory: 1 << 30, steps: 1000 };
        assert!(b.admit(&cost(Some(1 << 30), Some(1000))).is_ok());
        let e = b.admit(&cost(Some((1 << 30) + 1), Some(1))).unwrap_err().to_string();
        assert!(e.contains("`periods`") && e.contains("≈ 1.0 GiB memory") && e.contains("--max-memory"), "{e}");
        let e = b.admit(&cost(Some(1), Some(1001))).unwrap_err().to_string();
        assert!(e.contains("≈ 1001 time steps") && e.contains("budget of 1000") && e.contains("--max-steps"), "{e}");
        let e = b.admit(&cost(None, Some(1))).unwrap_err().to_string();
        assert!(e.contains("more than 2⁶⁴ memory"), "{e}");
    }

    #[test]
    fn sizes_multiply_with_overflow_refused_not_wrapped() {
        assert_eq!(product(&[1 << 32, 1 << 31]), Some(1 << 63));
        assert_eq!(product(&[1 << 32, 1 << 32]), None);
        assert_eq!(sum(&[Some(u64::MAX), Some(1)]), None);
        assert_eq!(sum(&[Some(2), None]), None);
        assert_eq!(whole(2.5), Some(3));
        assert_eq!(whole(f64::NAN), None);
        assert_eq!(whole(1e300), None);
        assert_eq!(whole(-1.0), None);
    }

    #[test]
    fn sizes_parse_with_binary_units() {
        assert_eq!(parse_bytes("8G"), Ok(8 << 30));
        assert_eq!(parse_bytes("512MiB"), Ok(512 << 20));
        assert_eq!(parse_bytes("1.5k"), Ok(1536));
        assert_eq!(parse_bytes("1000"), Ok(1000));
        assert!(parse_bytes("8X").is_err() && parse_bytes("").is_err() && parse_bytes("0").is_err());
        assert!(parse_bytes("1e400").is_err() && parse_bytes("-1G").is_err());
        assert_eq!(parse_steps("1e9"), Ok(1_000_000_000));
        assert!(parse_steps("0").is_err() && parse_steps("1.5").is_err() && parse_steps("nan").is_err());
        assert_eq!(bytes_text(3 << 29), "1.5 GiB");
        assert_eq!(count_text(2_000_000), "2.00e6");
    }

    #[test]
    fn the_machine_budget_is_half_the_available_memory() {
        let text = "MemTotal:       24684084 kB\nMemFree: 1 kB\nMemAvailable:   2048 kB\n";
        assert_eq!(available_kib(text), Some(2048));
        assert_eq!(available_kib("MemTotal: 5 kB\n"), None);
        assert!(machine_memory() >= 1 << 20);
    }
}
