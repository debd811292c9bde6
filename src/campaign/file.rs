//! The campaign file: its schema, its validation (every key, before any run starts) and its expansion
//! into runs. The format is documented in `docs/campaigns.md`.
//!
//! ```toml
//! scenario = "gao-circle"                   # a built-in name, or a path relative to this file
//! seeds = { count = 4, first = 1 }          # or seeds = [1, 5, 9]
//! [set]                                     # fixed overrides of scenario keys
//! duration_s = 300.0
//! [vary]                                    # a list: grid over its values
//! "law.k_f_kg_per_m_s2" = [0.002, 0.004]
//! ```
//!
//! Validation, in order (the first error is returned, naming the campaign file and the key):
//! 1. the campaign file's own keys and types;
//! 2. the scenario (a file next to the campaign file, or a built-in), read as a TOML table;
//! 3. each `[set]` key alone on the scenario (the path fits the scenario, the key exists in the scenario
//!    schema, the value has the right type), then all of `[set]` together with the scenario's full
//!    validation (ranges, consistency);
//! 4. each `[vary]` key with each of its listed values, and with both bounds of a range, alone on the
//!    scenario with `[set]`, through the scenario's full validation.
//!
//! A combination of valid values that the scenario or the engine refuses (e.g. a gain that is valid
//! alone but too stiff for a step set by another key) is not an error of the file: that run is recorded
//! as `refused`, with the message, and the other runs go on.

use std::path::{Path, PathBuf};

use serde::Deserialize;
use sha2::{Digest, Sha256};

use super::overrides::{self, KeyPath};
use super::sampling::{self, Method, Range, Scale};
use super::CampaignError;
use crate::scenario::{builtin, Scenario, ScenarioError};

/// Most runs one campaign holds (parameter points × seeds).
pub const MAX_RUNS: usize = 1_000_000;

/// Most samples of `[sampling] samples` (each range's draws must fit one random stream's budget).
pub const MAX_SAMPLES: usize = 100_000;

/// Seed of the sampling draws when `[sampling] seed` is absent.
pub const DEFAULT_SAMPLING_SEED: u64 = 1;

/// The campaign file as written (keys not listed here are refused).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileSchema {
    scenario: String,
    #[serde(default)]
    description: String,
    seeds: toml::Value,
    #[serde(default)]
    set: toml::Table,
    #[serde(default)]
    vary: toml::Table,
    sampling: Option<SamplingSchema>,
    outcomes: Option<Vec<String>>,
    #[serde(default)]
    keep_runs: bool,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SamplingSchema {
    method: Method,
    samples: usize,
    #[serde(default = "default_sampling_seed")]
    seed: u64,
}

fn default_sampling_seed() -> u64 {
    DEFAULT_SAMPLING_SEED
}

/// The scenario a campaign varies, as a TOML table.
#[derive(Clone, Debug)]
pub struct BaseScenario {
    /// Where it came from: a path, or `builtin:NAME`.
    pub source: String,
    /// Directory that the scenario's relative paths resolve against.
    pub base_dir: PathBuf,
    /// The scenario's TOML.
    pub table: toml::Table,
    /// SHA-256 of the scenario's text (lower-case hex).
    pub sha256: String,
}

/// The values one varied key takes.
#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    /// Listed values (a grid over them).
    List(Vec<toml::Value>),
    /// A range, sampled by `[sampling]`.
    Range(Range),
}

/// A varied key.
#[derive(Clone, Debug, PartialEq)]
pub struct Parameter {
    /// The dotted key in the scenario.
    pub key: KeyPath,
    /// Its values.
    pub values: Values,
}

impl Parameter {
    /// Whether the parameter's values are spread on a logarithmic scale (plots use a log axis).
    pub fn is_log(&self) -> bool {
        matches!(
            self.values,
            Values::Range(Range {
                scale: Scale::Log,
                ..
            })
        )
    }
}

/// `[sampling]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sampling {
    /// Latin hypercube or random.
    pub method: Method,
    /// Number of samples.
    pub samples: usize,
    /// Seed of the draws.
    pub seed: u64,
}

