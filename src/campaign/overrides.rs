//! Dotted keys into a scenario's TOML: `law.k_f_kg_per_m_s2`, `satellites.count`, `threats.0.speed_mps`
//! (a number indexes an array), and setting a value there.
//!
//! A campaign changes a scenario by editing its TOML table, never its typed structures: the edited table
//! is then read and validated by the scenario layer exactly as a file would be, so a key a campaign sets
//! is checked by the same code, with the same messages, as the key written in a scenario file.
//!
//! Setting a value ([`apply`]): tables on the way that the scenario does not have are created (a
//! scenario without `[sensing]` can still have `sensing.position_noise_m` set); an array element must
//! exist (`threats.3` of a scenario with two threats is refused); a table value merges into the table
//! at that key key by key (so `law.k = 1` and `law = { k = 1 }` do the same); any other value (number,
//! string, boolean, array) replaces the value at that key.

use std::fmt;

/// One step of a dotted key: a table key or an array index.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Segment {
    /// A key of a table.
    Key(String),
    /// An element of an array, from 0.
    Index(usize),
}

/// A dotted key, parsed into its segments.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct KeyPath {
    text: String,
    segments: Vec<Segment>,
}

impl KeyPath {
    /// Parses `a.b.0.c`: segments separated by `.`, each made of letters, digits, `_` and `-`; a segment
    /// of digits only is an array index. The error says what is allowed.
    pub fn parse(text: &str) -> Result<Self, String> {
        let mut segments = Vec::new();
        for part in text.split('.') {
            if part.is_empty()
                || !part
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
            {
                return Err(format!(
                    "`{text}` is not a dotted key (allowed: keys of letters, digits, `_` and `-` \
                     separated by `.`, an array element by its index from 0, e.g. `threats.0.speed_mps`)"
                ));
            }
            segments.push(if part.chars().all(|c| c.is_ascii_digit()) {
                Segment::Index(
                    part.parse()
                        .map_err(|_| format!("`{text}`: array index `{part}` is too large"))?,
                )
            } else {
                Segment::Key(part.to_string())
            });
        }
        if matches!(segments.first(), Some(Segment::Index(_))) {
            return Err(format!(
                "`{text}` starts with an array index (allowed: a scenario key first, e.g. `threats.0`)"
            ));
        }
        Ok(Self {
            text: text.to_string(),
            segments,
        })
    }

    /// The key as written.
    pub fn as_str(&self) -> &str {
        &self.text
    }

    /// The segments.
    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }

    /// Whether one key is the other or lies inside it (`law` and `law.k_f`): two such keys cannot both
    /// be set by one campaign.
    pub fn overlaps(&self, other: &KeyPath) -> bool {
        let n = self.segments.len().min(other.segments.len());
        self.segments[..n] == other.segments[..n]
    }
}

impl fmt::Display for KeyPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.text)
    }
}

/// Sets `value` at `path` in `table` (see the module documentation). The error says which part of the
/// path does not fit the scenario.
pub fn apply(table: &mut toml::Table, path: &KeyPath, value: &toml::Value) -> Result<(), String> {
    let segments = path.segments();
    let Some((Segment::Key(first), rest)) = segments.split_first() else {
        return Err(format!("`{path}` does not start with a key"));
    };
    if rest.is_empty() {
        merge_into(table, first, value);
        return Ok(());
    }
    let next_is_index = matches!(rest.first(), Some(Segment::Index(_)));
    if !table.contains_key(first) {
        if next_is_index {
            return Err(format!(
                "the scenario has no `{first}` (an array element is set only where the array has it)"
            ));
        }
        table.insert(first.clone(), toml::Value::Table(toml::Table::new()));
    }
    let mut node = table.get_mut(first).expect("inserted above");
    let mut walked = first.clone();
    for (k, segment) in rest.iter().enumerate() {
        let last = k + 1 == rest.len();
        let next_is_index = matches!(rest.get(k + 1), Some(Segment::Index(_)));
        node = match (segment, node) {
            (Segment::Key(key), toml::Value::Table(t)) => {
                if last {
                    merge_into(t, key, value);
                    return Ok(());
                }
                if !t.contains_key(key) {
                    if next_is_index {
                        return Err(format!(
                            "the scenario has no `{walked}.{key}` (an array element is set only where \
                             the array has it)"
                        ));
                    }
                    t.insert(key.clone(), toml::Value::Table(toml::Table::new()));
                }
                walked = format!("{walked}.{key}");
                t.get_mut(key).expect("inserted above")
            }
            (Segment::Index(i), toml::Value::Array(items)) => {
                let len = items.len();
                let Some(item) = items.get_mut(*i) else {
                    return Err(format!(
                        "`{walked}` has {len} element(s) in the scenario (allowed index: {})",
                        if len == 0 {
                            "none".to_string()
                        } else {
                            format!("0 to {}", len - 1)
                        }
                    ));
                };
                if last {
                    merge_value(item, value);
                    return Ok(());
                }
                walked = format!("{walked}.{i}");
                item
            }
            (Segment::Key(key), other) => {
                return Err(format!(
                    "`{walked}` is {} in the scenario, not a table: it has no key `{key}`",
                    article(other.type_str())
                ))
            }
            (Segment::Index(i), other) => {
                return Err(format!(
                    "`{walked}` is {} in the scenario, not an array: it has no element {i}",
                    article(other.type_str())
                ))
            }
        };
    }
    Ok(())
}

