//! The `[[events]]` of a scenario: when each fires (`time_s`, or a `condition` on the swarm's state,
//! see `docs/scenarios.md`, "Condition events") and what it does, translated into the engine's
//! [`Event`]s. Times, indices, thresholds and outcome names are checked here, and every law change
//! is built and checked against the dynamics and timing, so that a bad or too stiff update fails
//! before the run, not when its event fires.

use super::law::{build_law, merge_law_parameters};
use super::Checker;
use crate::guidance::LawConfig;
use crate::scenario::schema::{
    ActionSection, AxisName, ConditionSection, EventSection, SelectionSection,
};
use crate::scenario::Scenario;
use crate::scenario::ScenarioError;
use crate::swarm::{
    Bound, Condition, ConditionTest, Event, EventAction, Law, Origin, Selection, SimulationConfig,
    ThrustAxis, Trigger, SHAPE_REACHED,
};

/// Translates the timeline. Timed events are taken in time order, replaying the law changes: each
/// `set-law-parameters` is merged onto the law its time leaves in force. A condition event fires at
/// a time not known before the run, so its `set-law-parameters` is merged onto the scenario's
/// `[law]`, and is refused when another event changes the law (the law in force when it fires would
/// not be known).
pub(super) fn events(
    c: &Checker<'_>,
    scenario: &Scenario,
    count: usize,
    config: &SimulationConfig,
    min_mass_kg: f64,
) -> Result<Vec<Event>, ScenarioError> {
    let f = &scenario.file;
    let duration_s = config.duration_s;
    let mut timed: Vec<(usize, f64)> = Vec::new();
    let mut conditional: Vec<(usize, &ConditionSection)> = Vec::new();
    for (k, e) in f.events.iter().enumerate() {
        let event = scenario.event_key(k);
        match (e.time_s, &e.condition) {
            (Some(_), Some(_)) => {
                return Err(c.keys(
                    &format!("{event}.condition"),
                    "an event fires at `time_s` or on a `condition`, not both (remove one)",
                    "",
                ))
            }
            (None, None) => {
                return Err(c.keys(
                    &format!("{event}.time_s"),
                    "missing: an event needs `time_s` (seconds since the start) or a `condition`",
                    "",
                ))
            }
            (Some(t), None) => {
                if !(t.is_finite() && (0.0..=duration_s).contains(&t)) {
                    return Err(c.keys(
                        &format!("{event}.time_s"),
                        format!("{t} is out of range (allowed: [0, duration_s = {duration_s}])"),
                        "",
                    ));
                }
                timed.push((k, t));
            }
            (None, Some(condition)) => conditional.push((k, condition)),
        }
    }
    timed.sort_by(|a, b| a.1.total_cmp(&b.1));
    let laws = run_laws(f.law.clone(), &f.events);
    let mut current = f.law.clone();
    let mut out = Vec::with_capacity(f.events.len());
    for (k, time_s) in timed {
        let (law, action) = action(c, scenario, k, &current, count, config, min_mass_kg)?;
        current = law;
        out.push(Event::at(k, time_s, action));
    }
    for (k, section) in conditional {
        let event = scenario.event_key(k);
        let e = &f.events[k];
        if matches!(e.action, ActionSection::SetLawParameters { .. }) {
            if let Some(j) = f
                .events
                .iter()
                .enumerate()
                .position(|(j, other)| j != k && changes_law_kind(other))
            {
                return Err(c.keys(
                    &format!("{event}.parameters"),
                    format!(
                        "a condition event's set-law-parameters is merged onto [law], so no other \
                         event may change the law ({} does; allowed: use switch-law with the whole \
                         law instead)",
                        scenario.event_key(j)
                    ),
                    "",
                ));
            }
        }
        let condition = condition(
            c,
            &format!("{event}.condition"),
            section,
            &laws,
            config,
            count,
            f.conjunctions.is_some(),
        )?;
        let law_action = crate::scenario::controller::is_law_event(&e.action);
        if condition.repeat && law_action {
            return Err(c.keys(
                &format!("{event}.condition.repeat"),
                "a law event fires once (allowed with set-law-parameters and switch-law: repeat = \
                 false; give one event per change)",
                "",
            ));
        }
        let (_, action) = action(c, scenario, k, &f.law, count, config, min_mass_kg)?;
        out.push(Event {
            index: k,
            trigger: Trigger::Condition(condition),
            action,
        });
    }
    Ok(out)
}