/// One run of a campaign.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RunSpec {
    /// Run index, from 0: `point × seeds + seed index`.
    pub index: usize,
    /// Parameter point index.
    pub point: usize,
    /// The run's scenario seed.
    pub seed: u64,
}

/// A validated campaign.
#[derive(Clone, Debug)]
pub struct Campaign {
    /// The campaign file's path as given (for messages and the manifest).
    pub file: String,
    /// SHA-256 of the campaign file's bytes (lower-case hex).
    pub sha256: String,
    /// What the campaign is for.
    pub description: String,
    /// The scenario.
    pub scenario: BaseScenario,
    /// Seed of every run of a parameter point, in order.
    pub seeds: Vec<u64>,
    /// Fixed overrides, in key order.
    pub set: Vec<(KeyPath, toml::Value)>,
    /// Varied keys, in key order.
    pub parameters: Vec<Parameter>,
    /// How ranges are sampled (present when a parameter is a range).
    pub sampling: Option<Sampling>,
    /// Every parameter point: one value per parameter, in parameter order. The list parameters' grid
    /// (first key slowest) × the range samples.
    pub points: Vec<Vec<toml::Value>>,
    /// Outcomes to summarise (absent: the default headline outcomes).
    pub outcomes: Option<Vec<String>>,
    /// Keep every run's full outputs (trajectory, metrics) under `runs/NNNNN/`.
    pub keep_runs: bool,
}

/// Lower-case hex SHA-256 of `bytes`.
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

impl Campaign {
    /// Reads and validates a campaign file.
    pub fn load(path: &Path) -> Result<Self, CampaignError> {
        let file = path.display().to_string();
        let text = crate::input_file::read_document(path).map_err(|e| CampaignError::Io {
            file: file.clone(),
            message: e.to_string(),
        })?;
        Self::from_toml(&text, &file, path.parent().unwrap_or(Path::new(".")))
    }

