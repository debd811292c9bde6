//! A law as the engine holds it: [`Law`] wraps any [`GuidanceLaw`] together with the per-satellite states
//! of every satellite (two buffers: the states of the previous tick, read by every update, and the
//! states being written), behind one object-safe interface. [`LawParameters`] carries a law's typed
//! parameter set through the event timeline.

use std::any::Any;
use std::collections::BTreeMap;

use nalgebra::Vector3;
use rayon::prelude::*;

use super::{
    Broadcast, CommandKind, GuidanceLaw, LawContext, LawError, SatelliteView, SwarmFacts, SwarmView,
};

/// Smallest number of satellites per parallel work item (results never depend on the split: each
/// satellite's new state is computed on its own).
const CHUNK: usize = 256;

/// A typed parameter set for a law, carried by a `set-law-parameters` event. The law it reaches checks
/// that it is of its own [`GuidanceLaw::Parameters`] type.
pub struct LawParameters(Box<dyn Any + Send + Sync>);

impl LawParameters {
    /// Wraps a law's parameter set.
    pub fn new<P: Any + Send + Sync>(parameters: P) -> Self {
        Self(Box::new(parameters))
    }
}

impl std::fmt::Debug for LawParameters {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("LawParameters(..)")
    }
}

/// The object-safe face of a law with its states (implemented once, for [`Stateful`]).
trait ErasedLaw: Send + Sync {
    fn name(&self) -> &'static str;
    fn is_stateful(&self) -> bool;
    fn command_kind(&self) -> CommandKind;
    fn fastest_rate_per_s(&self, mass_kg: f64) -> Option<f64>;
    fn check_swarm(&self, swarm: &SwarmFacts) -> Result<(), LawError>;
    fn output_names(&self) -> &'static [&'static str];
    fn metric_names(&self) -> &'static [&'static str];
    fn initialise(&mut self, swarm: &SwarmView<'_>) -> Result<(), LawError>;
    fn update_states(
        &mut self,
        swarm: &SwarmView<'_>,
        active: &[bool],
        context: &(dyn Fn(usize) -> LawContext + Sync),
    );
    fn command(&self, satellite: &SatelliteView<'_>, context: &LawContext) -> Vector3<f64>;
    fn set_parameters(&mut self, parameters: &LawParameters) -> Result<(), LawError>;
    fn write_outputs(&self, values: &mut [f64]);
    fn record_metrics(&mut self, swarm: &SwarmView<'_>, values: &mut [f64]);
    fn centralised_due(&self, time_s: f64) -> bool;
    fn centralised_update(&mut self, swarm: &SwarmView<'_>) -> Result<(), LawError>;
    fn results(&self, swarm: &SwarmView<'_>) -> BTreeMap<String, serde_json::Value>;
    fn target_formation_hill_m(&self) -> Option<Vec<Vector3<f64>>>;
    fn as_any(&self) -> &dyn Any;
}

/// A law and its per-satellite states.
struct Stateful<L: GuidanceLaw> {
    law: L,
    /// States after the last update (read by commands, outputs and the next update).
    current: Vec<L::State>,
    /// Buffer the next update writes into.
    next: Vec<L::State>,
}

impl<L: GuidanceLaw> ErasedLaw for Stateful<L> {
    fn name(&self) -> &'static str {
        self.law.name()
    }

    fn is_stateful(&self) -> bool {
        std::mem::size_of::<L::State>() != 0
    }

    fn command_kind(&self) -> CommandKind {
        self.law.command_kind()
    }

    fn fastest_rate_per_s(&self, mass_kg: f64) -> Option<f64> {
        self.law.fastest_rate_per_s(mass_kg)
    }

    fn check_swarm(&self, swarm: &SwarmFacts) -> Result<(), LawError> {
        self.law.check_swarm(swarm)
    }

    fn output_names(&self) -> &'static [&'static str] {
        self.law.output_names()
    }

    fn metric_names(&self) -> &'static [&'static str] {
        self.law.metric_names()
    }

    fn initialise(&mut self, swarm: &SwarmView<'_>) -> Result<(), LawError> {
        self.current = vec![L::State::default(); swarm.len()];
        self.next = self.current.clone();
        self.law.initialise(swarm, &mut self.current)
    }

    fn update_states(
        &mut self,
        swarm: &SwarmView<'_>,
        active: &[bool],
        context: &(dyn Fn(usize) -> LawContext + Sync),
    ) {
        if !self.is_stateful() {
            return; // a memoryless law: nothing to update
        }
        let law = &self.law;
        let previous = &self.current;
        self.next
            .par_iter_mut()
            .with_min_len(CHUNK)
            .enumerate()
            .for_each(|(i, next)| {
                *next = if active[i] {
                    law.update_state(
                        &swarm.satellite(i),
                        &Broadcast::new(i, previous),
                        &context(i),
                    )
                } else {
                    previous[i].clone()
                };
            });
        std::mem::swap(&mut self.current, &mut self.next);
    }

    fn command(&self, satellite: &SatelliteView<'_>, context: &LawContext) -> Vector3<f64> {
        self.law
            .command(satellite, &self.current[satellite.id()], context)
    }

    fn set_parameters(&mut self, parameters: &LawParameters) -> Result<(), LawError> {
        let typed =
            parameters
                .0
                .downcast_ref::<L::Parameters>()
                .ok_or(LawError::ParameterType {
                    law: self.law.name(),
                    expected: std::any::type_name::<L::Parameters>(),
                })?;
        self.law.set_parameters(typed)
    }

    fn write_outputs(&self, values: &mut [f64]) {
        let k = self.law.output_names().len();
        if k == 0 {
            return;
        }
        for (state, row) in self.current.iter().zip(values.chunks_mut(k)) {
            self.law.write_outputs(state, row);
        }
    }

    fn record_metrics(&mut self, swarm: &SwarmView<'_>, values: &mut [f64]) {
        self.law.record_metrics(swarm, &self.current, values);
    }

    fn centralised_due(&self, time_s: f64) -> bool {
        self.law.centralised_due(time_s)
    }

    fn centralised_update(&mut self, swarm: &SwarmView<'_>) -> Result<(), LawError> {
        self.law.centralised_update(swarm)
    }

    fn results(&self, swarm: &SwarmView<'_>) -> BTreeMap<String, serde_json::Value> {
        self.law.results(swarm, &self.current)
    }

    fn target_formation_hill_m(&self) -> Option<Vec<Vector3<f64>>> {
        self.law.target_formation_hill_m()
    }

    fn as_any(&self) -> &dyn Any {
        &self.law
    }
}

/// A guidance law with the per-satellite states of every satellite, ready for the engine.
pub struct Law(Box<dyn ErasedLaw>);

impl Law {
    /// Wraps a law. Its states are created (as `Default`) when the engine initialises it.
    pub fn new<L: GuidanceLaw>(law: L) -> Self {
        Self(Box::new(Stateful {
            law,
            current: Vec::new(),
            next: Vec::new(),
        }))
    }

    /// Registry name of the law.
    pub fn name(&self) -> &'static str {
        self.0.name()
    }

    /// Whether the law keeps a per-satellite state (a zero-sized state means it does not, and the engine
    /// skips its update).
    pub fn is_stateful(&self) -> bool {
        self.0.is_stateful()
    }

    /// What the law commands.
    pub fn command_kind(&self) -> CommandKind {
        self.0.command_kind()
    }

    /// See [`GuidanceLaw::check_swarm`].
    pub fn check_swarm(&self, swarm: &SwarmFacts) -> Result<(), LawError> {
        self.0.check_swarm(swarm)
    }

    /// See [`GuidanceLaw::fastest_rate_per_s`] \[1/s\].
    pub fn fastest_rate_per_s(&self, mass_kg: f64) -> Option<f64> {
        self.0.fastest_rate_per_s(mass_kg)
    }

    /// Names of the per-satellite outputs ([`GuidanceLaw::output_names`]).
    pub fn output_names(&self) -> &'static [&'static str] {
        self.0.output_names()
    }

    /// Names of the law's metrics ([`GuidanceLaw::metric_names`]).
    pub fn metric_names(&self) -> &'static [&'static str] {
        self.0.metric_names()
    }

    /// The formation the law steers to, Hill frame relative to the LVLH origin \[m\]
    /// ([`GuidanceLaw::target_formation_hill_m`]; `None` when the law has no fixed target points).
    pub fn target_formation_hill_m(&self) -> Option<Vec<Vector3<f64>>> {
        self.0.target_formation_hill_m()
    }

    /// The law itself, if it is of type `L` (e.g. to read a law's own results after a run).
    pub fn downcast_ref<L: GuidanceLaw>(&self) -> Option<&L> {
        self.0.as_any().downcast_ref::<L>()
    }

    /// Writes every satellite's per-satellite outputs into `values` (satellite-major: satellite i's
    /// outputs at `i * k .. (i + 1) * k`, k = the number of output names).
    pub fn write_outputs(&self, values: &mut [f64]) {
        self.0.write_outputs(values)
    }

    pub(crate) fn initialise(&mut self, swarm: &SwarmView<'_>) -> Result<(), LawError> {
        self.0.initialise(swarm)
    }

    pub(crate) fn update_states(
        &mut self,
        swarm: &SwarmView<'_>,
        active: &[bool],
        context: &(dyn Fn(usize) -> LawContext + Sync),
    ) {
        self.0.update_states(swarm, active, context)
    }

    pub(crate) fn command(
        &self,
        satellite: &SatelliteView<'_>,
        context: &LawContext,
    ) -> Vector3<f64> {
        self.0.command(satellite, context)
    }

    pub(crate) fn set_parameters(&mut self, parameters: &LawParameters) -> Result<(), LawError> {
        self.0.set_parameters(parameters)
    }

    pub(crate) fn record_metrics(&mut self, swarm: &SwarmView<'_>, values: &mut [f64]) {
        self.0.record_metrics(swarm, values)
    }

    pub(crate) fn centralised_due(&self, time_s: f64) -> bool {
        self.0.centralised_due(time_s)
    }

    pub(crate) fn centralised_update(&mut self, swarm: &SwarmView<'_>) -> Result<(), LawError> {
        self.0.centralised_update(swarm)
    }

    pub(crate) fn results(&self, swarm: &SwarmView<'_>) -> BTreeMap<String, serde_json::Value> {
        self.0.results(swarm)
    }
}

impl std::fmt::Debug for Law {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Law({})", self.name())
    }
}
