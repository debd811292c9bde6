//! The satellites' physical properties, one value per satellite: from a key of `[satellites]` (one
//! value for all, a list of one per satellite, or a distribution drawn from the run's random
//! streams) or from a column of `[satellites] properties_file`, a CSV
//! `sat,mass_kg,drag_area_m2,drag_coefficient,srp_area_m2,reflectivity_coefficient,radius_m` (any of
//! the property columns after `sat`).

use std::collections::BTreeMap;

use crate::invalid::Invalid;
use crate::random::{Purpose, RandomStream};
use crate::scenario::schema::{PerSatellite, PropertyDistribution};
use crate::scenario::{Scenario, ScenarioError};

use super::{states_csv, Checker, MAX_STATES_CSV_BYTES};

/// The properties a file may give, in the order of their draws' stream index.
pub(super) const PROPERTIES: [&str; 6] = [
    "mass_kg",
    "drag_area_m2",
    "drag_coefficient",
    "srp_area_m2",
    "reflectivity_coefficient",
    "radius_m",
];

/// Draws of a normal distribution tried before its bounds are called too narrow.
const MAX_REJECTIONS: usize = 10_000;

/// The columns of `[satellites] properties_file`, by property name, each one value per satellite.
pub(super) struct PropertyFile {
    /// The file, for messages.
    pub file: String,
    /// The columns given.
    pub columns: BTreeMap<&'static str, Vec<f64>>,
}

/// Reads `[satellites] properties_file` (absent: `None`): a CSV in the scenario's folder, `sat` first
/// (every id of `0..count` once), then any of [`PROPERTIES`], finite numbers.
pub(super) fn read_file(
    c: &Checker<'_>,
    scenario: &Scenario,
    count: usize,
) -> Result<Option<PropertyFile>, ScenarioError> {
    let Some(name) = &scenario.file.satellites.properties_file else {
        return Ok(None);
    };
    let key = "satellites.properties_file";
    let path = states_csv::resolve(c, key, &scenario.base_dir, name)?;
    let file = path.display().to_string();
    let allowed = format!(
        "a CSV file with the header `sat` then any of {}, one row per satellite (every id of \
         0..={} once), finite numbers, at most {MAX_STATES_CSV_BYTES} bytes",
        PROPERTIES.join(", "),
        count.saturating_sub(1)
    );
    let bad = |problem: String| c.bad(key, &file, problem, &allowed);
    let csv_error =
        |line: String, e: csv::Error| states_csv::read_error(c, key, &path, &allowed, &line, e);
    let mut reader = states_csv::open_csv(c, key, &path, &allowed)?;
    let header = reader
        .headers()
        .map_err(|e| csv_error("line 1".into(), e))?
        .clone();
    let names: Vec<&str> = header.iter().map(str::trim).collect();
    if names.first() != Some(&"sat") || names.len() < 2 {
        return Err(bad("line 1 is not the required header".into()));
    }
    let mut properties: Vec<&'static str> = Vec::new();
    for name in &names[1..] {
        match PROPERTIES.iter().find(|p| *p == name) {
            Some(p) if !properties.contains(p) => properties.push(p),
            _ => {
                return Err(bad(
                    "line 1 names a column twice or one that is not a property".into(),
                ))
            }
        }
    }
    let mut columns: Vec<Vec<f64>> = vec![vec![f64::NAN; count]; properties.len()];
    let mut seen = vec![false; count];
    for (row, record) in reader.records().enumerate() {
        let line = row + 2;
        let record = record.map_err(|e| csv_error(format!("line {line}"), e))?;
        if record.len() != names.len() {
            return Err(bad(format!(
                "line {line}: expected {} columns, found {}",
                names.len(),
                record.len()
            )));
        }
        let id = record[0]
            .trim()
            .parse::<usize>()
            .ok()
            .filter(|&id| id < count && !seen[id])
            .ok_or_else(|| {
                bad(format!(
                    "line {line}: column sat is not a satellite id of 0..={} not given before",
                    count.saturating_sub(1)
                ))
            })?;
        seen[id] = true;
        for (k, column) in columns.iter_mut().enumerate() {
            let v = record[k + 1]
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite());
            column[id] = v.ok_or_else(|| {
                bad(format!(
                    "line {line}: column {} is not a finite number",
                    properties[k]
                ))
            })?;
        }
    }
    if let Some(missing) = seen.iter().position(|s| !s) {
        return Err(bad(format!("has no row for satellite {missing}")));
    }
    Ok(Some(PropertyFile {
        file,
        columns: properties.into_iter().zip(columns).collect(),
    }))
}