    /// Validates campaign text. `file` names it in errors; `base_dir` resolves a scenario path.
    pub fn from_toml(text: &str, file: &str, base_dir: &Path) -> Result<Self, CampaignError> {
        let invalid = |key: &str, message: String| CampaignError::Invalid {
            file: file.to_string(),
            key: key.to_string(),
            message,
        };
        let schema: FileSchema = toml::from_str(text).map_err(|e| CampaignError::Parse {
            file: file.to_string(),
            message: e.to_string().trim_end().to_string(),
        })?;
        let scenario =
            base_scenario(&schema.scenario, base_dir).map_err(|m| invalid("scenario", m))?;
        let seeds = seeds(&schema.seeds).map_err(|m| invalid("seeds", m))?;

        // [set]: each key alone, then together.
        let mut set = Vec::new();
        for (name, value) in overrides::leaves(&schema.set) {
            let key = override_key(&name).map_err(|m| invalid(&format!("set.{name}"), m))?;
            if let Some((other, _)) = set.iter().find(|(k, _): &&(KeyPath, _)| k.overlaps(&key)) {
                return Err(invalid(
                    &format!("set.{name}"),
                    format!("overlaps `set.{other}` (allowed: each scenario key once)"),
                ));
            }
            set.push((key, value));
        }
        // The scenario as written must read before keys are blamed for what it lacks.
        read_scenario(&scenario, scenario.table.clone())
            .map_err(|e| invalid("scenario", e.to_string()))?;
        for (key, value) in &set {
            let mut table = scenario.table.clone();
            overrides::apply(&mut table, key, value)
                .and_then(|()| read_scenario(&scenario, table).map_err(|e| e.to_string()))
                .map_err(|m| invalid(&format!("set.{key}"), format!("{value}: {m}")))?;
        }
        let mut with_set = scenario.table.clone();
        for (key, value) in &set {
            overrides::apply(&mut with_set, key, value)
                .map_err(|m| invalid(&format!("set.{key}"), format!("{value}: {m}")))?;
        }
        check_scenario(&scenario, with_set.clone()).map_err(|e| {
            let culprit = match &e {
                ScenarioError::Invalid { key, .. } => KeyPath::parse(key)
                    .ok()
                    .and_then(|k| set.iter().find(|(s, _)| s.overlaps(&k)))
                    .map(|(s, _)| format!("set.{s}")),
                _ => None,
            };
            invalid(culprit.as_deref().unwrap_or("set"), e.to_string())
        })?;

        // [vary].
        let mut parameters = Vec::new();
        collect_parameters("", &schema.vary, &mut parameters).map_err(|(k, m)| invalid(&k, m))?;
        parameters.sort_by(|a, b| a.key.as_str().cmp(b.key.as_str()));
        for (i, p) in parameters.iter().enumerate() {
            let name = format!("vary.{}", p.key);
            if let Some((s, _)) = set.iter().find(|(s, _)| s.overlaps(&p.key)) {
                return Err(invalid(
                    &name,
                    format!("overlaps `set.{s}` (allowed: a key is either set or varied)"),
                ));
            }
            if let Some(q) = parameters[..i].iter().find(|q| q.key.overlaps(&p.key)) {
                return Err(invalid(
                    &name,
                    format!(
                        "overlaps `vary.{}` (allowed: each scenario key once)",
                        q.key
                    ),
                ));
            }
        }
        let ranges: Vec<(usize, Range)> = parameters
            .iter()
            .enumerate()
            .filter_map(|(i, p)| match p.values {
                Values::Range(r) => Some((i, r)),
                Values::List(_) => None,
            })
            .collect();
        let sampling = match (schema.sampling, ranges.first()) {
            (None, Some(&(i, _))) => return Err(invalid(
                &format!("vary.{}", parameters[i].key),
                "a range needs [sampling] with `method` (\"latin-hypercube\" or \"random\") and \
                     `samples` (lists need none: they are a grid)"
                    .into(),
            )),
            (Some(_), None) => {
                return Err(invalid(
                    "sampling",
                    "[vary] has no range to sample (allowed: [sampling] only with a range \
                     `{ min, max, scale }` in [vary])"
                        .into(),
                ))
            }
            (Some(s), Some(_)) => {
                if !(1..=MAX_SAMPLES).contains(&s.samples) {
                    return Err(invalid(
                        "sampling.samples",
                        format!(
                            "{} is out of range (allowed: 1 to {MAX_SAMPLES})",
                            s.samples
                        ),
                    ));
                }
                Some(Sampling {
                    method: s.method,
                    samples: s.samples,
                    seed: s.seed,
                })
            }
            (None, None) => None,
        };
        // Each value alone (a range by its bounds), through the scenario's full validation.
        for p in &parameters {
            let name = format!("vary.{}", p.key);
            let candidates: Vec<toml::Value> = match &p.values {
                Values::List(values) => values.clone(),
                Values::Range(r) => vec![toml::Value::Float(r.min), toml::Value::Float(r.max)],
            };
            for value in candidates {
                let mut table = with_set.clone();
                overrides::apply(&mut table, &p.key, &value)
                    .and_then(|()| check_scenario(&scenario, table).map_err(|e| e.to_string()))
                    .map_err(|m| invalid(&name, format!("{value}: {m}")))?;
            }
        }

        // Points: the lists' grid × the samples.
        let lists: Vec<Vec<toml::Value>> = parameters
            .iter()
            .filter_map(|p| match &p.values {
                Values::List(v) => Some(v.clone()),
                Values::Range(_) => None,
            })
            .collect();
        let grid_size = lists.iter().try_fold(1usize, |n, l| n.checked_mul(l.len()));
        let sample_count = sampling.map_or(1, |s| s.samples);
        let run_count = grid_size
            .and_then(|g| g.checked_mul(sample_count))
            .and_then(|p| p.checked_mul(seeds.len()));
        match run_count {
            Some(n) if n <= MAX_RUNS => {}
            _ => {
                return Err(invalid(
                    "vary",
                    format!(
                        "the campaign has more than {MAX_RUNS} runs (parameter points × {} seeds; \
                         allowed: <= {MAX_RUNS})",
                        seeds.len()
                    ),
                ))
            }
        }
        let samples = match sampling {
            Some(s) => sampling::unit_samples(s.method, ranges.len(), s.samples, s.seed),
            None => vec![Vec::new()],
        };
        let mut points = Vec::new();
        for combination in sampling::grid(&lists) {
            for sample in &samples {
                let (mut listed, mut drawn) = (combination.iter(), sample.iter().zip(&ranges));
                points.push(
                    parameters
                        .iter()
                        .map(|p| match &p.values {
                            Values::List(_) => listed.next().expect("one per list").clone(),
                            Values::Range(_) => {
                                let (u, (_, r)) = drawn.next().expect("one per range");
                                toml::Value::Float(r.at(*u))
                            }
                        })
                        .collect(),
                );
            }
        }
        if let Some(outcomes) = &schema.outcomes {
            if let Some(bad) = outcomes.iter().find(|o| o.trim().is_empty()) {
                return Err(invalid(
                    "outcomes",
                    format!("`{bad}` is empty (allowed: outcome names of summary.json, e.g. `delta_v_mps.mean`)"),
                ));
            }
            if let Some(bad) = outcomes
                .iter()
                .find(|o| !super::summary::is_known_outcome(o))
            {
                return Err(invalid(
                    "outcomes",
                    format!(
                        "`{bad}` is not an outcome of a run (allowed: {}; a component `NAME.K` of {}; \
                         or `law.NAME`, a result of the law)",
                        super::summary::KNOWN_OUTCOMES.join(", "),
                        super::summary::VECTOR_OUTCOMES.join(", ")
                    ),
                ));
            }
        }
        Ok(Self {
            file: file.to_string(),
            sha256: sha256_hex(text.as_bytes()),
            description: schema.description,
            scenario,
            seeds,
            set,
            parameters,
            sampling,
            points,
            outcomes: schema.outcomes,
            keep_runs: schema.keep_runs,
        })
    }

