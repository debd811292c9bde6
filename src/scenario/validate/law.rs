//! `[law]` and `[[events]]`: the law built and checked against the dynamics, the timing and the swarm,
//! and every law change of the timeline replayed and checked at load time.

use nalgebra::Vector3;
use serde::Deserialize;

use crate::guidance::LawConfig;
use crate::scenario::schema::{ActionSection, AxisName, SelectionSection};
use crate::scenario::{Scenario, ScenarioError};
use crate::swarm::{
    check_law_fits, Event, EventAction, Law, LawError, Origin, SatelliteInit, Selection, SimError,
    SimulationConfig, SwarmFacts, ThrustAxis,
};

use super::Checker;

/// The load-time warnings about the scenario's `[law]` at t = 0 (see [`Prepared::warnings`]): for the
/// `pigeon` law with pattern switching, an initial egalitarian link graph that is not connected
/// (pairs within `egalitarian_range_m − link_delay_m` in the law's y–z plane,
/// `docs/methods/pigeon.md`).
pub(super) fn law_warnings(law: &LawConfig, satellites: &[SatelliteInit]) -> Vec<String> {
    match law {
        LawConfig::Pigeon(p) => {
            let positions: Vec<Vector3<f64>> = satellites
                .iter()
                .map(|s| s.relative_state.position_m)
                .collect();
            crate::guidance::pigeon::connectivity::initial_link_warning(&positions, p)
                .into_iter()
                .collect()
        }
        _ => Vec::new(),
    }
}

/// Builds a law and checks that it fits the dynamics and timing; an error names `key` (the law's table,
/// or the event that sets it) and, for a timing that cannot resolve the law, the timing key too.
pub(super) fn build_law(
    c: &Checker<'_>,
    key: &str,
    law: &LawConfig,
    config: &SimulationConfig,
    count: usize,
    min_mass_kg: f64,
) -> Result<Law, ScenarioError> {
    let built = law.build().map_err(|e| law_error(c, key, e))?;
    check_law(c, key, built, config, count, min_mass_kg)
}

/// Checks that a built law fits the dynamics and timing and the swarm; an error names `key` as
/// [`build_law`] does.
pub(super) fn check_law(
    c: &Checker<'_>,
    key: &str,
    built: Law,
    config: &SimulationConfig,
    count: usize,
    min_mass_kg: f64,
) -> Result<Law, ScenarioError> {
    check_law_fits(&built, config, min_mass_kg).map_err(|e| {
        let hint = match e {
            SimError::ControlPeriodTooLong { .. } => "; shorten control.period_s or soften the law",
            SimError::StepTooLong { .. } => "; shorten dynamics.step_s or soften the law",
            SimError::AdaptiveStepTooLong { .. } => "",
            SimError::CommandKindMismatch { .. } => "; choose another dynamics.model or law",
            _ => "",
        };
        c.keys(key, format!("{e}{hint}"), "")
    })?;
    built
        .check_swarm(&swarm_facts(config, count))
        .map_err(|e| law_error(c, key, e))?;
    Ok(built)
}

/// What a law may check about the swarm, from the scenario (see [`SwarmFacts`]).
fn swarm_facts(config: &SimulationConfig, count: usize) -> SwarmFacts {
    SwarmFacts {
        sensing_range_m: config.sensing.range_m,
        count,
        threat_velocities_hill_mps: config
            .threats
            .iter()
            .map(|t| t.velocity_hill_mps())
            .collect(),
    }
}

/// `current` with the keys of a `set-law-parameters` table replaced, re-validated by deserialisation
/// (unknown keys and wrong types are refused with the deserialiser's message; the law's name cannot
/// change this way: that is `switch-law`).
pub fn merge_law_parameters(
    current: &LawConfig,
    update: &toml::Table,
) -> Result<LawConfig, String> {
    if update.contains_key("name") {
        return Err("`name` cannot be changed by set-law-parameters (use switch-law)".into());
    }
    let mut table = toml::Table::try_from(current).map_err(|e| e.to_string())?;
    for (key, value) in update {
        table.insert(key.clone(), value.clone());
    }
    <LawConfig as Deserialize>::deserialize(table).map_err(|e| e.to_string())
}

/// A law's refusal of its parameters or of the swarm, as the scenario's error on `key` (the law's table
/// or the event that sets it).
fn law_error(c: &Checker<'_>, key: &str, e: LawError) -> ScenarioError {
    c.keys(key, e.to_string(), "")
}

