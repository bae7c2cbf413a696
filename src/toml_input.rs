//! TOML input files (cases, sweeps, optimisations, meshes) read into their schemas, with
//! a mistake named the way the user wrote it: the dotted field (`actuator[0].voltage.amplitud`),
//! its line, what is wrong, and what to do — the nearest field name for a misspelt key, the
//! unit rule for a value written with a unit, the right command for the wrong kind of file.
//!
//! The schemas are plain serde types; `serde_path_to_error` follows the deserialiser down
//! and reports where it stopped, and the TOML deserialiser's span gives the line.

use serde::de::DeserializeOwned;

use crate::error::{Error, Result};

/// The kinds of TOML file beamflow reads, each with the command or place that takes it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Case,
    Sweep,
    Optimization,
    Mesh,
    PlateMesh,
}

impl Kind {
    /// What a file of this kind is and what to do with it, for a file given in the wrong place.
    fn advice(self) -> &'static str {
        match self {
            Kind::Case => "this is a case file: use `beamflow run` (or `beamflow check`) on it",
            Kind::Sweep => "this is a sweep file: use `beamflow sweep` on it",
            Kind::Optimization => "this is an optimisation file: use `beamflow optimize` on it",
            Kind::Mesh => "this is a mesh file: name it in a case as `[beam.mesh] file = \"…\"`",
            Kind::PlateMesh => "this is a plate's mesh file: name it in a case as `[plate.mesh] file = \"…\"`",
        }
    }

    /// The kind a document's top-level keys point to, if they point to one.
    fn of(doc: &toml::Table) -> Option<Kind> {
        let has = |keys: &[&str]| keys.iter().any(|k| doc.contains_key(*k));
        if has(&["parameter", "combine"]) {
            Some(Kind::Sweep)
        } else if has(&["variable", "objective", "search", "constraint"]) {
            Some(Kind::Optimization)
        } else if doc.contains_key("nodes") && doc.contains_key("format") {
            Some(Kind::Mesh)
        } else if has(&["x", "y"]) && doc.contains_key("format") {
            Some(Kind::PlateMesh)
        } else if has(&["beam", "actuator", "analysis", "sensor", "load", "damping", "measurement"]) {
            Some(Kind::Case)
        } else {
            None
        }
    }
}

/// At least how many values the top-level array `key` of a TOML text holds, counted from
/// its commas without parsing the text: a mesh too fine for an analysis is refused before
/// the parser's document (about twenty bytes per byte of text) is built. Commas in
/// comments are skipped; the count is exact for a well-formed array of numbers. Only lines
/// before the first table header are searched for the key (a table's `x` is not the
/// document's).
pub fn values_at_least(text: &str, key: &str) -> usize {
    let mut lines = text.lines().take_while(|l| !l.trim_start().starts_with('['));
    let Some(start) = lines.position(|l| {
        let l = l.trim_start();
        l.strip_prefix(key).is_some_and(|r| r.trim_start().starts_with('='))
    }) else {
        return 0;
    };
    // Values: one per comma, plus one if a value follows the last comma.
    let (mut commas, mut pending, mut in_array) = (0usize, false, false);
    for line in text.lines().skip(start) {
        let code = line.split('#').next().unwrap_or("");
        for c in code.chars() {
            match c {
                '[' => in_array = true,
                ',' if in_array => (commas, pending) = (commas + 1, false),
                ']' if in_array => return commas + usize::from(pending),
                c if in_array && !c.is_whitespace() => pending = true,
                _ => {}
            }
        }
    }
    commas + usize::from(pending)
}

/// `text` (the file `file`, of kind `kind`) read into `T`.
pub fn parse<T: DeserializeOwned>(text: &str, file: &str, kind: Kind) -> Result<T> {
    serde_path_to_error::deserialize(toml::Deserializer::new(text)).map_err(|e| explain(text, file, kind, e))
}

/// A document already parsed (built in code, or from Python) read into `T`; mistakes are
/// named as [`parse`] names them, without lines.
pub fn from_value<T: DeserializeOwned>(doc: toml::Table, file: &str, kind: Kind) -> Result<T> {
    serde_path_to_error::deserialize(toml::Value::Table(doc.clone())).map_err(|e| explain_in(&doc, None, file, kind, e))
}

/// The error of a document that did not fit its schema, said as the user wrote it.
fn explain(text: &str, file: &str, kind: Kind, e: serde_path_to_error::Error<toml::de::Error>) -> Error {
    match text.parse::<toml::Table>() {
        Ok(doc) => explain_in(&doc, Some(text), file, kind, e),
        // A document that is not TOML at all: the parser's own message has line and column.
        Err(_) => Error::Parse { file: file.to_string(), message: e.into_inner().to_string().trim_end().to_string() },
    }
}