    /// Number of runs: parameter points × seeds.
    pub fn run_count(&self) -> usize {
        self.points.len() * self.seeds.len()
    }

    /// Run `index` (< [`Self::run_count`]): point `index / seeds`, seed `seeds[index mod seeds]`.
    pub fn run(&self, index: usize) -> RunSpec {
        let s = self.seeds.len();
        RunSpec {
            index,
            point: index / s,
            seed: self.seeds[index % s],
        }
    }

    /// Every run, in index order.
    pub fn runs(&self) -> Vec<RunSpec> {
        (0..self.run_count()).map(|i| self.run(i)).collect()
    }

    /// The parameter values of point `point`, by key.
    pub fn point_values(&self, point: usize) -> Vec<(&KeyPath, &toml::Value)> {
        self.parameters
            .iter()
            .map(|p| &p.key)
            .zip(&self.points[point])
            .collect()
    }

    /// The scenario of a run: the scenario with `[set]`, the run's parameter values and its seed. Not
    /// yet validated beyond its types (running it validates it); an error means this combination is
    /// refused.
    pub fn scenario(&self, run: &RunSpec) -> Result<Scenario, ScenarioError> {
        let mut table = self.scenario.table.clone();
        let values = self
            .set
            .iter()
            .map(|(k, v)| (k, v))
            .chain(self.point_values(run.point));
        for (key, value) in values {
            overrides::apply(&mut table, key, value).map_err(|message| {
                ScenarioError::invalid(
                    &self.scenario.source,
                    crate::invalid::Invalid::keys(key.to_string(), message, ""),
                )
            })?;
        }
        let mut scenario = read_scenario(&self.scenario, table)?;
        scenario.file.seed = run.seed;
        Ok(scenario)
    }
}

/// A `[set]` or `[vary]` key: a dotted key that is not `seed` (the campaign sets it).
fn override_key(name: &str) -> Result<KeyPath, String> {
    let key = KeyPath::parse(name)?;
    if name == "seed" {
        return Err("the run seeds come from the campaign's `seeds` (remove this key)".into());
    }
    Ok(key)
}

