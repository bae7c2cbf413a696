//! The sweep table: one row per case (index, inputs, headline outputs), its HDF5 form, the
//! per-case checkpoint files a running sweep leaves behind, and merging shards.

use super::spec::{fnv1a, Sweep, FNV_OFFSET};
use crate::error::{Error, Result};
use crate::io::hdf5::{ResultsFile, ResultsReader};
use std::collections::BTreeMap;
use std::path::Path;

/// Which part of a sweep a run covers: case indices i with `i % n == k − 1` (1-based k).
/// Round-robin rather than contiguous blocks, so that every shard gets a similar mix of
/// cheap and expensive cases.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub k: usize,
    pub n: usize,
}

impl Default for Shard {
    fn default() -> Self {
        Shard::ALL
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

impl Shard {
    /// The whole sweep.
    pub const ALL: Shard = Shard { k: 1, n: 1 };

    /// Parses `k/N` with 1 ≤ k ≤ N; `file` and `field` name the source in messages
    /// (`<cli>`, `--shard` on the command line).
    pub fn parse(s: &str, file: &str, field: &str) -> Result<Shard> {
        let bad = |why: &str| Error::input(file, field, format!("`{s}`: {why}"));
        let (k, n) = s.split_once('/').ok_or_else(|| bad("write the shard as k/N, e.g. 2/8"))?;
        let k: usize = k.trim().parse().map_err(|_| bad("k in k/N must be a whole number"))?;
        let n: usize = n.trim().parse().map_err(|_| bad("N in k/N must be a whole number"))?;
        if n == 0 {
            return Err(bad("N must be at least 1"));
        }
        if k == 0 || k > n {
            return Err(bad(&format!("k must lie in 1..={n} (shards are numbered from 1)")));
        }
        Ok(Shard { k, n })
    }

    pub fn contains(&self, i: usize) -> bool {
        i % self.n == self.k - 1
    }

    /// The case indices of this shard, ascending.
    pub fn indices(&self, total: usize) -> Vec<usize> {
        (self.k - 1..total).step_by(self.n).collect()
    }
}

/// One evaluated case.
#[derive(Clone, Debug)]
pub struct Row {
    pub index: usize,
    /// Parameter values, in parameter order.
    pub inputs: Vec<f64>,
    /// Net mean power into the beam per actuator (W).
    pub net_power: Vec<f64>,
    /// Mean power into the beam per link (W).
    pub mean_power: Vec<f64>,
    /// Amplitude of the transmitted force at the drive's fundamental per link (N).
    pub force_amplitude: Vec<f64>,
    /// Mean power dissipated by the beam's damping (W).
    pub beam_dissipation: f64,
    /// Relative energy-balance error (–).
    pub balance_error: f64,
}

impl Row {
    /// Total net power of all actuators (W).
    pub fn total_net_power(&self) -> f64 {
        self.net_power.iter().sum()
    }

    fn floats(&self) -> impl Iterator<Item = f64> + '_ {
        self.inputs
            .iter()
            .chain(&self.net_power)
            .chain(&self.mean_power)
            .chain(&self.force_amplitude)
            .copied()
            .chain([self.beam_dissipation, self.balance_error])
    }

    /// Equal bit for bit (NaN equals NaN of the same payload).
    pub fn bitwise_eq(&self, o: &Row) -> bool {
        self.index == o.index
            && self.inputs.len() == o.inputs.len()
            && self.net_power.len() == o.net_power.len()
            && self.mean_power.len() == o.mean_power.len()
            && self.force_amplitude.len() == o.force_amplitude.len()
            && self.floats().zip(o.floats()).all(|(a, b)| a.to_bits() == b.to_bits())
    }
}

const PART_MAGIC: &[u8; 8] = b"BFSWPRT1";

/// A finished case as a small binary checkpoint file: magic, sweep hash, index, the three
/// column counts, the values as little-endian f64, and an FNV-1a checksum of all that.
/// Exact (no decimal round trip) and self-checking: a truncated or foreign file is
/// recognised and the case recomputed.
pub fn encode_part(row: &Row, hash: &str) -> Vec<u8> {
    let mut b = Vec::with_capacity(64 + 8 * 16);
    b.extend_from_slice(PART_MAGIC);
    b.extend_from_slice(&u64::from_str_radix(hash, 16).unwrap_or(0).to_le_bytes());
    b.extend_from_slice(&(row.index as u64).to_le_bytes());
    for n in [row.inputs.len(), row.net_power.len(), row.mean_power.len()] {
        b.extend_from_slice(&(n as u32).to_le_bytes());
    }
    for v in row.floats() {
        b.extend_from_slice(&v.to_le_bytes());
    }
    let sum = fnv1a(&b, FNV_OFFSET);
    b.extend_from_slice(&sum.to_le_bytes());
    b
}

/// Decodes a checkpoint; `None` if it is damaged, from another sweep or of another shape.
pub fn decode_part(b: &[u8], hash: &str, shape: (usize, usize, usize)) -> Option<Row> {
    if b.len() < 8 + 8 + 8 + 12 + 8 || &b[..8] != PART_MAGIC {
        return None;
    }
    let (body, sum) = b.split_at(b.len() - 8);
    if fnv1a(body, FNV_OFFSET).to_le_bytes() != sum {
        return None;
    }
    let u64_at = |o: usize| u64::from_le_bytes(body[o..o + 8].try_into().expect("8 bytes"));
    let u32_at = |o: usize| u32::from_le_bytes(body[o..o + 4].try_into().expect("4 bytes")) as usize;
    if u64_at(8) != u64::from_str_radix(hash, 16).ok()? {
        return None;
    }
    let index = u64_at(16) as usize;
    let (ni, na, nl) = (u32_at(24), u32_at(28), u32_at(32));
    if (ni, na, nl) != shape {
        return None;
    }
    let floats = &body[36..];
    if floats.len() != 8 * (ni + na + 2 * nl + 2) {
        return None;
    }
    let f: Vec<f64> = floats.chunks_exact(8).map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes"))).collect();
    let mut it = f.into_iter();
    let mut take = |n: usize| (&mut it).take(n).collect::<Vec<f64>>();
    let inputs = take(ni);
    let net_power = take(na);
    let mean_power = take(nl);
    let force_amplitude = take(nl);
    let rest = take(2);
    Some(Row {
        index,
        inputs,
        net_power,
        mean_power,
        force_amplitude,
        beam_dissipation: rest[0],
        balance_error: rest[1],
    })
}

/// The result of a sweep (or of one shard of it).
#[derive(Clone, Debug)]
pub struct SweepTable {
    pub title: String,
    /// The sweep file as named when it ran, its text and the base case text.
    pub sweep_file: String,
    pub sweep_text: String,
    pub base_text: String,
    pub hash: String,
    /// Cases in the whole sweep, and the part this table covers.
    pub total_cases: usize,
    pub shard: Shard,
    pub analysis: String,
    pub harmonics: usize,
    pub samples_per_period: usize,
    /// Rayleigh (a₀, a₁) computed once for all cases, if cached.
    pub damping: Option<(f64, f64)>,
    /// A reduced sweep's check of its reduction against the full model.
    pub reduction: Option<ReductionCheck>,
    pub best: usize,
    pub parameters: Vec<String>,
    pub units: Vec<String>,
    pub actuators: Vec<String>,
    pub links: Vec<String>,
    /// Rows sorted by case index.
    pub rows: Vec<Row>,
}

/// A reduced study's check of its reduction: its best case (largest total net power) solved
/// on the full model as well.
#[derive(Clone, Debug, PartialEq)]
pub struct ReductionCheck {
    /// Cut-off (Hz) and modes kept by the reduction.
    pub cutoff_hz: f64,
    pub modes_kept: usize,
    /// The case checked (None: an optimisation's optimum), and the largest relative
    /// difference of its point and net powers from the full model's (each against its own
    /// size, or 1e-6 of the largest where smaller).
    pub case: Option<usize>,
    pub max_relative_error: f64,
}

impl ReductionCheck {
    /// The worse of two checks (shards merged).
    fn worse(a: Option<Self>, b: Option<Self>) -> Option<Self> {
        match (a, b) {
            (Some(a), Some(b)) => Some(if b.max_relative_error > a.max_relative_error { b } else { a }),
            (a, b) => a.or(b),
        }
    }
}

impl SweepTable {
    /// What the power goes into, in labels, from the base case the table keeps: `beam`,
    /// `plate`, `model` (imported) or `base` (a rigid base).
    pub fn into_word(&self) -> &'static str {
        let Ok(case) = self.base_text.parse::<toml::Table>() else { return "structure" };
        if case.contains_key("imported") {
            "model"
        } else if case.contains_key("plate") {
            "plate"
        } else if case.get("base").and_then(|b| b.as_str()) == Some("rigid") {
            "base"
        } else {
            "beam"
        }
    }

