//! The orbit files a scenario names (`satellites.initial` of distribution `oem`, `omm` or `tle`;
//! `[reference] oem`, `omm` or `tle`; a threat's or obstacle's `omm` or `tle`), read once before
//! anything needs them, and the scenario epoch they give when `epoch_utc` is absent (the swarm's and
//! the reference's only: a real threat's element set is propagated to the scenario epoch).

use crate::orbit::CartesianState;
use crate::orbit_files::{self, OemObject, Sgp4Object};
use crate::scenario::schema::{InitialSection, ScenarioFile};
use crate::scenario::{Scenario, ScenarioError};
use crate::time::Epoch;

use super::{states_csv, Checker};

/// The format of an orbit file.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Format {
    Oem,
    Omm,
    Tle,
}

/// The objects of one orbit input: OEM objects, or SGP4 element sets (OMM, TLE).
enum Objects {
    Oem(Vec<OemObject>),
    Sgp4(Vec<Sgp4Object>),
}

/// One orbit input of the scenario: the key that names it, its file(s) and its objects.
pub(super) struct OrbitInput {
    key: String,
    files: String,
    objects: Objects,
}

impl OrbitInput {
    /// How many objects (satellites) it holds.
    pub(super) fn len(&self) -> usize {
        match &self.objects {
            Objects::Oem(o) => o.len(),
            Objects::Sgp4(o) => o.len(),
        }
    }

    /// The key that names it (`satellites.initial.files`, `reference.omm`, …).
    pub(super) fn key(&self) -> &str {
        &self.key
    }

    /// The one SGP4 element set of an OMM or TLE input (`None` for an OEM input).
    pub(super) fn sgp4_object(&self) -> Option<&Sgp4Object> {
        match &self.objects {
            Objects::Sgp4(o) => o.first(),
            Objects::Oem(_) => None,
        }
    }

    /// The files, for messages.
    pub(super) fn files(&self) -> &str {
        &self.files
    }

    /// The epoch the input gives the scenario: the latest instant at which every object has a
    /// state of its own (OEM: the latest first state; OMM/TLE: the latest element-set epoch).
    fn epoch(&self) -> Epoch {
        let latest = |a: Epoch, b: Epoch| if b > a { b } else { a };
        match &self.objects {
            Objects::Oem(o) => o.iter().map(OemObject::start).reduce(latest),
            Objects::Sgp4(o) => o.iter().map(Sgp4Object::epoch).reduce(latest),
        }
        .expect("an orbit input holds an object")
    }

    /// Every object's state at `epoch`, EME2000 \[m, m/s\], in file order.
    pub(super) fn states_eme2000(
        &self,
        c: &Checker<'_>,
        epoch: Epoch,
    ) -> Result<Vec<CartesianState>, ScenarioError> {
        let fail = |e: orbit_files::OrbitFileError| c.keys(&self.key, e.to_string(), "");
        match &self.objects {
            Objects::Oem(o) => o
                .iter()
                .map(|x| x.state_eme2000(epoch).map_err(fail))
                .collect(),
            Objects::Sgp4(o) => o
                .iter()
                .map(|x| x.state_eme2000(epoch).map_err(fail))
                .collect(),
        }
    }
}

/// The scenario's orbit inputs: of the swarm, of the reference orbit, and of the real objects among
/// the threats and obstacles.
pub(super) struct OrbitInputs {
    /// `satellites.initial` with distribution `oem`, `omm` or `tle`.
    pub(super) swarm: Option<OrbitInput>,
    /// `[reference] oem`, `omm` or `tle`.
    pub(super) reference: Option<OrbitInput>,
    /// `threats[k].omm` or `tle`, by threat.
    pub(super) threats: Vec<Option<OrbitInput>>,
    /// `obstacles[k].omm` or `tle`, by obstacle.
    pub(super) obstacles: Vec<Option<OrbitInput>>,
}