/// Whether an event changes the law other than by a condition event's own merge onto `[law]`: a
/// switch-law, or a timed set-law-parameters.
fn changes_law_kind(e: &EventSection) -> bool {
    match e.action {
        ActionSection::SwitchLaw { .. } => true,
        ActionSection::SetLawParameters { .. } => e.time_s.is_some(),
        _ => false,
    }
}

/// The laws a run may have in force: `[law]` and every `switch-law` target, built (those that do not
/// build are refused where their key is checked).
fn run_laws(law: LawConfig, events: &[EventSection]) -> Vec<Law> {
    std::iter::once(law)
        .chain(events.iter().filter_map(|e| match &e.action {
            ActionSection::SwitchLaw { law } => Some(law.clone()),
            _ => None,
        }))
        .filter_map(|config| config.build().ok())
        .collect()
}

/// The condition of an event (`key` is `events[k].condition`), checked: one test, its own keys only,
/// thresholds in range, an outcome the run's `laws` declare, a conjunction monitor for `conjunction`
/// (`conjunctions_monitored`: the scenario has `[conjunctions]`).
fn condition(
    c: &Checker<'_>,
    key: &str,
    s: &ConditionSection,
    laws: &[Law],
    config: &SimulationConfig,
    count: usize,
    conjunctions_monitored: bool,
) -> Result<Condition, ScenarioError> {
    let sub = |name: &str| format!("{key}.{name}");
    let tests: Vec<&str> = [
        ("min_separation_below_m", s.min_separation_below_m.is_some()),
        ("threat_within_m", s.threat_within_m.is_some()),
        ("formation_reached", s.formation_reached.is_some()),
        (
            "satellites_lost_at_least",
            s.satellites_lost_at_least.is_some(),
        ),
        ("conjunction", s.conjunction.is_some()),
        ("law_outcome", s.law_outcome.is_some()),
    ]
    .into_iter()
    .filter_map(|(name, given)| given.then_some(name))
    .collect();
    let allowed = "min_separation_below_m, threat_within_m, formation_reached, \
                   satellites_lost_at_least, conjunction or law_outcome";
    let test_key = match tests.as_slice() {
        [one] => *one,
        [] => {
            return Err(c.keys(
                key,
                format!("names no condition (allowed: one of {allowed})"),
                "",
            ))
        }
        [_, second, ..] => {
            return Err(c.keys(
                &sub(second),
                format!("a condition tests one thing (allowed: one of {allowed})"),
                "",
            ))
        }
    };
    // Keys that belong to another test than this one.
    let strays = [
        (
            "uniformity_l",
            s.uniformity_l.is_some(),
            "formation_reached",
        ),
        (
            "uniformity_tolerance",
            s.uniformity_tolerance.is_some(),
            "formation_reached",
        ),
        ("above", s.above.is_some(), "law_outcome"),
        ("below", s.below.is_some(), "law_outcome"),
    ];
    if let Some((name, _, owner)) = strays
        .iter()
        .find(|(_, given, owner)| *given && *owner != test_key)
    {
        return Err(c.keys(
            &sub(name),
            format!("goes with `{owner}`, not with `{test_key}`"),
            "",
        ));
    }
    let distance = matches!(test_key, "min_separation_below_m" | "threat_within_m");
    let numeric = matches!(test_key, "law_outcome")
        || (test_key == "formation_reached" && s.uniformity_l.is_some());
    let hysteresis = match (s.hysteresis_m, s.hysteresis) {
        (Some(_), _) if !distance => {
            return Err(c.keys(
                &sub("hysteresis_m"),
                format!(
                    "goes with a distance condition (min_separation_below_m, threat_within_m), \
                     not with `{test_key}`{}",
                    if numeric { " (use `hysteresis`)" } else { "" }
                ),
                "",
            ))
        }
        (_, Some(_)) if !numeric => {
            return Err(c.keys(
                &sub("hysteresis"),
                format!(
                    "goes with law_outcome or uniformity_l, not with `{test_key}`{}",
                    if distance {
                        " (use `hysteresis_m`)"
                    } else {
                        ""
                    }
                ),
                "",
            ))
        }
        (Some(h), _) => c.non_negative(&sub("hysteresis_m"), h)?,
        (_, Some(h)) => c.non_negative(&sub("hysteresis"), h)?,
        (None, None) => 0.0,
    };
    let repeat = s.repeat.unwrap_or(false);
    let test = match test_key {
        "min_separation_below_m" => ConditionTest::MinSeparationBelow {
            threshold_m: c.positive(&sub(test_key), s.min_separation_below_m.unwrap_or(0.0))?,
        },
        "threat_within_m" => {
            let distance_m = c.positive(&sub(test_key), s.threat_within_m.unwrap_or(0.0))?;
            if config.threats.is_empty() {
                return Err(c.keys(
                    &sub(test_key),
                    "the scenario has no [[threats]] to approach (add one, or remove this condition)", ""
                ));
            }
            ConditionTest::ThreatWithin { distance_m }
        }
        "formation_reached" => formation(c, key, s, laws)?,
        "satellites_lost_at_least" => {
            let k = s.satellites_lost_at_least.unwrap_or(0);
            let n = count;
            if !(1..=n).contains(&k) {
                return Err(c.keys(
                    &sub(test_key),
                    format!("{k} is out of range (allowed: 1..={n}, the satellites of the swarm)"),
                    "",
                ));
            }
            if repeat {
                return Err(c.keys(
                    &sub("repeat"),
                    "removed satellites do not come back, so this condition fires once (allowed: \
                     repeat = false)",
                    "",
                ));
            }
            ConditionTest::SatellitesLostAtLeast(k)
        }
        "conjunction" => {
            if s.conjunction != Some(true) {
                return Err(c.keys(
                    &sub(test_key),
                    "allowed: true (the condition fires when the conjunction monitor finds an \
                     encounter)",
                    "",
                ));
            }
            if !conjunctions_monitored {
                return Err(c.keys(
                    &sub(test_key),
                    "the scenario has no conjunction monitor (add [conjunctions] threshold_m, or \
                     remove this condition)",
                    "",
                ));
            }
            ConditionTest::Conjunction
        }
        _ => law_outcome(c, key, s, laws)?,
    };
    Ok(Condition {
        test,
        hysteresis,
        repeat,
    })
}