/// The varied keys of `[vary]`: a list is a grid over its values; a table with `min` or `max` is a
/// range; any other table holds further dotted keys. Errors are (key, message).
fn collect_parameters(
    prefix: &str,
    table: &toml::Table,
    out: &mut Vec<Parameter>,
) -> Result<(), (String, String)> {
    for (name, value) in table {
        let full = overrides::join(prefix, name);
        let key_name = format!("vary.{full}");
        match value {
            toml::Value::Table(t) if t.contains_key("min") || t.contains_key("max") => {
                let range = range(t).map_err(|m| (key_name.clone(), m))?;
                let key = override_key(&full).map_err(|m| (key_name.clone(), m))?;
                out.push(Parameter {
                    key,
                    values: Values::Range(range),
                });
            }
            toml::Value::Table(t) => collect_parameters(&full, t, out)?,
            toml::Value::Array(values) => {
                let key = override_key(&full).map_err(|m| (key_name.clone(), m))?;
                if values.is_empty() {
                    return Err((
                        key_name,
                        "is an empty list (allowed: one value or more, or a range { min, max })"
                            .into(),
                    ));
                }
                out.push(Parameter {
                    key,
                    values: Values::List(values.clone()),
                });
            }
            other => {
                return Err((
                    key_name,
                    format!(
                        "{other} is not a list or a range (allowed: a list of values, e.g. [1.0, 2.0], \
                         or a range {{ min = 1.0, max = 2.0, scale = \"linear\" }}; a fixed value goes \
                         in [set])"
                    ),
                ))
            }
        }
    }
    Ok(())
}

/// A range `{ min, max, scale }`.
fn range(t: &toml::Table) -> Result<Range, String> {
    #[derive(Deserialize)]
    #[serde(deny_unknown_fields)]
    struct RangeSchema {
        min: f64,
        max: f64,
        #[serde(default)]
        scale: Scale,
    }
    let r: RangeSchema = toml::Value::Table(t.clone())
        .try_into()
        .map_err(|e: toml::de::Error| {
            format!(
                "{} (allowed: a range {{ min = NUMBER, max = NUMBER, scale = \"linear\" or \"log\" }})",
                e.message().trim_end()
            )
        })?;
    if !(r.min.is_finite() && r.max.is_finite() && r.min < r.max) {
        return Err(format!(
            "min = {}, max = {} (allowed: finite, min < max)",
            r.min, r.max
        ));
    }
    if r.scale == Scale::Log && r.min <= 0.0 {
        return Err(format!(
            "min = {} with scale = \"log\" (allowed: min > 0 on a log scale)",
            r.min
        ));
    }
    Ok(Range {
        min: r.min,
        max: r.max,
        scale: r.scale,
    })
}

/// The seeds: a list of distinct integers ≥ 0, or `{ count, first }` (seeds first, first + 1, …).
fn seeds(value: &toml::Value) -> Result<Vec<u64>, String> {
    const ALLOWED: &str =
        "allowed: { count = N, first = S } for seeds S, S+1, …, S+N−1, or a list of \
                           distinct integers >= 0 such as [1, 5, 9]";
    let seeds: Vec<u64> = match value {
        toml::Value::Array(items) => items
            .iter()
            .map(|v| match v {
                toml::Value::Integer(i) if *i >= 0 => Ok(*i as u64),
                other => Err(format!("{other} is not a seed ({ALLOWED})")),
            })
            .collect::<Result<_, _>>()?,
        toml::Value::Table(t) => {
            #[derive(Deserialize)]
            #[serde(deny_unknown_fields)]
            struct Count {
                count: u64,
                first: u64,
            }
            let c: Count = toml::Value::Table(t.clone())
                .try_into()
                .map_err(|e: toml::de::Error| format!("{} ({ALLOWED})", e.message().trim_end()))?;
            if c.count == 0 || c.count > MAX_RUNS as u64 {
                return Err(format!(
                    "count = {} is out of range (allowed: 1 to {MAX_RUNS})",
                    c.count
                ));
            }
            (0..c.count)
                .map(|k| {
                    c.first
                        .checked_add(k)
                        .ok_or_else(|| format!("first = {} + count overflows 64 bits", c.first))
                })
                .collect::<Result<_, _>>()?
        }
        other => return Err(format!("{other} is not a seed list ({ALLOWED})")),
    };
    if seeds.is_empty() {
        return Err(format!("is empty ({ALLOWED})"));
    }
    let mut sorted = seeds.clone();
    sorted.sort_unstable();
    if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
        return Err(format!(
            "seed {} is listed twice (a repeated seed repeats a run; {ALLOWED})",
            w[0]
        ));
    }
    Ok(seeds)
}