    /// An empty table for (a shard of) a sweep.
    pub fn new(sweep: &Sweep, shard: Shard) -> SweepTable {
        SweepTable {
            title: sweep.title.clone(),
            sweep_file: sweep.file.clone(),
            sweep_text: sweep.text.clone(),
            base_text: sweep.base.text.clone(),
            hash: sweep.hash.clone(),
            total_cases: sweep.len(),
            shard,
            analysis: sweep.analysis.as_str().to_string(),
            harmonics: sweep.harmonics,
            samples_per_period: sweep.samples_per_period,
            damping: sweep.base.cached_damping.map(|r| (r.a0, r.a1)),
            reduction: None,
            best: sweep.best,
            parameters: sweep.parameter_names(),
            units: sweep.parameters.iter().map(|p| p.field.unit.to_string()).collect(),
            actuators: sweep.base.actuators.clone(),
            links: sweep.base.links.clone(),
            rows: Vec::new(),
        }
    }

    /// (inputs, actuators, links): the shape of every row.
    pub fn shape(&self) -> (usize, usize, usize) {
        (self.parameters.len(), self.actuators.len(), self.links.len())
    }

    /// Case indices this table should hold but does not.
    pub fn missing(&self) -> Vec<usize> {
        let have: std::collections::BTreeSet<usize> = self.rows.iter().map(|r| r.index).collect();
        self.shard.indices(self.total_cases).into_iter().filter(|i| !have.contains(i)).collect()
    }

