//! Applying the events of the timeline that fall due: law parameters and switches, ground messages,
//! link outages, satellite losses and thruster failures.

use crate::swarm::events::Event;
use crate::swarm::events::{EventAction, Selection, ThrustAxis};
use crate::swarm::simulation::{check_law_fits, SimError, Simulation};

/// The event timeline and what it has set in force.
pub(super) struct Timeline {
    /// Pending events, latest first (popped from the back).
    pub events: Vec<Event>,
    /// Per threat: whether a ground warning about it is in force.
    pub threat_warnings: Vec<bool>,
}

impl Simulation {
    /// Applies every pending event whose time has come (in time order, file order for equal times).
    pub(super) fn apply_due_events(&mut self) -> Result<(), SimError> {
        let eps = self.config.time_epsilon_s();
        while self
            .timeline
            .events
            .last()
            .is_some_and(|e| e.time_s <= self.clock.time_s + eps)
        {
            let event = self.timeline.events.pop().expect("checked non-empty");
            match event.action {
                EventAction::SetLawParameters(parameters) => {
                    self.law.set_parameters(&parameters)?;
                    check_law_fits(&self.law, &self.config, self.min_mass_kg())?;
                }
                EventAction::SwitchLaw(law) => {
                    check_law_fits(&law, &self.config, self.min_mass_kg())?;
                    self.law = law;
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
            }
        }
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
}