/// The scenario named by a campaign: a path relative to the campaign file's folder if that file
/// exists, otherwise a built-in name.
fn base_scenario(name: &str, base_dir: &Path) -> Result<BaseScenario, String> {
    let path = base_dir.join(name);
    let (source, dir, text) = if path.is_file() {
        let text = crate::input_file::read_document(&path)
            .map_err(|e| format!("{}: cannot read the file: {e}", path.display()))?;
        let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
        (path.display().to_string(), dir, text)
    } else if let Some(b) = builtin::find(name) {
        (
            format!("builtin:{}", b.name),
            PathBuf::from("."),
            b.toml.to_string(),
        )
    } else {
        return Err(format!(
            "no scenario file `{}` and no built-in scenario `{name}` (allowed: a path relative to the \
             campaign file, or a built-in: {})",
            path.display(),
            builtin::names().join(", ")
        ));
    };
    let table: toml::Table =
        toml::from_str(&text).map_err(|e| format!("{source}: {}", e.to_string().trim_end()))?;
    Ok(BaseScenario {
        source,
        base_dir: dir,
        sha256: sha256_hex(text.as_bytes()),
        table,
    })
}

/// Reads a scenario table into a [`Scenario`] (types and keys; not the ranges).
fn read_scenario(base: &BaseScenario, table: toml::Table) -> Result<Scenario, ScenarioError> {
    Scenario::from_table(table, &base.source, &base.base_dir)
}

/// Reads and fully validates a scenario table.
fn check_scenario(base: &BaseScenario, table: toml::Table) -> Result<(), ScenarioError> {
    read_scenario(base, table)?.prepare().map(|_| ())
}

#[cfg(test)]
mod tests {
    use super::*;

    const SHORT_HOLD: &str =
        "scenario = \"hold\"\nseeds = [3, 1]\n[set]\nduration_s = 20.0\nevents = []\n";

    fn load(text: &str) -> Result<Campaign, CampaignError> {
        Campaign::from_toml(text, "c.toml", Path::new("."))
    }

    fn error(text: &str) -> (String, String) {
        match load(text).unwrap_err() {
            CampaignError::Invalid { file, key, message } => {
                assert_eq!(file, "c.toml");
                (key, message)
            }
            other => panic!("not a key error: {other}"),
        }
    }