/// `formation_reached = true`: the law's own report ([`SHAPE_REACHED`]), or the uniformity L within a
/// tolerance of a target.
fn formation(
    c: &Checker<'_>,
    key: &str,
    s: &ConditionSection,
    laws: &[Law],
) -> Result<ConditionTest, ScenarioError> {
    let sub = |name: &str| format!("{key}.{name}");
    if s.formation_reached != Some(true) {
        return Err(c.keys(
            &sub("formation_reached"),
            "allowed: true (the condition fires when the formation is reached)",
            "",
        ));
    }
    match (s.uniformity_l, s.uniformity_tolerance) {
        (Some(target), Some(tolerance)) => Ok(ConditionTest::UniformityWithin {
            target: c.non_negative(&sub("uniformity_l"), target)?,
            tolerance: c.non_negative(&sub("uniformity_tolerance"), tolerance)?,
        }),
        (Some(_), None) => Err(c.keys(
            &sub("uniformity_tolerance"),
            "missing: uniformity_l needs uniformity_tolerance (the largest |L - target| that \
             counts as reached)",
            "",
        )),
        (None, Some(_)) => Err(c.keys(
            &sub("uniformity_l"),
            "missing: uniformity_tolerance needs uniformity_l (the target L)",
            "",
        )),
        (None, None) => {
            if laws
                .iter()
                .any(|law| law.metric_names().contains(&SHAPE_REACHED))
            {
                Ok(ConditionTest::ShapeReached)
            } else {
                let names: Vec<&str> = laws.iter().map(Law::name).collect();
                Err(c.keys(
                    &sub("formation_reached"),
                    format!(
                        "no law of this run reports whether its formation is reached (`{SHAPE_REACHED}`; \
                         laws: {}); give uniformity_l and uniformity_tolerance to test the five \
                         elements' uniformity L instead",
                        names.join(", ")
                    ), ""
                ))
            }
        }
    }
}