    pub fn is_complete(&self) -> bool {
        self.missing().is_empty()
    }

    /// Same metadata and rows, bit for bit (the sweep file's name may differ).
    pub fn bitwise_eq(&self, o: &SweepTable) -> bool {
        self.hash == o.hash
            && self.total_cases == o.total_cases
            && self.shard == o.shard
            && self.parameters == o.parameters
            && self.actuators == o.actuators
            && self.links == o.links
            && self.rows.len() == o.rows.len()
            && self.rows.iter().zip(&o.rows).all(|(a, b)| a.bitwise_eq(b))
    }

    /// Index of a parameter by path.
    pub fn parameter(&self, path: &str) -> Option<usize> {
        self.parameters.iter().position(|p| p == path)
    }

    /// Writes the table as HDF5, atomically (see `docs/sweeps.md` for the layout).
    pub fn write(&self, path: &Path) -> Result<()> {
        let f = ResultsFile::create(path)?;
        f.set_attr_str("program", "beamflow")?;
        f.set_attr_str("version", env!("CARGO_PKG_VERSION"))?;
        f.set_attr_str("kind", "sweep table")?;
        f.set_attr_str("title", &self.title)?;
        f.set_attr_str("sweep_file", &self.sweep_file)?;
        f.set_attr_str("sweep_hash", &self.hash)?;
        f.set_attr_i64("total_cases", self.total_cases as i64)?;
        f.set_attr_str("shard", &self.shard.to_string())?;
        f.set_attr_str("analysis", &self.analysis)?;
        f.set_attr_i64("harmonics", self.harmonics as i64)?;
        f.set_attr_i64("samples_per_period", self.samples_per_period as i64)?;
        f.set_attr_i64("best", self.best as i64)?;
        if let Some((a0, a1)) = self.damping {
            f.set_attr_f64("cached_rayleigh_a0", a0)?;
            f.set_attr_f64("cached_rayleigh_a1", a1)?;
        }
        if let Some(c) = &self.reduction {
            f.set_attr_f64("reduction_cutoff_hz", c.cutoff_hz)?;
            f.set_attr_i64("reduction_modes", c.modes_kept as i64)?;
            f.set_attr_i64("reduction_checked_case", c.case.map_or(-1, |i| i as i64))?;
            f.set_attr_f64("reduction_max_relative_error", c.max_relative_error)?;
        }
        {
            let s = f.group("sweep")?;
            s.write_str("toml", &self.sweep_text)?;
            s.write_str("base_toml", &self.base_text)?;
        }
        let g = f.group("table")?;
        let n = self.rows.len();
        let (np, na, nl) = self.shape();
        g.write_i64(
            "case_index",
            &self.rows.iter().map(|r| r.index as i64).collect::<Vec<_>>(),
            &[n],
            "1",
            "case index in the whole sweep (cartesian: last parameter fastest)",
        )?;
        g.write_str_list("parameters", &self.parameters)?;
        g.write_str_list("actuators", &self.actuators)?;
        g.write_str_list("links", &self.links)?;
        {
            let inp = g.group("inputs")?;
            for (k, p) in self.parameters.iter().enumerate() {
                let col: Vec<f64> = self.rows.iter().map(|r| r.inputs[k]).collect();
                let name = column_name(p);
                inp.write_f64(&name, &col, &[n], &self.units[k], &format!("swept case field `{p}`"))?;
            }
        }
        let flat = |f: &dyn Fn(&Row) -> &[f64]| -> Vec<f64> { self.rows.iter().flat_map(|r| f(r).to_vec()).collect() };
        g.write_f64(
            "net_power",
            &flat(&|r| &r.net_power),
            &[n, na],
            "W",
            "net mean power into the beam per actuator (columns: `actuators`)",
        )?;
        g.write_f64(
            "mean_power",
            &flat(&|r| &r.mean_power),
            &[n, nl],
            "W",
            "mean power into the beam at each link's foot (columns: `links`)",
        )?;
        g.write_f64(
            "force_amplitude",
            &flat(&|r| &r.force_amplitude),
            &[n, nl],
            "N",
            "amplitude of the transmitted force at the drive's fundamental per link (columns: `links`)",
        )?;
        g.write_f64(
            "beam_dissipation",
            &self.rows.iter().map(|r| r.beam_dissipation).collect::<Vec<_>>(),
            &[n],
            "W",
            "mean power dissipated by the beam's damping",
        )?;
        g.write_f64(
            "balance_error",
            &self.rows.iter().map(|r| r.balance_error).collect::<Vec<_>>(),
            &[n],
            "1",
            "relative energy-balance error (net input vs beam dissipation)",
        )?;
        let _ = np;
        drop(g);
        f.finish()
    }

