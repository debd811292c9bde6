//! `[law]`: the law built and checked against the dynamics, the timing and the swarm (the events'
//! law changes are checked with the same functions, in `events`).

use nalgebra::Vector3;
use serde::Deserialize;

use crate::guidance::LawConfig;
use crate::scenario::ScenarioError;
use crate::swarm::{
    check_law_fits, Law, LawError, SatelliteInit, SimError, SimulationConfig, SwarmFacts,
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
            .map(|t| t.velocity_hill_mps(0.0))
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