/// Reads every orbit file the scenario names (confined to its folder, size-limited, parsed in full).
pub(super) fn read(c: &Checker<'_>, scenario: &Scenario) -> Result<OrbitInputs, ScenarioError> {
    let f = &scenario.file;
    let builtin = scenario.source.strip_prefix("builtin:");
    let read_files = |key: &str,
                      names: &[String],
                      format: Format|
     -> Result<OrbitInput, ScenarioError> {
        let fail = |e: orbit_files::OrbitFileError| c.keys(key, e.to_string(), "");
        // A built-in scenario's files are embedded with it; others are on the disk, in its folder.
        let embedded: Option<Vec<(String, &str)>> = builtin.and_then(|b| {
            names
                .iter()
                .map(|n| {
                    crate::scenario::builtin::file(b, n).map(|t| (format!("builtin:{b}/{n}"), t))
                })
                .collect()
        });
        let (files, objects) = match embedded {
            Some(texts) => {
                let mut oem = Vec::new();
                let mut sgp4 = Vec::new();
                for (name, text) in &texts {
                    match format {
                        Format::Oem => {
                            oem.extend(orbit_files::parse_oem(text, name).map_err(fail)?)
                        }
                        Format::Omm => {
                            sgp4.extend(orbit_files::parse_omm(text, name).map_err(fail)?)
                        }
                        Format::Tle => {
                            sgp4.extend(orbit_files::parse_tle(text, name).map_err(fail)?)
                        }
                    }
                }
                let names: Vec<&str> = texts.iter().map(|(n, _)| n.as_str()).collect();
                let objects = if format == Format::Oem {
                    Objects::Oem(oem)
                } else {
                    Objects::Sgp4(sgp4)
                };
                (names.join(", "), objects)
            }
            None => {
                let mut paths = Vec::with_capacity(names.len());
                for (k, name) in names.iter().enumerate() {
                    let key_k = if key.ends_with("files") {
                        format!("{key}[{k}]")
                    } else {
                        key.to_string()
                    };
                    paths.push(states_csv::resolve(c, &key_k, &scenario.base_dir, name)?);
                }
                let objects = match format {
                    Format::Oem => Objects::Oem(orbit_files::read_oem_files(&paths).map_err(fail)?),
                    Format::Omm => {
                        Objects::Sgp4(orbit_files::read_omm_file(&paths[0]).map_err(fail)?)
                    }
                    Format::Tle => {
                        Objects::Sgp4(orbit_files::read_tle_file(&paths[0]).map_err(fail)?)
                    }
                };
                let names: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
                (names.join(", "), objects)
            }
        };
        let input = OrbitInput {
            key: key.to_string(),
            files,
            objects,
        };
        if input.len() == 0 {
            return Err(c.keys(key, format!("{} holds no object", input.files), ""));
        }
        Ok(input)
    };
    let swarm = match &f.satellites.initial {
        InitialSection::Oem { files } => {
            if files.is_empty() {
                return Err(c.keys(
                    "satellites.initial.files",
                    "is empty",
                    "one or more OEM files",
                ));
            }
            Some(read_files("satellites.initial.files", files, Format::Oem)?)
        }
        InitialSection::Omm { file } => Some(read_files(
            "satellites.initial.file",
            std::slice::from_ref(file),
            Format::Omm,
        )?),
        InitialSection::Tle { file } => Some(read_files(
            "satellites.initial.file",
            std::slice::from_ref(file),
            Format::Tle,
        )?),
        _ => None,
    };
    let r = &f.reference;
    let reference = match (&r.oem, &r.omm, &r.tle) {
        (Some(file), None, None) => Some(read_files(
            "reference.oem",
            std::slice::from_ref(file),
            Format::Oem,
        )?),
        (None, Some(file), None) => Some(read_files(
            "reference.omm",
            std::slice::from_ref(file),
            Format::Omm,
        )?),
        (None, None, Some(lines)) => Some(inline_tle(c, "reference.tle", lines)?),
        (None, None, None) => None,
        _ => {
            return Err(c.keys(
                "reference",
                "names more than one of oem, omm and tle",
                "one orbit source for the reference",
            ))
        }
    };
    let one_object = |input: &OrbitInput, what: &str| {
        if input.len() == 1 {
            Ok(())
        } else {
            Err(c.bad(
                input.key(),
                input.files(),
                format!("holds {} objects", input.len()),
                format!("a file holding the one {what}"),
            ))
        }
    };
    if let Some(input) = &reference {
        one_object(input, "reference orbit")?;
    }
    // A real threat or obstacle: `omm` or `tle`, holding its one element set.
    let object_input = |prefix: String, omm: &Option<String>, tle: &Option<Vec<String>>| {
        let input = match (omm, tle) {
            (Some(file), None) => Some(read_files(
                &format!("{prefix}.omm"),
                std::slice::from_ref(file),
                Format::Omm,
            )?),
            (None, Some(lines)) => Some(inline_tle(c, &format!("{prefix}.tle"), lines)?),
            (None, None) => None,
            (Some(_), Some(_)) => {
                return Err(c.keys(&prefix, "names both omm and tle", "one element set"))
            }
        };
        if let Some(input) = &input {
            one_object(input, "object")?;
        }
        Ok(input)
    };
    let threats = f
        .threats
        .iter()
        .enumerate()
        .map(|(k, t)| object_input(format!("threats[{k}]"), &t.omm, &t.tle))
        .collect::<Result<_, _>>()?;
    let obstacles = f
        .obstacles
        .iter()
        .enumerate()
        .map(|(k, o)| object_input(format!("obstacles[{k}]"), &o.omm, &o.tle))
        .collect::<Result<_, _>>()?;
    Ok(OrbitInputs {
        swarm,
        reference,
        threats,
        obstacles,
    })
}