/// [`explain`] for the document `doc`, parsed from `text` if given (for line numbers).
fn explain_in(
    doc: &toml::Table,
    text: Option<&str>,
    file: &str,
    kind: Kind,
    e: serde_path_to_error::Error<toml::de::Error>,
) -> Error {
    let path = e.path().to_string();
    let inner = e.into_inner();
    if let Some(other) = Kind::of(doc).filter(|&k| k != kind) {
        return Error::input(file, "<file>", other.advice());
    }
    let message = inner.message().trim_end();
    let mut line = text.zip(inner.span()).map(|(t, s)| line_of(t, s.start));
    let mut field = if path.is_empty() || path == "." { String::new() } else { path };
    // Tagged enums (a drive's `kind`, an analysis's `type`) are read from a buffer that
    // has lost the key and its span: the error stops at the table. Name the key in it.
    if let Some(key) = table_at(doc, &field).and_then(|t| culprit(t, message)) {
        line = text.zip(line).map(|(t, header)| key_line(t, header, &key));
        field = if field.is_empty() { key } else { format!("{field}.{key}") };
    }
    let field = if field.is_empty() { "<file>".to_string() } else { field };
    let line = line.map(|l| format!("line {l}: ")).unwrap_or_default();
    Error::input(file, field, format!("{line}{message}{}", hint(message)))
}

/// The table at a dotted path as `serde_path_to_error` prints it (`actuator[0].voltage`).
fn table_at<'a>(doc: &'a toml::Table, path: &str) -> Option<&'a toml::Table> {
    let mut value: Option<&toml::Value> = None;
    let mut table = doc;
    for part in path.split('.').filter(|p| !p.is_empty()) {
        let mut pieces = part.split('[');
        let key = pieces.next()?;
        let mut v = table.get(key)?;
        for index in pieces {
            v = v.as_array()?.get(index.trim_end_matches(']').parse::<usize>().ok()?)?;
        }
        value = Some(v);
        table = v.as_table()?;
    }
    match value {
        Some(v) => v.as_table(),
        None => Some(doc),
    }
}

/// The key of `table` that a schema error is about: the unknown field it names, or the
/// one key holding the string it could not take.
fn culprit(table: &toml::Table, message: &str) -> Option<String> {
    if let Some(rest) = message.strip_prefix("unknown field `") {
        let name = rest.split('`').next()?;
        return table.contains_key(name).then(|| name.to_string());
    }
    let rest = message.strip_prefix("invalid type: string \"")?;
    let (bad, _) = rest.split_once("\", expected")?;
    let mut keys = table.iter().filter(|(_, v)| v.as_str() == Some(bad)).map(|(k, _)| k);
    match (keys.next(), keys.next()) {
        (Some(k), None) => Some(k.clone()),
        _ => None,
    }
}

/// The line of `key = …` in the table whose header is on line `header`, else `header`.
fn key_line(text: &str, header: usize, key: &str) -> usize {
    let is_key = |l: &str| {
        let l = l.trim_start();
        let rest = l.strip_prefix(key).or_else(|| l.strip_prefix(&format!("\"{key}\"")));
        rest.is_some_and(|r| r.trim_start().starts_with('='))
    };
    text.lines()
        .enumerate()
        .skip(header)
        .take_while(|(_, l)| !l.trim_start().starts_with('['))
        .find(|(_, l)| is_key(l))
        .map_or(header, |(i, _)| i + 1)
}

/// 1-based line of the byte `offset` in `text`.
fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())].iter().filter(|&&b| b == b'\n').count() + 1
}

/// What to do about a schema error, from serde's wording of it.
fn hint(message: &str) -> String {
    if let Some(rest) = message.strip_prefix("unknown field `") {
        let (name, expected) = rest.split_once('`').unwrap_or((rest, ""));
        return nearest(name, &quoted(expected)).map(|n| format!("; did you mean `{n}`?")).unwrap_or_default();
    }
    if let Some(rest) = message.strip_prefix("unknown variant `") {
        let (name, expected) = rest.split_once('`').unwrap_or((rest, ""));
        return nearest(name, &quoted(expected)).map(|n| format!("; did you mean `{n}`?")).unwrap_or_default();
    }
    if message.starts_with("invalid type: string")
        && ["f64", "u64", "usize", "integer", "float"].iter().any(|t| message.contains(t))
    {
        return "; values are plain numbers in SI units, without a unit (60 Hz is `frequency = 60.0`, 150 mm is `0.15`)"
            .into();
    }
    String::new()
}

/// The names between backticks in serde's "expected one of `a`, `b`" list.
fn quoted(text: &str) -> Vec<&str> {
    text.split('`').skip(1).step_by(2).collect()
}