/// A satellite selection of an event (`"all"` or ids among `count`).
fn selection(
    c: &Checker<'_>,
    key: &str,
    s: &SelectionSection,
    count: usize,
) -> Result<Selection, ScenarioError> {
    match s {
        SelectionSection::Word(w) if w == "all" => Ok(Selection::All),
        SelectionSection::Word(w) => Err(c.bad(
            key,
            format!("`{w}`"),
            "is not allowed",
            "\"all\" or a list of satellite indices",
        )),
        SelectionSection::Ids(ids) => {
            for &i in ids {
                c.index(key, i, count)?;
            }
            Ok(Selection::Satellites(ids.clone()))
        }
    }
}

/// Translates the timeline, checking times, indices and — by replaying the law changes in time order —
/// every parameter update and law switch: each resulting law is built and checked against the dynamics
/// and timing, so that a bad or too stiff update fails before the run, not when its event fires.
pub(super) fn events(
    c: &Checker<'_>,
    scenario: &Scenario,
    count: usize,
    config: &SimulationConfig,
    min_mass_kg: f64,
) -> Result<Vec<Event>, ScenarioError> {
    let f = &scenario.file;
    let duration_s = config.duration_s;
    let mut order: Vec<usize> = (0..f.events.len()).collect();
    order.sort_by(|&a, &b| f.events[a].time_s.total_cmp(&f.events[b].time_s));
    let mut current = f.law.clone();
    let mut out = Vec::with_capacity(f.events.len());
    for k in order {
        let e = &f.events[k];
        let event = scenario.event_key(k);
        let key = |name: &str| format!("{event}.{name}");
        if !(e.time_s.is_finite() && (0.0..=duration_s).contains(&e.time_s)) {
            return Err(c.range(
                &key("time_s"),
                e.time_s,
                format!("[0, duration_s = {duration_s}]"),
            ));
        }
        let action = match &e.action {
            ActionSection::SetLawParameters { parameters } => {
                let merged = merge_law_parameters(&current, parameters).map_err(|err| {
                    c.keys(
                        &key("parameters"),
                        format!("law `{}`: {err}", current.name()),
                        "the keys of the law's table, of their types",
                    )
                })?;
                build_law(c, &key("parameters"), &merged, config, count, min_mass_kg)?;
                current = merged.clone();
                EventAction::SetLawParameters(merged.into_parameters())
            }
            ActionSection::SwitchLaw { law } => {
                let built = build_law(c, &key("law"), law, config, count, min_mass_kg)?;
                current = law.clone();
                EventAction::SwitchLaw(built)
            }
            ActionSection::ThreatWarning { threat, active } => EventAction::ThreatWarning {
                threat: if *threat < config.threats.len() {
                    *threat
                } else if config.threats.is_empty() {
                    return Err(c.bad(
                        &key("threat"),
                        threat,
                        "names a threat, but the scenario has no [[threats]] to warn about",
                        "a [[threats]] entry to warn about: add one, or remove this threat-warning \
                         event",
                    ));
                } else {
                    return Err(c.bad(
                        &key("threat"),
                        format!("threat {threat}"),
                        "does not exist",
                        format!(
                            "0..{}, the [[threats]] of the scenario",
                            config.threats.len()
                        ),
                    ));
                },
                active: *active,
            },
            ActionSection::CutLinks { satellites } => {
                EventAction::CutLinks(selection(c, &key("satellites"), satellites, count)?)
            }
            ActionSection::RestoreLinks { satellites } => {
                EventAction::RestoreLinks(selection(c, &key("satellites"), satellites, count)?)
            }
            ActionSection::RemoveSatellite { satellite } => {
                let id = c.index(&key("satellite"), *satellite, count)?;
                if config.origin == Origin::Member(id) {
                    return Err(c.bad(
                        &key("satellite"),
                        format!("satellite {id}"),
                        "is reference.origin_member, the origin of the relative frame; removing it \
                         would freeze the frame",
                        "any other satellite, or origin = \"virtual\"",
                    ));
                }
                EventAction::RemoveSatellite(id)
            }
            ActionSection::FailThruster { satellite, axis } => EventAction::FailThruster {
                satellite: c.index(&key("satellite"), *satellite, count)?,
                axis: match axis {
                    AxisName::X => ThrustAxis::X,
                    AxisName::Y => ThrustAxis::Y,
                    AxisName::Z => ThrustAxis::Z,
                    AxisName::All => ThrustAxis::All,
                },
            },
        };
        out.push(Event {
            time_s: e.time_s,
            action,
        });
    }
    Ok(out)
}
