//! Case fields by dotted path (`actuator[0].x_e`, `actuator[0].voltage.frequency`,
//! `damping.zeta`, …): parsing a path, reading and setting it on a case's TOML document,
//! and the unit of the field it names. Sweeps and optimisations vary cases through these.

/// One segment of a dotted field path: `actuator[0]` is key `actuator`, index 0.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Segment {
    pub key: String,
    pub index: Option<usize>,
}

/// Parses `actuator[0].voltage.frequency` into segments.
pub fn parse_path(path: &str) -> std::result::Result<Vec<Segment>, String> {
    if path.trim().is_empty() {
        return Err("the path is empty".into());
    }
    let mut out = Vec::new();
    for part in path.split('.') {
        let (key, index) = match part.find('[') {
            Some(b) => {
                let rest = &part[b + 1..];
                let idx = rest
                    .strip_suffix(']')
                    .and_then(|d| d.parse::<usize>().ok())
                    .ok_or_else(|| format!("`{part}`: an index must be written `name[N]` with N ≥ 0"))?;
                (&part[..b], Some(idx))
            }
            None => (part, None),
        };
        if key.is_empty() || !key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return Err(format!("`{part}` is not a field name (letters, digits and `_`, optionally `[N]`)"));
        }
        out.push(Segment { key: key.to_string(), index });
    }
    Ok(out)
}

/// Sets `path` in a TOML document to `value`, creating missing tables on the way. Arrays
/// (e.g. `actuator`) must exist and hold the index: a sweep varies cases, it does not add
/// actuators. Setting a point's `node` drops its `at`: the point moves to that node.
pub fn set_path(root: &mut toml::Value, path: &[Segment], value: toml::Value) -> std::result::Result<(), String> {
    let mut cur = root;
    let mut walked = String::new();
    for (n, seg) in path.iter().enumerate() {
        let last = n + 1 == path.len();
        let table = cur.as_table_mut().ok_or_else(|| format!("`{walked}` in the base case is a value, not a table"))?;
        if !walked.is_empty() {
            walked.push('.');
        }
        walked.push_str(&seg.key);
        match seg.index {
            None if last => {
                // A point moved to a node leaves the position the base case gave it.
                if seg.key == "node" {
                    table.remove("at");
                }
                table.insert(seg.key.clone(), value);
                return Ok(());
            }
            None => {
                cur = table.entry(seg.key.clone()).or_insert_with(|| toml::Value::Table(Default::default()));
            }
            Some(i) => {
                let arr = table
                    .get_mut(&seg.key)
                    .ok_or_else(|| format!("the base case has no `{walked}` to index"))?
                    .as_array_mut()
                    .ok_or_else(|| format!("`{walked}` in the base case is not an array"))?;
                let len = arr.len();
                let slot = arr
                    .get_mut(i)
                    .ok_or_else(|| format!("the base case has {len} entries in `{walked}`, not {}", i + 1))?;
                walked.push_str(&format!("[{i}]"));
                if last {
                    *slot = value;
                    return Ok(());
                }
                cur = slot;
            }
        }
    }
    Ok(())
}

/// The value at `path`, if the base case has one.
pub fn get_path<'a>(root: &'a toml::Value, path: &[Segment]) -> Option<&'a toml::Value> {
    let mut cur = root;
    for seg in path {
        cur = cur.as_table()?.get(&seg.key)?;
        if let Some(i) = seg.index {
            cur = cur.as_array()?.get(i)?;
        }
    }
    Some(cur)
}

/// The unit of a case field, from its last name (physics spec and case schema).
pub fn unit_of(path: &str) -> &'static str {
    let name = path.rsplit('.').next().unwrap_or(path);
    let name = name.split('[').next().unwrap_or(name);
    match name {
        "x_e" | "a" | "e" | "x" | "at" | "length" | "length_x" | "length_y" | "width" | "thickness" | "h0" => "m",
        "direction" => "deg",
        "poisson_ratio" => "1",
        "frequency" | "f_start" | "f_end" => "Hz",
        "amplitude" | "offset" | "from" | "to" => "V",
        "phase" => "rad",
        "m_t" | "m_b" | "m_p" | "mass" => "kg",
        "j_b" | "rotary_inertia" => "kg m^2",
        "k_l" | "k_l_right" | "k_p" | "k_w" | "stiffness" => "N/m",
        "c_l" | "c_l_right" | "c_p" | "damping" => "N s/m",
        "k_theta" => "N m/rad",
        "d_p" => "m/V",
        "beta" | "gamma" => "1/V",
        "alpha" | "zeta" | "ratios" | "elements" | "modes" | "node" => "1",
        "youngs_modulus" => "Pa",
        "density" => "kg/m^3",
        "a0" => "1/s",
        "a1" | "duration" | "time" | "rise_time" => "s",
        _ => "?",
    }
}

/// A case field that a study varies: its path, whether it is written as a TOML integer, and
/// its unit.
#[derive(Clone, Debug)]
pub struct Field {
    /// Dotted case-field path, e.g. `actuator[0].x_e`.
    pub path: String,
    pub segments: Vec<Segment>,
    /// Written as a TOML integer (the field is an integer, e.g. `beam.mesh.elements`).
    pub integer: bool,
    /// SI unit, from the field name (`"1"` dimensionless, `"?"` unknown).
    pub unit: &'static str,
}

impl Field {
    /// Parses `path`; `integer` from the base case's value there (see [`get_path`]).
    pub fn parse(path: &str) -> std::result::Result<Field, String> {
        Ok(Field { path: path.to_string(), segments: parse_path(path)?, integer: false, unit: unit_of(path) })
    }

    /// The actuator whose drive this field sets, if its path starts with
    /// `actuator[a].voltage.`: such a field changes what the stack is driven with, not
    /// the model that is assembled.
    pub fn drive_of(&self) -> Option<usize> {
        match self.segments.as_slice() {
            [a, v, _, ..] if a.key == "actuator" && v.key == "voltage" && v.index.is_none() => a.index,
            _ => None,
        }
    }

    /// The value as TOML.
    pub fn toml(&self, v: f64) -> toml::Value {
        if self.integer {
            toml::Value::Integer(v as i64)
        } else {
            toml::Value::Float(v)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_parse() {
        assert_eq!(
            parse_path("actuator[0].voltage.frequency").unwrap(),
            vec![
                Segment { key: "actuator".into(), index: Some(0) },
                Segment { key: "voltage".into(), index: None },
                Segment { key: "frequency".into(), index: None },
            ]
        );
        for bad in ["", "a..b", "a[x].b", "a[0", "a b", "[0]"] {
            assert!(parse_path(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn set_path_creates_tables_but_not_array_entries() {
        let mut v: toml::Value = toml::from_str("[[actuator]]\nx_e = 0.1\n").unwrap();
        set_path(&mut v, &parse_path("damping.zeta").unwrap(), toml::Value::Float(0.02)).unwrap();
        set_path(&mut v, &parse_path("actuator[0].voltage.frequency").unwrap(), toml::Value::Float(60.0)).unwrap();
        assert_eq!(v["damping"]["zeta"].as_float(), Some(0.02));
        assert_eq!(v["actuator"][0]["voltage"]["frequency"].as_float(), Some(60.0));
        let e = set_path(&mut v, &parse_path("actuator[1].x_e").unwrap(), toml::Value::Float(0.2)).unwrap_err();
        assert!(e.contains("1 entries in `actuator`"), "{e}");
        let e = set_path(&mut v, &parse_path("sensor[0].x").unwrap(), toml::Value::Float(0.2)).unwrap_err();
        assert!(e.contains("no `sensor`"), "{e}");
    }
}