    /// The table as tidy CSV: one row per case, columns named as the HDF5 datasets
    /// (`inputs/<parameter>`, `net_power <actuator>`, `mean_power <link>`, …) with units.
    pub fn csv_table(&self) -> crate::io::csv::Table {
        use crate::io::csv::{Column, Table};
        let mut t = Table::default();
        t.push(Column::int("case_index", self.rows.iter().map(|r| r.index as i64).collect()));
        for (k, p) in self.parameters.iter().enumerate() {
            t.push(Column::num(
                format!("inputs/{}", column_name(p)),
                &self.units[k],
                self.rows.iter().map(|r| r.inputs[k]).collect(),
            ));
        }
        let per = |name: &str, unit: &str, labels: &[String], f: &dyn Fn(&Row) -> &[f64]| -> Vec<Column> {
            labels
                .iter()
                .enumerate()
                .map(|(j, l)| Column::num(format!("{name} {l}"), unit, self.rows.iter().map(|r| f(r)[j]).collect()))
                .collect()
        };
        t.columns.extend(per("net_power", "W", &self.actuators, &|r| &r.net_power));
        t.columns.extend(per("mean_power", "W", &self.links, &|r| &r.mean_power));
        t.columns.extend(per("force_amplitude", "N", &self.links, &|r| &r.force_amplitude));
        t.push(Column::num("beam_dissipation", "W", self.rows.iter().map(|r| r.beam_dissipation).collect()));
        t.push(Column::num("balance_error", "1", self.rows.iter().map(|r| r.balance_error).collect()));
        t
    }