/// `tle = ["line 1", "line 2"]` (or a title line first) under `key`.
fn inline_tle(c: &Checker<'_>, key: &str, lines: &[String]) -> Result<OrbitInput, ScenarioError> {
    let (name, l1, l2) = match lines {
        [l1, l2] => (None, l1, l2),
        [title, l1, l2] => (Some(title.trim()), l1, l2),
        _ => {
            return Err(c.bad(
                key,
                format!("{} lines", lines.len()),
                "is not a two-line element set",
                "the two lines of a TLE, or a title line and the two",
            ))
        }
    };
    let object = Sgp4Object::from_tle_lines(key, name, l1.trim_end(), l2.trim_end())
        .map_err(|e| c.keys(key, e.to_string(), ""))?;
    Ok(OrbitInput {
        key: key.into(),
        files: format!("the scenario's {key}"),
        objects: Objects::Sgp4(vec![object]),
    })
}

/// The scenario epoch: `epoch_utc` when given, else the epoch of the orbit inputs (which must agree
/// to 1 ms, else an error naming both), else [`crate::time::DEFAULT_EPOCH_UTC`].
pub(super) fn epoch(
    c: &Checker<'_>,
    f: &ScenarioFile,
    inputs: &OrbitInputs,
) -> Result<Epoch, ScenarioError> {
    if let Some(text) = &f.epoch_utc {
        return crate::time::parse_epoch_utc(text).map_err(|e| c.keys("epoch_utc", e, ""));
    }
    let given: Vec<&OrbitInput> = [&inputs.reference, &inputs.swarm]
        .into_iter()
        .flatten()
        .collect();
    match given.as_slice() {
        [] => crate::time::parse_epoch_utc(crate::time::DEFAULT_EPOCH_UTC)
            .map_err(|e| c.keys("epoch_utc", e, "")),
        [one] => Ok(one.epoch()),
        [a, b, ..] => {
            let (ea, eb) = (a.epoch(), b.epoch());
            if (ea - eb).abs().to_seconds() <= 1e-3 {
                Ok(ea)
            } else {
                Err(c.keys(
                    "epoch_utc",
                    format!(
                        "is absent and the orbit inputs disagree: `{}` ({}) gives {}, `{}` ({}) gives {}",
                        a.key(),
                        a.files(),
                        crate::time::utc_iso(ea),
                        b.key(),
                        b.files(),
                        crate::time::utc_iso(eb)
                    ),
                    "epoch_utc given, or orbit inputs of one epoch",
                ))
            }
        }
    }
}