/// The value at `path` in `table`, if the table has it.
pub fn get<'a>(table: &'a toml::Table, path: &KeyPath) -> Option<&'a toml::Value> {
    let (Segment::Key(first), rest) = path.segments().split_first()? else {
        return None;
    };
    let mut node = table.get(first)?;
    for segment in rest {
        node = match (segment, node) {
            (Segment::Key(key), toml::Value::Table(t)) => t.get(key)?,
            (Segment::Index(i), toml::Value::Array(items)) => items.get(*i)?,
            _ => return None,
        };
    }
    Some(node)
}

/// Whether `found` (a value read back from a scenario) is what setting `value` made it: numbers by
/// value (an integer set on a float key reads back as a float), tables key by key for the keys `value`
/// sets (a table merges into the scenario's), arrays element by element, anything else equal.
pub fn holds(found: &toml::Value, value: &toml::Value) -> bool {
    use toml::Value::{Array, Float, Integer, Table};
    match (found, value) {
        (Integer(a), Integer(b)) => a == b,
        (Float(_) | Integer(_), Float(_) | Integer(_)) => {
            found.as_float().or(found.as_integer().map(|i| i as f64))
                == value.as_float().or(value.as_integer().map(|i| i as f64))
        }
        (Table(found), Table(value)) => value
            .iter()
            .all(|(k, v)| found.get(k).is_some_and(|f| holds(f, v))),
        (Array(found), Array(value)) => {
            found.len() == value.len() && found.iter().zip(value).all(|(f, v)| holds(f, v))
        }
        _ => found == value,
    }
}

/// `a table`, `an integer`.
fn article(type_name: &str) -> String {
    if type_name.starts_with(['a', 'e', 'i', 'o', 'u']) {
        format!("an {type_name}")
    } else {
        format!("a {type_name}")
    }
}

/// Sets `table[key]` to `value`, merging a table value into an existing table.
fn merge_into(table: &mut toml::Table, key: &str, value: &toml::Value) {
    match table.get_mut(key) {
        Some(existing) => merge_value(existing, value),
        None => {
            table.insert(key.to_string(), value.clone());
        }
    }
}

/// Replaces `existing` by `value`, or merges `value` into it key by key when both are tables.
fn merge_value(existing: &mut toml::Value, value: &toml::Value) {
    match (existing, value) {
        (toml::Value::Table(old), toml::Value::Table(new)) => {
            for (key, v) in new {
                merge_into(old, key, v);
            }
        }
        (existing, value) => *existing = value.clone(),
    }
}

/// The leaves of a table of overrides (a campaign's `[set]`): each non-table value with its dotted key,
/// nested tables walked (`[set.law] k = 1` and `"law.k" = 1` both give `law.k`). Keys in table order.
pub fn leaves(table: &toml::Table) -> Vec<(String, toml::Value)> {
    let mut out = Vec::new();
    collect_leaves("", table, &mut out);
    out
}

fn collect_leaves(prefix: &str, table: &toml::Table, out: &mut Vec<(String, toml::Value)>) {
    for (key, value) in table {
        let name = join(prefix, key);
        match value {
            toml::Value::Table(t) => collect_leaves(&name, t, out),
            other => out.push((name, other.clone())),
        }
    }
}

