//! Case and controller: what is flown and how it is steered, separated.
//!
//! A scenario file holds both. The **controller** is its `[law]` table, its law events
//! (`switch-law`, `set-law-parameters`) and its control timing (`[control]`); the **case** is everything
//! else: the reference orbit, the satellites and their initial states, threats, obstacles, the events
//! that are not law commands, the duration, dynamics, sensing and output.
//!
//! A controller file (`satflock run CASE --law FILE.toml`, `satflock compare CASE --law …`) holds a
//! `[law]` table and optionally `description`, `[control]` and `[[events]]` with law events only; any
//! other key is refused naming the file and the key. `builtin:NAME` names the controller of a built-in
//! scenario (its law, law events and control timing). [`Scenario::with_controller`] puts a controller
//! on a case; the result is validated as any scenario, and a refusal names both files
//! ([`Scenario::sources`]).

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::schema::{ActionSection, ControlSection, EventSection};
use super::{builtin, parse_error_message, Scenario, ScenarioError};
use crate::guidance::LawConfig;

/// The prefix naming the controller of a built-in scenario (`builtin:gao-circle`).
pub const BUILTIN_PREFIX: &str = "builtin:";

/// The content of a controller file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ControllerFile {
    /// What the controller is and where its values come from.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub description: String,
    /// The guidance law (`name` selects it; other keys are its parameters).
    pub law: LawConfig,
    /// Control timing; absent: the case's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub control: Option<ControlSection>,
    /// Law events (`switch-law`, `set-law-parameters`) only.
    #[serde(default)]
    pub events: Vec<EventSection>,
}

/// A controller and where it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct Controller {
    /// The controller.
    pub file: ControllerFile,
    /// Where it came from: a path, or `builtin:NAME`.
    pub source: String,
}

/// Where the controller of a scenario came from when it replaced the file's own, and where each event of
/// its timeline came from (for error messages that name the key in its own file).
#[derive(Clone, Debug, PartialEq)]
pub struct ControllerOrigin {
    /// The controller's source: a path, or `builtin:NAME`.
    pub source: String,
    /// For each event of the scenario's `events`, in order: the file it came from and its index there.
    pub events: Vec<EventOrigin>,
}

/// The file an event of a scenario with a replaced controller came from, and its index there.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EventOrigin {
    /// The case's `events[k]`.
    Case(usize),
    /// The controller's `events[k]`.
    Controller(usize),
}

/// Whether an event is a law command (part of the controller) rather than part of the case.
pub fn is_law_event(action: &ActionSection) -> bool {
    matches!(
        action,
        ActionSection::SetLawParameters { .. } | ActionSection::SwitchLaw { .. }
    )
}

impl Controller {
    /// Parses a controller file's text; `source` names it in errors. Refuses unknown keys (any scenario
    /// key other than the controller's) and events that are not law events.
    pub fn from_toml(text: &str, source: &str) -> Result<Self, ScenarioError> {
        let file: ControllerFile = toml::from_str(text).map_err(|e| ScenarioError::Parse {
            file: source.to_string(),
            message: format!(
                "{} (a controller file holds `description`, `[law]`, `[control]` and law \
                 `[[events]]` only; the rest belongs to the case)",
                parse_error_message(text, &e)
            ),
        })?;
        if let Some(k) = file.events.iter().position(|e| !is_law_event(&e.action)) {
            return Err(ScenarioError::invalid(
                source,
                crate::invalid::Invalid::keys(
                    format!("events[{k}].action"),
                    "is not a law event",
                    "in a controller file: \"switch-law\", \"set-law-parameters\"; ground \
                     messages, link cuts, losses and failures belong to the case",
                ),
            ));
        }
        Ok(Self {
            file,
            source: source.to_string(),
        })
    }

    /// Reads a controller file.
    pub fn from_path(path: &Path) -> Result<Self, ScenarioError> {
        let source = path.display().to_string();
        let text = crate::input_file::read_document(path).map_err(|e| ScenarioError::Io {
            file: source.clone(),
            message: e.to_string(),
        })?;
        Self::from_toml(&text, &source)
    }

    /// `builtin:NAME`: the controller of that built-in scenario; anything else: a controller file.
    pub fn load(spec: &str) -> Result<Self, ScenarioError> {
        match spec.strip_prefix(BUILTIN_PREFIX) {
            Some(name) => match builtin::find(name) {
                Some(b) => Ok(Self::of(&Scenario::from_toml(
                    b.toml,
                    &format!("{BUILTIN_PREFIX}{}", b.name),
                    Path::new("."),
                )?)),
                None => Err(ScenarioError::Unknown {
                    name: spec.to_string(),
                    known: builtin::names().join(", "),
                }),
            },
            None => Self::from_path(Path::new(spec)),
        }
    }