    /// The issue's example form, as shipped in `campaigns/`.
    #[test]
    fn the_issue_example_expands_to_the_grid_times_the_seeds() {
        let text = include_str!("../../campaigns/gao-circle-k-f.toml");
        let c = load(text).unwrap();
        assert_eq!(c.seeds, [1, 2, 3, 4]);
        assert_eq!(c.run_count(), 8);
        assert_eq!(c.scenario.source, "builtin:gao-circle");
        let runs = c.runs();
        assert_eq!(
            runs[5],
            RunSpec {
                index: 5,
                point: 1,
                seed: 2
            }
        );
        let s = c.scenario(&runs[5]).unwrap();
        assert_eq!(s.file.seed, 2);
        assert_eq!(s.file.duration_s, 300.0);
        match &s.file.law {
            crate::guidance::LawConfig::Bifurcating(p) => {
                assert_eq!(p.k_f_kg_per_m_s2, 0.004)
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(c.sha256, sha256_hex(text.as_bytes()));
        assert_eq!(c.sha256.len(), 64);
    }

    #[test]
    fn grid_of_two_lists_and_a_sampled_range() {
        let text = format!(
            "{SHORT_HOLD}[vary]\n\"law.stiffness_per_s2\" = {{ min = 1e-5, max = 1e-3, scale = \"log\" }}\n\
             \"satellites.mass_kg\" = [5.0, 10.0, 20.0]\n\"sensing.range_m\" = [500.0, 900.0]\n\
             [sampling]\nmethod = \"latin-hypercube\"\nsamples = 4\n"
        );
        let c = load(&text).unwrap();
        let keys: Vec<&str> = c.parameters.iter().map(|p| p.key.as_str()).collect();
        assert_eq!(
            keys,
            [
                "law.stiffness_per_s2",
                "satellites.mass_kg",
                "sensing.range_m"
            ]
        );
        // 3 × 2 grid × 4 samples = 24 points, × 2 seeds.
        assert_eq!(c.points.len(), 24);
        assert_eq!(c.run_count(), 48);
        // The samples are shared by every grid point: points 0..4 and 4..8 differ only in the lists.
        for k in 0..4 {
            assert_eq!(c.points[k][0], c.points[k + 4][0]);
            assert_eq!(c.points[k][1], toml::Value::Float(5.0));
            assert_eq!(c.points[k][2], toml::Value::Float(500.0));
            assert_eq!(c.points[k + 4][2], toml::Value::Float(900.0));
        }
        assert_eq!(c.run(3).seed, 1);
        assert!(c.parameters[0].is_log());
    }

    #[test]
    fn unknown_keys_wrong_types_and_out_of_range_values_name_the_key() {
        let (k, m) = error(&format!(
            "{SHORT_HOLD}[vary]\n\"law.no_such_gain\" = [1.0]\n"
        ));
        assert_eq!(k, "vary.law.no_such_gain");
        assert!(m.contains("no_such_gain"), "{m}");
        let (k, m) = error(&format!(
            "{SHORT_HOLD}[vary]\n\"satellites.count\" = [2, 2.5]\n"
        ));
        assert_eq!(k, "vary.satellites.count");
        assert!(m.starts_with("2.5: ") && m.contains("invalid type"), "{m}");
        let (k, m) = error(&format!(
            "{SHORT_HOLD}[vary]\n\"sensing.range_m\" = [100.0, -1.0]\n"
        ));
        assert_eq!(k, "vary.sensing.range_m");
        assert!(m.contains("-1") && m.contains("sensing.range_m"), "{m}");
        let (k, m) = error(&SHORT_HOLD.replace("duration_s = 20.0", "duration_s = -20.0"));
        assert_eq!(k, "set.duration_s");
        assert!(m.contains("allowed"), "{m}");
        let (k, _) = error(&SHORT_HOLD.replace("duration_s", "durations"));
        assert_eq!(k, "set.durations");
        let (k, m) = error(&format!(
            "{SHORT_HOLD}[vary]\n\"threats.0.speed_mps\" = [1.0]\n"
        ));
        assert_eq!(k, "vary.threats.0.speed_mps");
        assert!(m.contains("no `threats`"), "{m}");
        let (k, _) = error(&format!("{SHORT_HOLD}[vary]\nseed = [1, 2]\n"));
        assert_eq!(k, "vary.seed");
        let (k, _) = error(&format!("{SHORT_HOLD}[vary]\n\"duration_s\" = [1.0]\n"));
        assert_eq!(k, "vary.duration_s");
        let (k, m) = error(&format!(
            "{SHORT_HOLD}[vary]\n\"law.stiffness_per_s2\" = {{ min = 1.0, max = 2.0 }}\n"
        ));
        assert_eq!(k, "vary.law.stiffness_per_s2");
        assert!(m.contains("[sampling]"), "{m}");
        let (k, m) = error(&format!(
            "{SHORT_HOLD}[vary]\n\"law.stiffness_per_s2\" = {{ min = 0.0, max = 2.0, scale = \"log\" }}\n"
        ));
        assert_eq!(k, "vary.law.stiffness_per_s2");
        assert!(m.contains("min > 0"), "{m}");
        assert_eq!(error(&SHORT_HOLD.replace("[3, 1]", "[3, 3]")).0, "seeds");
        assert_eq!(
            error(&SHORT_HOLD.replace("[3, 1]", "{ count = 0, first = 1 }")).0,
            "seeds"
        );
        assert_eq!(
            error(&SHORT_HOLD.replace("\"hold\"", "\"nope\"")).0,
            "scenario"
        );
        assert!(matches!(
            load(&format!("{SHORT_HOLD}[extra]\n")),
            Err(CampaignError::Parse { .. })
        ));
    }
}
