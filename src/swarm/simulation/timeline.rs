//! The event timeline: the timed events that fall due, the condition events evaluated at every tick
//! (`conditions.rs` gives their values), the actions of both (law parameters and switches, ground
//! messages, link outages, satellite losses, thruster failures, stopping the run, an extra
//! recording) and the log of every firing.

use crate::swarm::events::{Condition, Event, EventAction, Firing, Selection, ThrustAxis, Trigger};
use crate::swarm::simulation::{check_law_fits, SimError, Simulation};

/// The event timeline and what it has set in force.
pub(super) struct Timeline {
    /// Pending timed events, latest first (popped from the back).
    pub events: Vec<Event>,
    /// The condition events, in index order.
    pub conditions: Vec<ConditionEvent>,
    /// Per threat: whether a ground warning about it is in force.
    pub threat_warnings: Vec<bool>,
    /// Every firing so far, in firing order.
    pub fired: Vec<Firing>,
    /// How many of `fired` the recorder has been handed.
    pub fired_sent: usize,
    /// The `stop-run` firing that ended the run, once one has fired.
    pub stop: Option<Firing>,
    /// A `record-snapshot` fired at this time: the recorder gets a snapshot now.
    pub snapshot_requested: bool,
}

/// A condition event and where it stands.
pub(super) struct ConditionEvent {
    /// Its index in the scenario's `[[events]]`.
    pub index: usize,
    pub condition: Condition,
    /// The action; `None` once a law action that fires once has been handed over.
    pub action: Option<EventAction>,
    /// Whether it fires at the next tick at which the condition holds.
    pub armed: bool,
}

impl Timeline {
    /// The timeline of `events` (timed events sorted by time, file order for equal times; condition
    /// events by index), with `threats` threat warnings off.
    pub fn new(events: Vec<Event>, threats: usize) -> Self {
        let (mut timed, conditional): (Vec<Event>, Vec<Event>) = events
            .into_iter()
            .partition(|e| matches!(e.trigger, Trigger::Time(_)));
        // Stable sort keeps the file order of simultaneous events; reversed so that pop() is the next.
        timed.sort_by(|a, b| {
            let time = |e: &Event| e.time_s().unwrap_or(f64::INFINITY);
            time(a).total_cmp(&time(b))
        });
        timed.reverse();
        let mut conditions: Vec<ConditionEvent> = conditional
            .into_iter()
            .filter_map(|e| match e.trigger {
                Trigger::Condition(condition) => Some(ConditionEvent {
                    index: e.index,
                    condition,
                    action: Some(e.action),
                    armed: true,
                }),
                Trigger::Time(_) => None,
            })
            .collect();
        conditions.sort_by_key(|c| c.index);
        Self {
            events: timed,
            conditions,
            threat_warnings: vec![false; threats],
            fired: Vec::new(),
            fired_sent: 0,
            stop: None,
            snapshot_requested: false,
        }
    }

    /// The time of the next timed event \[s\] (infinite when none is pending).
    pub fn next_time_s(&self) -> f64 {
        self.events
            .last()
            .and_then(Event::time_s)
            .unwrap_or(f64::INFINITY)
    }

    /// The actions still pending, timed and conditional.
    pub fn pending_actions(&self) -> impl Iterator<Item = &EventAction> {
        self.events
            .iter()
            .rev()
            .map(|e| &e.action)
            .chain(self.conditions.iter().filter_map(|c| c.action.as_ref()))
    }
}

impl Simulation {
    /// Applies every pending timed event whose time has come (in time order, file order for equal
    /// times), logging each.
    pub(super) fn apply_due_events(&mut self) -> Result<(), SimError> {
        let eps = self.config.time_epsilon_s();
        while self.timeline.next_time_s() <= self.clock.time_s + eps {
            let event = self.timeline.events.pop().expect("checked non-empty");
            let firing = self.firing(event.index, "time_s", None, &event.action);
            self.apply_action(event.action, firing)?;
        }
        Ok(())
    }