    /// The controller of a scenario: its law, its law events and its control timing.
    pub fn of(scenario: &Scenario) -> Self {
        Self {
            file: ControllerFile {
                description: String::new(),
                law: scenario.file.law.clone(),
                control: Some(scenario.file.control.clone()),
                events: scenario
                    .file
                    .events
                    .iter()
                    .filter(|e| is_law_event(&e.action))
                    .cloned()
                    .collect(),
            },
            source: scenario.source.clone(),
        }
    }

    /// A short label: the built-in's name, or the file name without its extension.
    pub fn label(&self) -> String {
        match self.source.strip_prefix(BUILTIN_PREFIX) {
            Some(name) => name.to_string(),
            None => Path::new(&self.source)
                .file_stem()
                .map_or_else(|| self.source.clone(), |s| s.to_string_lossy().into_owned()),
        }
    }
}

impl Scenario {
    /// This scenario (the case) steered by `controller`: its law, its law events in place of the case's
    /// (the case's other events are kept, before the controller's), and its control timing if it gives
    /// one. Nothing is validated here; [`Scenario::prepare`] validates the result, and its errors name
    /// both files.
    pub fn with_controller(&self, controller: &Controller) -> Scenario {
        let mut file = self.file.clone();
        let mut origins = Vec::new();
        let mut events = Vec::new();
        for (k, e) in self.file.events.iter().enumerate() {
            if !is_law_event(&e.action) {
                events.push(e.clone());
                origins.push(self.event_origin(k));
            }
        }
        for (k, e) in controller.file.events.iter().enumerate() {
            events.push(e.clone());
            origins.push(EventOrigin::Controller(k));
        }
        file.events = events;
        file.law = controller.file.law.clone();
        if let Some(control) = &controller.file.control {
            file.control = control.clone();
        }
        Scenario {
            file,
            source: self.source.clone(),
            base_dir: self.base_dir.clone(),
            controller: Some(ControllerOrigin {
                source: controller.source.clone(),
                events: origins,
            }),
        }
    }

    /// The scenario's source for error messages: the file, and the controller's file if one replaced
    /// its own (`case.toml with the controller laws/hold.toml`).
    pub fn sources(&self) -> String {
        match &self.controller {
            Some(c) => format!("{} with the controller {}", self.source, c.source),
            None => self.source.clone(),
        }
    }

    /// The key of event `k` of the timeline in its own file: `events[k]` of the case, or
    /// `controller events[j]`.
    pub fn event_key(&self, k: usize) -> String {
        match self.event_origin(k) {
            EventOrigin::Case(i) => format!("events[{i}]"),
            EventOrigin::Controller(j) => format!("controller events[{j}]"),
        }
    }