/// `prefix.key`, or `key` without a prefix.
pub fn join(prefix: &str, key: &str) -> String {
    if prefix.is_empty() {
        key.to_string()
    } else {
        format!("{prefix}.{key}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> toml::Table {
        toml::from_str(text).unwrap()
    }

    fn key(text: &str) -> KeyPath {
        KeyPath::parse(text).unwrap()
    }

    #[test]
    fn parses_keys_and_indices() {
        let k = key("threats.0.speed_mps");
        assert_eq!(
            k.segments(),
            [
                Segment::Key("threats".into()),
                Segment::Index(0),
                Segment::Key("speed_mps".into())
            ]
        );
        for bad in ["", "law..k", "law.k f", "0.law", "law."] {
            assert!(KeyPath::parse(bad).is_err(), "{bad}");
        }
        assert!(key("law").overlaps(&key("law.k")));
        assert!(key("law.k").overlaps(&key("law.k")));
        assert!(!key("law.k").overlaps(&key("law.kk")));
    }

    #[test]
    fn sets_creates_tables_merges_tables_and_replaces_the_rest() {
        let mut t = table(
            "duration_s = 10.0\n[law]\nname = \"hold\"\nk = 1.0\n[[threats]]\nspeed_mps = 1.0\n",
        );
        apply(&mut t, &key("law.k"), &toml::Value::Float(2.0)).unwrap();
        apply(&mut t, &key("sensing.range_m"), &toml::Value::Float(5.0)).unwrap();
        apply(
            &mut t,
            &key("threats.0.speed_mps"),
            &toml::Value::Integer(3),
        )
        .unwrap();
        apply(
            &mut t,
            &key("law"),
            &toml::Value::Table(table("damping = 0.5")),
        )
        .unwrap();
        let expected = table(
            "duration_s = 10.0\n[law]\nname = \"hold\"\nk = 2.0\ndamping = 0.5\n[sensing]\nrange_m = 5.0\n\
             [[threats]]\nspeed_mps = 3\n",
        );
        assert_eq!(t, expected);
    }

    #[test]
    fn refuses_paths_that_do_not_fit() {
        let mut t = table("duration_s = 10.0\n[[threats]]\nspeed_mps = 1.0\n");
        let v = toml::Value::Float(1.0);
        let e = apply(&mut t, &key("threats.1.speed_mps"), &v).unwrap_err();
        assert!(e.contains("1 element(s)") && e.contains("0 to 0"), "{e}");
        let e = apply(&mut t, &key("obstacles.0.radius_m"), &v).unwrap_err();
        assert!(e.contains("no `obstacles`"), "{e}");
        let e = apply(&mut t, &key("duration_s.x"), &v).unwrap_err();
        assert!(e.contains("`duration_s` is a float"), "{e}");
        let e = apply(&mut t, &key("threats.x"), &v).unwrap_err();
        assert!(e.contains("an array in the scenario, not a table"), "{e}");
    }

    #[test]
    fn gets_values_back_and_compares_them_as_set() {
        let t = table(
            "duration_s = 60.0\n[law]\nk = 2.0\nname = \"hold\"\n[[threats]]\nspeed_mps = 3.0\n",
        );
        let got = |k: &str| get(&t, &key(k)).cloned();
        assert_eq!(got("law.k"), Some(toml::Value::Float(2.0)));
        assert_eq!(got("threats.0.speed_mps"), Some(toml::Value::Float(3.0)));
        for missing in ["law.x", "threats.1.speed_mps", "duration_s.x", "threats.x"] {
            assert_eq!(got(missing), None, "{missing}");
        }
        let found = got("duration_s").unwrap();
        assert!(holds(&found, &toml::Value::Integer(60)));
        assert!(holds(&found, &toml::Value::Float(60.0)));
        assert!(!holds(&found, &toml::Value::Float(60.5)));
        let law = got("law").unwrap();
        assert!(holds(&law, &toml::Value::Table(table("k = 2"))));
        assert!(!holds(&law, &toml::Value::Table(table("k = 3.0"))));
        assert!(!holds(&law, &toml::Value::String("hold".into())));
    }

    #[test]
    fn leaves_walk_nested_tables() {
        let t = table("duration_s = 1.0\n\"law.k\" = 2\n[sensing]\nrange_m = 3.0\n");
        let names: Vec<String> = leaves(&t).into_iter().map(|(k, _)| k).collect();
        assert_eq!(names, ["duration_s", "law.k", "sensing.range_m"]);
    }
}