    /// Evaluates every condition event on the truth now and applies those that fire, in index order
    /// (all are evaluated before any applies, so the order of the events does not change which fire).
    pub(super) fn apply_condition_events(&mut self) -> Result<(), SimError> {
        if self.timeline.conditions.iter().all(|c| c.action.is_none()) {
            return Ok(());
        }
        let values = self.condition_values();
        let mut due = Vec::new();
        for (c, value) in self.timeline.conditions.iter_mut().zip(values) {
            if c.action.is_none() {
                continue;
            }
            let test = &c.condition.test;
            if c.armed {
                if test.holds(value) {
                    c.armed = false;
                    // A law action is handed over: its event fires once even if it repeats.
                    let copy = c
                        .condition
                        .repeat
                        .then(|| c.action.as_ref()?.repeatable_copy());
                    let action = copy.flatten().or_else(|| c.action.take());
                    due.extend(action.map(|a| (c.index, test.key(), value, a)));
                }
            } else if c.condition.repeat && test.rearms(value, c.condition.hysteresis) {
                c.armed = true;
            }
        }
        for (index, key, value, action) in due {
            let firing = self.firing(index, key, value, &action);
            self.apply_action(action, firing)?;
        }
        Ok(())
    }

    /// The log entry of event `index` firing now.
    fn firing(
        &self,
        index: usize,
        trigger: &'static str,
        value: Option<f64>,
        action: &EventAction,
    ) -> Firing {
        Firing {
            event: index,
            time_s: self.clock.time_s,
            tick: self.clock.step_count,
            trigger,
            value,
            action: action.name(),
        }
    }

    /// Applies one action and logs its firing.
    fn apply_action(&mut self, action: EventAction, firing: Firing) -> Result<(), SimError> {
        match action {
            EventAction::SetLawParameters(parameters) => {
                self.law.set_parameters(&parameters)?;
                check_law_fits(&self.law, &self.config, self.min_mass_kg())?;
            }
            EventAction::SwitchLaw(law) => {
                check_law_fits(&law, &self.config, self.min_mass_kg())?;
                self.law = law;
                self.sensed.grids.neighbours = self.law.senses_neighbours();
                self.initialise_law()?;
            }
            EventAction::ThreatWarning { threat, active } => {
                self.timeline.threat_warnings[threat] = active;
            }
            EventAction::CutLinks(selection) => self.set_links(&selection, false),
            EventAction::RestoreLinks(selection) => self.set_links(&selection, true),
            EventAction::RemoveSatellite(id) => {
                let index = self.satellites.fleet.order.index_of(id);
                self.satellites.fleet.active[index] = false;
            }
            EventAction::FailThruster { satellite, axis } => {
                let index = self.satellites.fleet.order.index_of(satellite);
                let axes = &mut self.satellites.fleet.actuators[index].working_axes;
                match axis {
                    ThrustAxis::X => axes[0] = false,
                    ThrustAxis::Y => axes[1] = false,
                    ThrustAxis::Z => axes[2] = false,
                    ThrustAxis::All => *axes = [false; 3],
                }
            }
            EventAction::StopRun => {
                if self.timeline.stop.is_none() {
                    self.timeline.stop = Some(firing.clone());
                }
            }
            EventAction::RecordSnapshot => self.timeline.snapshot_requested = true,
        }
        self.timeline.fired.push(firing);
        Ok(())
    }

    /// Sets the link flag of every satellite `selection` names to `up`.
    fn set_links(&mut self, selection: &Selection, up: bool) {
        let order = &self.satellites.fleet.order;
        for (index, links_up) in self.satellites.fleet.links_up.iter_mut().enumerate() {
            if selection.contains(order.id_at(index)) {
                *links_up = up;
            }
        }
    }

    /// Mass of the lightest satellite \[kg\] (the one with the fastest closed-loop rate).
    fn min_mass_kg(&self) -> f64 {
        self.satellites
            .fleet
            .masses_kg
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min)
    }

    /// Every event firing so far, in firing order.
    pub fn fired_events(&self) -> &[Firing] {
        &self.timeline.fired
    }

    /// The `stop-run` firing that ended the run, if one did.
    pub fn stopped_by(&self) -> Option<&Firing> {
        self.timeline.stop.as_ref()
    }
}