    fn event_origin(&self, k: usize) -> EventOrigin {
        self.controller
            .as_ref()
            .and_then(|c| c.events.get(k).copied())
            .unwrap_or(EventOrigin::Case(k))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::schema::ControlMode;

    fn invalid_key(e: &ScenarioError) -> (&str, &str) {
        match e {
            ScenarioError::Invalid { file, key, .. } => (file, key),
            other => panic!("not an Invalid error: {other}"),
        }
    }

    #[test]
    fn a_controller_file_refuses_case_keys_naming_file_and_key() {
        let law = "[law]\nname = \"hold\"\nstiffness_per_s2 = 1e-4\ndamping_per_s = 2e-2\n";
        // A top-level case key.
        let e =
            Controller::from_toml(&format!("duration_s = 10.0\n{law}"), "laws/x.toml").unwrap_err();
        let text = e.to_string();
        assert!(
            text.starts_with("laws/x.toml: ") && text.contains("`duration_s`"),
            "{text}"
        );
        // A case table.
        let e = Controller::from_toml(
            &format!("{law}\n[sensing]\nrange_m = 100.0\n"),
            "laws/x.toml",
        )
        .unwrap_err();
        assert!(e.to_string().contains("`sensing`"), "{e}");
        // A case event.
        let e = Controller::from_toml(
            &format!("{law}\n[[events]]\ntime_s = 1.0\naction = \"fail-thruster\"\nsatellite = 0\naxis = \"x\"\n"),
            "laws/x.toml",
        )
        .unwrap_err();
        assert_eq!(invalid_key(&e), ("laws/x.toml", "events[0].action"));
        // A law parameter the law does not have is the law's error, in its table.
        let e = Controller::from_toml(&format!("{law}gain = 1.0\n"), "laws/x.toml").unwrap_err();
        assert!(
            e.to_string().contains("gain") && e.to_string().contains("`law`"),
            "{e}"
        );
        // The valid file.
        let c = Controller::from_toml(law, "laws/x.toml").unwrap();
        assert_eq!(c.file.law.name(), "hold");
        assert_eq!(c.label(), "x");
    }

    #[test]
    fn a_controller_replaces_law_law_events_and_timing_and_keeps_case_events() {
        // The `hold` built-in: a set-law-parameters event at 1000 s and a fail-thruster event at 2000 s,
        // sampled control at 1 s.
        let case = Scenario::load("hold").unwrap();
        assert_eq!(case.file.events.len(), 2);
        let controller = Controller::from_toml(
            "[law]\nname = \"none\"\n\n[[events]]\ntime_s = 500.0\naction = \"switch-law\"\n\
             law = { name = \"hold\", stiffness_per_s2 = 1e-4, damping_per_s = 2e-2 }\n",
            "laws/drift-then-hold.toml",
        )
        .unwrap();
        let merged = case.with_controller(&controller);
        assert_eq!(merged.file.law.name(), "none");
        assert_eq!(merged.file.events.len(), 2);
        assert!(matches!(
            merged.file.events[0].action,
            ActionSection::FailThruster { satellite: 3, .. }
        ));
        assert_eq!(merged.file.events[0].time_s, Some(2000.0));
        assert!(matches!(
            merged.file.events[1].action,
            ActionSection::SwitchLaw { .. }
        ));
        assert_eq!(merged.event_key(0), "events[1]");
        assert_eq!(merged.event_key(1), "controller events[0]");
        // No [control] in the controller: the case's timing stays.
        assert_eq!(merged.file.control, case.file.control);
        // Everything else is the case's.
        assert_eq!(merged.file.satellites, case.file.satellites);
        assert_eq!(merged.file.seed, case.file.seed);
        merged.prepare().unwrap();
        // A built-in's controller brings its timing: gao-circle's is continuous.
        let gao = Controller::load("builtin:gao-circle").unwrap();
        assert_eq!(gao.label(), "gao-circle");
        assert!(gao.file.events.is_empty());
        let merged = case.with_controller(&gao);
        assert_eq!(merged.file.control.mode, ControlMode::Continuous);
        assert_eq!(merged.file.law.name(), "bifurcating");
        assert_eq!(merged.file.events.len(), 1);
        assert!(Controller::load("builtin:no-such").is_err());
    }

    #[test]
    fn a_combination_that_cannot_work_names_both_files() {
        // A controller event after the end of the case.
        let case = Scenario::load("hold").unwrap();
        let controller = Controller::from_toml(
            "[law]\nname = \"none\"\n\n[[events]]\ntime_s = 9000.0\naction = \"set-law-parameters\"\nparameters = {}\n",
            "laws/late.toml",
        )
        .unwrap();
        let e = case
            .with_controller(&controller)
            .prepare()
            .err()
            .expect("refused");
        let text = e.to_string();
        assert!(
            text.starts_with("builtin:hold with the controller laws/late.toml: key `controller events[0].time_s`"),
            "{text}"
        );
        // The equilibrium-shaping rhombus of E1 (4 nodes) on the 6 satellites of E3a.
        let es = Controller::load("builtin:es-e1").unwrap();
        let e = Scenario::load("es-e3a")
            .unwrap()
            .with_controller(&es)
            .prepare()
            .err()
            .expect("refused");
        let text = e.to_string();
        assert!(
            text.contains("builtin:es-e3a with the controller builtin:es-e1: key `law`")
                && text.contains("4 nodes but the swarm 6 satellites"),
            "{text}"
        );
        // A controller reacting to threat 1 on a case without threats (E1 without its threat and its
        // warnings).
        let mut no_threat = Scenario::load("es-e1").unwrap();
        no_threat.file.threats.clear();
        no_threat.file.events.clear();
        let mut table = toml::Table::try_from(&es.file.law).unwrap();
        table.insert("threat".into(), toml::Value::Integer(1));
        let controller = Controller {
            file: ControllerFile {
                law: LawConfig::deserialize(table).unwrap(),
                ..es.file.clone()
            },
            source: "laws/es-threat-1.toml".into(),
        };
        let e = no_threat
            .with_controller(&controller)
            .prepare()
            .err()
            .expect("refused");
        assert!(
            e.to_string()
                .contains("threat = 1 but the scenario has no threats"),
            "{e}"
        );
        // Threat 0 (the default) on it only shapes.
        no_threat.with_controller(&es).prepare().unwrap();
    }
}