/// `law_outcome = "NAME"` with `above` or `below`: NAME must be a declared outcome (a headline) of
/// a law of the run.
fn law_outcome(
    c: &Checker<'_>,
    key: &str,
    s: &ConditionSection,
    laws: &[Law],
) -> Result<ConditionTest, ScenarioError> {
    let sub = |name: &str| format!("{key}.{name}");
    let name = s.law_outcome.clone().unwrap_or_default();
    let mut declared: Vec<&str> = laws
        .iter()
        .flat_map(|law| law.headlines().iter().map(|h| h.name))
        .collect();
    declared.dedup();
    if !declared.contains(&name.as_str()) {
        return Err(c.keys(
            &sub("law_outcome"),
            format!(
                "`{name}` is not an outcome the laws of this run declare (allowed: {})",
                if declared.is_empty() {
                    "none: the laws of this run declare no outcome".to_string()
                } else {
                    declared.join(", ")
                }
            ),
            "",
        ));
    }
    let bound = match (s.above, s.below) {
        (Some(x), None) => Bound::Above(finite(c, &sub("above"), x)?),
        (None, Some(x)) => Bound::Below(finite(c, &sub("below"), x)?),
        (Some(_), Some(_)) => {
            return Err(c.keys(&sub("below"), "give `above` or `below`, not both", ""))
        }
        (None, None) => return Err(c.keys(
            &sub("above"),
            "missing: law_outcome needs `above = VALUE` or `below = VALUE` (in the outcome's unit)",
            "",
        )),
    };
    Ok(ConditionTest::LawOutcome { name, bound })
}

fn finite(c: &Checker<'_>, key: &str, x: f64) -> Result<f64, ScenarioError> {
    c.finite(key, &[x]).map(|_| x)
}

/// The action of event `k`, with the law in force after it (`current` unless it changes the law).
fn action(
    c: &Checker<'_>,
    scenario: &Scenario,
    k: usize,
    current: &LawConfig,
    count: usize,
    config: &SimulationConfig,
    min_mass_kg: f64,
) -> Result<(LawConfig, EventAction), ScenarioError> {
    let event = scenario.event_key(k);
    let key = |name: &str| format!("{event}.{name}");
    let mut law = current.clone();
    let action = match &scenario.file.events[k].action {
        ActionSection::SetLawParameters { parameters } => {
            let merged = merge_law_parameters(current, parameters).map_err(|err| {
                c.keys(
                    &key("parameters"),
                    format!("law `{}`: {err}", current.name()),
                    "",
                )
            })?;
            build_law(c, &key("parameters"), &merged, config, count, min_mass_kg)?;
            law = merged.clone();
            EventAction::SetLawParameters(merged.into_parameters())
        }
        ActionSection::SwitchLaw { law: next } => {
            let built = build_law(c, &key("law"), next, config, count, min_mass_kg)?;
            law = next.clone();
            EventAction::SwitchLaw(built)
        }
        ActionSection::ThreatWarning { threat, active } => EventAction::ThreatWarning {
            threat: if *threat < config.threats.len() {
                *threat
            } else if config.threats.is_empty() {
                return Err(c.keys(
                    &key("threat"),
                    "the scenario has no [[threats]] to warn about (add one, or remove this \
                     threat-warning event)",
                    "",
                ));
            } else {
                return Err(c.keys(
                    &key("threat"),
                    format!(
                        "threat {threat} does not exist (allowed: 0..{}, the [[threats]] of the scenario)",
                        config.threats.len()
                    ), ""
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
                return Err(c.keys(
                    &key("satellite"),
                    format!(
                        "satellite {id} is reference.origin_member, the origin of the relative \
                         frame; removing it would freeze the frame (allowed: any other satellite, \
                         or origin = \"virtual\")"
                    ),
                    "",
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
        ActionSection::StopRun => EventAction::StopRun,
        ActionSection::RecordSnapshot => EventAction::RecordSnapshot,
    };
    Ok((law, action))
}

fn selection(
    c: &Checker<'_>,
    key: &str,
    s: &SelectionSection,
    count: usize,
) -> Result<Selection, ScenarioError> {
    match s {
        SelectionSection::Word(w) if w == "all" => Ok(Selection::All),
        SelectionSection::Word(w) => Err(c.keys(
            key,
            format!("`{w}` is not allowed (allowed: \"all\" or a list of satellite indices)"),
            "",
        )),
        SelectionSection::Ids(ids) => {
            for &i in ids {
                c.index(key, i, count)?;
            }
            Ok(Selection::Satellites(ids.clone()))
        }
    }
}