    /// Reads a table written by [`write`](Self::write).
    pub fn read(path: &Path) -> Result<SweepTable> {
        let file = path.display().to_string();
        let not_a_table =
            |why: &str| Error::input(&file, "kind", format!("not a beamflow sweep table{why}; it is left as it is"));
        if !is_hdf5(path)? {
            return Err(not_a_table(" (not an HDF5 file)"));
        }
        let r = ResultsReader::open(path)?;
        if r.attr_str("/", "kind").ok().as_deref() != Some("sweep table") {
            return Err(not_a_table(""));
        }
        let shard = Shard::parse(&r.attr_str("/", "shard")?, &file, "shard")?;
        let parameters = r.read_str_list("table/parameters")?;
        let actuators = r.read_str_list("table/actuators")?;
        let links = r.read_str_list("table/links")?;
        let (idx, _) = r.read_i64("table/case_index")?;
        let n = idx.len();
        let mut inputs = Vec::new();
        let mut units = Vec::new();
        for p in &parameters {
            let name = format!("table/inputs/{}", column_name(p));
            inputs.push(r.read_f64(&name)?.0);
            units.push(r.attr_str(&name, "unit")?);
        }
        let read2 = |name: &str, cols: usize| -> Result<Vec<f64>> {
            let (v, shape) = r.read_f64(&format!("table/{name}"))?;
            if shape != [n, cols] {
                return Err(Error::input(
                    &file,
                    format!("table/{name}"),
                    format!("shape {shape:?}, expected [{n}, {cols}]"),
                ));
            }
            Ok(v)
        };
        let net = read2("net_power", actuators.len())?;
        let mean = read2("mean_power", links.len())?;
        let force = read2("force_amplitude", links.len())?;
        let diss = r.read_f64("table/beam_dissipation")?.0;
        let bal = r.read_f64("table/balance_error")?.0;
        let (na, nl) = (actuators.len(), links.len());
        let rows = (0..n)
            .map(|j| Row {
                index: idx[j] as usize,
                inputs: inputs.iter().map(|c| c[j]).collect(),
                net_power: net[j * na..(j + 1) * na].to_vec(),
                mean_power: mean[j * nl..(j + 1) * nl].to_vec(),
                force_amplitude: force[j * nl..(j + 1) * nl].to_vec(),
                beam_dissipation: diss[j],
                balance_error: bal[j],
            })
            .collect();
        let damping = match (r.attr_f64("/", "cached_rayleigh_a0"), r.attr_f64("/", "cached_rayleigh_a1")) {
            (Ok(a0), Ok(a1)) => Some((a0, a1)),
            _ => None,
        };
        let reduction = match r.attr_f64("/", "reduction_cutoff_hz") {
            Ok(cutoff_hz) => Some(ReductionCheck {
                cutoff_hz,
                modes_kept: r.attr_i64("/", "reduction_modes")? as usize,
                case: usize::try_from(r.attr_i64("/", "reduction_checked_case")?).ok(),
                max_relative_error: r.attr_f64("/", "reduction_max_relative_error")?,
            }),
            Err(_) => None,
        };
        Ok(SweepTable {
            title: r.attr_str("/", "title")?,
            sweep_file: r.attr_str("/", "sweep_file")?,
            sweep_text: r.read_str("sweep/toml")?,
            base_text: r.read_str("sweep/base_toml")?,
            hash: r.attr_str("/", "sweep_hash")?,
            total_cases: r.attr_i64("/", "total_cases")? as usize,
            shard,
            analysis: r.attr_str("/", "analysis")?,
            harmonics: r.attr_i64("/", "harmonics")? as usize,
            samples_per_period: r.attr_i64("/", "samples_per_period")? as usize,
            damping,
            reduction,
            best: r.attr_i64("/", "best")? as usize,
            parameters,
            units,
            actuators,
            links,
            rows,
        })
    }
}

/// The dataset name of a parameter's column: the path with `[i]` written `_i`
/// (`actuator[0].x_e` → `actuator_0.x_e`), because h5dump reads brackets in a dataset
/// name as a selection.
pub fn column_name(path: &str) -> String {
    path.replace('[', "_").replace(']', "")
}