/// The candidate closest to `name`, if it is close enough to be a slip of the keyboard.
fn nearest<'a>(name: &str, candidates: &[&'a str]) -> Option<&'a str> {
    candidates
        .iter()
        .map(|c| (strsim::damerau_levenshtein(name, c), *c))
        .filter(|&(d, c)| d <= 2.max(c.len() / 3))
        .min_by_key(|&(d, _)| d)
        .map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;

    #[derive(Deserialize, Debug)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Voltage {
        amplitude: f64,
        #[serde(default)]
        frequency: f64,
    }

    #[derive(Deserialize, Debug)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Actuator {
        x_e: f64,
        voltage: Voltage,
    }

    #[derive(Deserialize, Debug)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Doc {
        #[serde(default)]
        actuator: Vec<Actuator>,
    }

    fn error(text: &str) -> String {
        parse::<Doc>(text, "c.toml", Kind::Case).unwrap_err().to_string()
    }

    #[test]
    fn a_misspelt_key_is_named_by_its_dotted_path_and_line_with_the_nearest_name() {
        let e = error("[[actuator]]\nx_e = 0.1\n[actuator.voltage]\namplitud = 3.0\n");
        assert!(e.contains("c.toml") && e.contains("`actuator[0].voltage.amplitud`"), "{e}");
        assert!(e.contains("line 4") && e.contains("did you mean `amplitude`?"), "{e}");
    }

    #[test]
    fn a_value_with_a_unit_gets_the_unit_rule() {
        let e = error("[[actuator]]\nx_e = 0.1\n[actuator.voltage]\namplitude = 3.0\nfrequency = \"60 Hz\"\n");
        assert!(e.contains("`actuator[0].voltage.frequency`") && e.contains("line 5"), "{e}");
        assert!(e.contains("SI units, without a unit"), "{e}");
    }

    /// A tagged enum, as drives are: serde reads it from a buffer without keys or spans.
    #[derive(Deserialize, Debug)]
    #[serde(tag = "kind", deny_unknown_fields)]
    #[allow(dead_code)]
    enum Drive {
        #[serde(rename = "sine")]
        Sine { amplitude: f64, frequency: f64 },
    }

    #[derive(Deserialize, Debug)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Driven {
        drive: Drive,
    }

    #[test]
    fn keys_inside_tagged_tables_are_found_by_name() {
        let text = "[drive]\nkind = \"sine\"\namplitud = 1.0\nfrequency = 2.0\n";
        let e = parse::<Driven>(text, "d.toml", Kind::Case).unwrap_err().to_string();
        assert!(e.contains("`drive.amplitud`") && e.contains("line 3"), "{e}");
        let text = "[drive]\nkind = \"sine\"\namplitude = 1.0\nfrequency = \"2 Hz\"\n";
        let e = parse::<Driven>(text, "d.toml", Kind::Case).unwrap_err().to_string();
        assert!(e.contains("`drive.frequency`") && e.contains("line 4") && e.contains("without a unit"), "{e}");
    }

    #[test]
    fn the_wrong_kind_of_file_gets_the_right_command() {
        let e = error("base = \"a.toml\"\n[[parameter]]\npath = \"x\"\n");
        assert!(e.contains("this is a sweep file: use `beamflow sweep`"), "{e}");
        let e = error("base = \"a.toml\"\n[[variable]]\npath = \"x\"\n");
        assert!(e.contains("use `beamflow optimize`"), "{e}");
    }

    #[test]
    fn syntax_errors_keep_the_parsers_location() {
        let e = error("[[actuator]\n");
        assert!(e.contains("c.toml") && e.contains("line 1"), "{e}");
    }

    #[test]
    fn documents_built_in_code_are_named_by_path_without_lines() {
        let doc: toml::Table = "[[actuator]]\nx_e = 0.1\n[actuator.voltage]\namplitud = 3.0\n".parse().unwrap();
        let e = from_value::<Doc>(doc, "<dict>", Kind::Case).unwrap_err().to_string();
        assert!(e.contains("`actuator[0].voltage.amplitud`") && !e.contains("line"), "{e}");
    }

    #[test]
    fn array_values_are_counted_before_the_first_table() {
        let text = "format = \"m\"\n# a, b, c\nx = [0.0, 0.1, # p, q\n 0.2,\n 0.3]\n[[region]]\ny = [1, 2, 3]\n";
        assert_eq!(values_at_least(text, "x"), 4);
        assert_eq!(values_at_least(text, "y"), 0, "a table's key is not the document's");
        assert_eq!(values_at_least("x = [0.0, 0.1, 0.2,]\n", "x"), 3, "a trailing comma adds no value");
        assert_eq!(values_at_least("xs = [0.0, 0.1]\n", "x"), 0);
    }

    #[test]
    fn far_names_get_no_suggestion() {
        assert_eq!(nearest("zzzzzz", &["amplitude", "frequency"]), None);
        assert_eq!(nearest("frequncy", &["amplitude", "frequency"]), Some("frequency"));
    }
}