/// Where the values of one property come from: the `[satellites]` key, or the file's column.
pub(super) struct Property<'a> {
    /// The property's name ([`PROPERTIES`]).
    pub name: &'static str,
    /// The key's value, if given.
    pub key: Option<&'a PerSatellite>,
    /// Whether a force model (or the engine, for mass and radius) reads it.
    pub used: bool,
    /// The value when neither key nor column gives it (`None`: required when used).
    pub default: Option<f64>,
}

/// One value per satellite of `property` (0 when neither given nor used). A key and a file column
/// for the same property are refused; a key no force model reads is refused
/// ([`super::satellites::unused_property`]); a file column no force model reads is taken and named in
/// `warnings`. `seed` fixes the draws of a distribution: satellite i's value of property k is the
/// first accepted draw of the stream (seed, properties, i, k).
pub(super) fn values(
    c: &Checker<'_>,
    property: &Property<'_>,
    file: Option<&PropertyFile>,
    count: usize,
    seed: u64,
    warnings: &mut Vec<String>,
) -> Result<Vec<f64>, ScenarioError> {
    let key = format!("satellites.{}", property.name);
    let column = file.and_then(|f| f.columns.get(property.name).map(|col| (f, col)));
    match (property.key, column) {
        (Some(_), Some((f, _))) => Err(c.keys(
            &key,
            format!("is given both here and as a column of {}", f.file),
            "one of the key and the column",
        )),
        (None, Some((f, col))) => {
            if !property.used {
                warnings.push(format!(
                    "{}: the column {} is read, but no force model of [dynamics.forces] uses it",
                    f.file, property.name
                ));
            }
            Ok(col.clone())
        }
        (Some(_), None) if !property.used => Err(super::satellites::unused_property(c, &key)),
        (None, None) => match (property.used, property.default) {
            (false, _) => Ok(vec![0.0; count]),
            (true, Some(d)) => Ok(vec![d; count]),
            (true, None) => Err(c.err(Invalid::missing(
                &key,
                "one value for every satellite, a list of one per satellite, a distribution, or a \
                 column of satellites.properties_file: a force model of [dynamics.forces] reads it",
            ))),
        },
        (Some(PerSatellite::All(v)), None) => Ok(vec![*v; count]),
        (Some(PerSatellite::Each(list)), None) => {
            if list.len() == count {
                Ok(list.clone())
            } else {
                Err(c.bad(
                    &key,
                    format!("{} values", list.len()),
                    format!("for {count} satellites"),
                    "one value, or exactly one per satellite",
                ))
            }
        }
        (Some(PerSatellite::Drawn(d)), None) => draw(c, &key, property.name, d, count, seed),
    }
}

/// `count` draws of `d`, satellite by satellite, from the streams of property `name`.
fn draw(
    c: &Checker<'_>,
    key: &str,
    name: &str,
    d: &PropertyDistribution,
    count: usize,
    seed: u64,
) -> Result<Vec<f64>, ScenarioError> {
    let index = PROPERTIES
        .iter()
        .position(|p| *p == name)
        .expect("a known property") as u64;
    let stream = |i: usize| RandomStream::new(seed, Purpose::Properties, i as u64, index);
    match *d {
        PropertyDistribution::Uniform { min, max } => {
            c.finite(&format!("{key}.min"), &[min, max])?;
            if min > max {
                return Err(c.bad(
                    &format!("{key}.min"),
                    min,
                    format!("is larger than max = {max}"),
                    "min <= max",
                ));
            }
            Ok((0..count)
                .map(|i| stream(i).uniform_range(min, max))
                .collect())
        }
        PropertyDistribution::Normal {
            mean,
            sigma,
            min,
            max,
        } => {
            c.finite(&format!("{key}.mean"), &[mean, min, max])?;
            c.non_negative(&format!("{key}.sigma"), sigma)?;
            if !(min <= mean && mean <= max) {
                return Err(c.bad(
                    &format!("{key}.mean"),
                    mean,
                    format!("is outside [min, max] = [{min}, {max}]"),
                    "min <= mean <= max",
                ));
            }
            (0..count)
                .map(|i| {
                    let mut s = stream(i);
                    (0..MAX_REJECTIONS)
                        .map(|_| mean + sigma * s.standard_normal())
                        .find(|v| (min..=max).contains(v))
                        .ok_or_else(|| {
                            c.bad(
                                &format!("{key}.sigma"),
                                sigma,
                                format!(
                                    "leaves almost no draw in [min, max] = [{min}, {max}] \
                                     ({MAX_REJECTIONS} tried)"
                                ),
                                "bounds that hold a fair share of the distribution",
                            )
                        })
                })
                .collect()
        }
    }
}