/// Joins shard tables (`(file name, table)`) into the whole sweep's table, sorted by case
/// index. They must come from the same sweep (same hash) and together hold every case
/// exactly once.
pub fn merge(shards: &[(String, SweepTable)]) -> Result<SweepTable> {
    let (first_file, first) = shards.first().ok_or_else(|| Error::input("<cli>", "SHARD", "no shard files given"))?;
    let mut by_index: BTreeMap<usize, (&str, &Row)> = BTreeMap::new();
    for (file, t) in shards {
        if t.hash != first.hash {
            return Err(Error::input(
                file,
                "sweep_hash",
                format!(
                    "comes from a different sweep ({}) than {first_file} ({}): the sweep file, its base case or \
                     the beamflow version differ",
                    t.hash, first.hash
                ),
            ));
        }
        if t.total_cases != first.total_cases || t.shape() != first.shape() {
            return Err(Error::input(file, "table", format!("does not have the layout of {first_file}")));
        }
        for row in &t.rows {
            if let Some((other, _)) = by_index.insert(row.index, (file, row)) {
                return Err(Error::input(
                    file,
                    "case_index",
                    format!("case {} is also in {other}: a shard was given twice or shards overlap", row.index),
                ));
            }
        }
    }
    let missing: Vec<usize> = (0..first.total_cases).filter(|i| !by_index.contains_key(i)).collect();
    if !missing.is_empty() {
        let shown: Vec<String> = missing.iter().take(8).map(|i| i.to_string()).collect();
        return Err(Error::input(
            first_file,
            "case_index",
            format!(
                "{} of {} cases are missing from the shards given (e.g. {}{}): is a shard missing or unfinished?",
                missing.len(),
                first.total_cases,
                shown.join(", "),
                if missing.len() > 8 { ", …" } else { "" }
            ),
        ));
    }
    if let Some(i) = by_index.keys().find(|&&i| i >= first.total_cases) {
        return Err(Error::input(
            first_file,
            "case_index",
            format!("case {i} is beyond the sweep's {} cases", first.total_cases),
        ));
    }
    let mut out = first.clone();
    out.shard = Shard::ALL;
    out.reduction = shards.iter().fold(None, |w, (_, t)| ReductionCheck::worse(w, t.reduction.clone()));
    out.rows = by_index.into_values().map(|(_, r)| r.clone()).collect();
    Ok(out)
}

/// Reads shard files and merges them.
pub fn merge_files(paths: &[impl AsRef<Path>]) -> Result<SweepTable> {
    let tables = paths
        .iter()
        .map(|p| Ok((p.as_ref().display().to_string(), SweepTable::read(p.as_ref())?)))
        .collect::<Result<Vec<_>>>()?;
    merge(&tables)
}

/// Whether the file at `path` starts with HDF5's signature (beamflow writes no user block),
/// read before the HDF5 library reports another file as a stack of its own errors.
fn is_hdf5(path: &Path) -> Result<bool> {
    use std::io::Read;
    crate::input_file::regular_file(path)?;
    let mut head = [0u8; 8];
    let n = std::fs::File::open(path)
        .and_then(|mut f| f.read(&mut head))
        .map_err(|e| Error::input(path.display().to_string(), "file", e.to_string()))?;
    Ok(n == 8 && head == *b"\x89HDF\r\n\x1a\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_partition_round_robin() {
        let s = Shard::parse("2/3", "<cli>", "--shard").unwrap();
        assert_eq!(s.indices(8), vec![1, 4, 7]);
        let mut all: Vec<usize> = (1..=3).flat_map(|k| Shard { k, n: 3 }.indices(8)).collect();
        all.sort();
        assert_eq!(all, (0..8).collect::<Vec<_>>());
        for bad in ["0/3", "4/3", "1/0", "a/3", "3", ""] {
            let e = Shard::parse(bad, "<cli>", "--shard").unwrap_err().to_string();
            assert!(e.contains("<cli>") && e.contains("--shard"), "{e}");
        }
    }

    #[test]
    fn part_files_round_trip_and_detect_damage() {
        let row = Row {
            index: 42,
            inputs: vec![0.15, 60.0],
            net_power: vec![1e-3],
            mean_power: vec![1e-3, -2.0, f64::NAN],
            force_amplitude: vec![1.0, 2.0, 3.0],
            beam_dissipation: 1e-3,
            balance_error: 1e-12,
        };
        let hash = "0123456789abcdef";
        let b = encode_part(&row, hash);
        let back = decode_part(&b, hash, (2, 1, 3)).unwrap();
        assert!(back.bitwise_eq(&row));
        assert!(decode_part(&b, "0123456789abcdee", (2, 1, 3)).is_none());
        assert!(decode_part(&b, hash, (2, 1, 2)).is_none());
        assert!(decode_part(&b[..b.len() - 1], hash, (2, 1, 3)).is_none());
        let mut flipped = b.clone();
        flipped[40] ^= 1;
        assert!(decode_part(&flipped, hash, (2, 1, 3)).is_none());
    }
}
