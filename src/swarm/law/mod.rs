//! The interface between the engine and a guidance law.
//!
//! * [`GuidanceLaw`]: the **core** every law implements — its parameters, a per-satellite **state**
//!   (its own type, stored by the engine for every satellite; `()` for none), a per-tick state
//!   **update**, and a **command** (an acceleration, or a velocity in the kinematic mode) from what one
//!   satellite senses.
//! * The **capabilities** (module `capability`), optional traits a law implements only if it has
//!   them and declares with [`capabilities!`](crate::capabilities): [`Centralised`] (a periodic step
//!   with the whole swarm), [`Reports`] (typed results for `summary.json` and the headline outcomes),
//!   [`Diagnostics`] (trajectory and metrics columns), [`TargetFormation`] (the points it steers to)
//!   and [`CommandsDrag`] (a drag attitude per satellite).
//! * [`SatelliteView`] / [`SwarmView`] (module `view`): the read-only sensing views the engine builds.
//! * [`LawContext`] (module `context`): what a law may use besides its view — its own random stream, the
//!   control period and its satellite's actuator.
//! * [`Headline`] (module `headline`): a law's headline outcomes ([`Reports::headlines`]), the rows
//!   `satflock compare` shows for it.
//! * [`Law`] (module `handle`): a law together with the per-satellite states of every satellite, as the
//!   engine holds it (the one type-erased layer); it runs the double-buffered (or, for a law that reads
//!   only its own state, in-place) state update in parallel.
//!
//! Decentralisation is enforced by the types: a law computes one satellite's new state and command from a
//! [`SatelliteView`] (its own navigation state, the neighbours its sensors and links reach, the threats and
//! obstacles within its sensing range, the ground messages in force) and what those neighbours broadcast
//! at the previous tick ([`Broadcast`]). Only [`GuidanceLaw::initialise`] (once, before the run or after a
//! law switch), [`Centralised::centralised_update`] (a periodic **centralised** step the law schedules
//! itself, e.g. a ground-computed grouping) and the recording hooks ([`Diagnostics::record_metrics`],
//! [`Reports::results`]) see the whole swarm.
//!
//! Every vector here is in the engine's internal LVLH convention, Hill/RSW (x radial out, y along-track,
//! z orbit normal), relative to the LVLH origin (the virtual reference orbit or a member satellite). Laws
//! written in another convention (Gao's o-xyz) convert at their boundary with
//! [`crate::orbit::hill_to_gao`] / [`crate::orbit::gao_to_hill`].

mod capability;
mod context;
mod handle;
mod headline;
mod state_pass;
#[cfg(test)]
mod test_swarm;
mod view;

use nalgebra::Vector3;
use thiserror::Error;

pub use capability::{
    Centralised, CommandsDrag, Diagnostics, Reports, SerialisedReports, TargetFormation,
};
pub use context::LawContext;
pub(crate) use handle::{own_batch, TickEvaluation, OWN_BATCH};
pub use handle::{Law, LawParameters};
pub use headline::{Better, Headline};
pub(crate) use view::OwnSample;
pub use view::{
    Broadcast, EnvironmentView, Neighbour, SatelliteView, SensedObstacle, SensedThreat, SharedInfo,
    SwarmFacts, SwarmView,
};

/// What a law's command is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CommandKind {
    /// An acceleration, Hill frame \[m/s^2\], applied through the actuators (dynamic models).
    Acceleration,
    /// A velocity, Hill frame \[m/s\], followed exactly (the kinematic model only).
    Velocity,
}

/// A law's failure to accept its parameters or to start.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum LawError {
    /// A parameter is missing, unknown, of the wrong type or out of range: the one typed error of
    /// the scenario layer ([`crate::invalid::Invalid`]: the key in the law's table, the value, what is
    /// allowed).
    #[error("law `{law}`: {invalid}")]
    InvalidParameters {
        /// The law's registry name.
        law: String,
        /// The key, the value and what is allowed.
        invalid: crate::invalid::Invalid,
    },
    /// Parameters of another law's type were handed to this law.
    #[error("law `{law}` takes parameters of type `{expected}`")]
    ParameterType {
        /// The law's registry name.
        law: &'static str,
        /// The parameter type the law takes.
        expected: &'static str,
    },
    /// The law failed while the run was going (from [`Centralised::centralised_update`]): a law that
    /// calls code outside the engine (a guidance law written in Python) raised an error or returned
    /// commands that cannot be used. The run stops with this error and its outputs stay valid.
    #[error("law `{law}` failed at t = {time_s} s: {message}")]
    Failed {
        /// The law's name.
        law: String,
        /// Time of the tick at which it failed \[s\].
        time_s: f64,
        /// What went wrong.
        message: String,
    },
}

impl LawError {
    /// The law `law` refuses a parameter: `invalid` names it, its value and what is allowed.
    pub fn invalid(law: &str, invalid: crate::invalid::Invalid) -> Self {
        Self::InvalidParameters {
            law: law.to_string(),
            invalid,
        }
    }
}

/// A guidance law's core: maps what one satellite senses, and its own state, to its command. A law
/// must give [`GuidanceLaw::name`], [`GuidanceLaw::command`] and [`GuidanceLaw::set_parameters`]; the
/// other methods have defaults, and what a law may do besides is a capability (see the module docs),
/// declared with [`capabilities!`](crate::capabilities), which writes the `as_*` accessors.
///
/// **Per-tick order** (see `DESIGN.md`): sense → [`GuidanceLaw::update_state`] for every satellite →
/// [`GuidanceLaw::command`] → actuate → integrate → monitor → record. The update runs once per control
/// tick (sampled mode) or once per integration step (continuous mode), outside the integrator's
/// right-hand side, in parallel over satellites, and is double-buffered: satellite i's update reads its
/// own previous state and its neighbours' previous states, never a state written in the same tick, so the
/// result does not depend on satellite order or thread count (a law that reads no neighbour's state
/// declares it with [`GuidanceLaw::reads_neighbour_broadcasts`] and is updated in place, with the same
/// result). The command may run many times per step
/// (once per Runge–Kutta stage in continuous mode) and only reads the state.
///
/// Implementations must be deterministic functions of their inputs: randomness comes only from
/// [`LawContext::random`], so runs are reproducible on any thread count. A law never touches the
/// integrator or the truth state.
pub trait GuidanceLaw: Send + Sync + 'static {
    /// Per-satellite state kept by the engine between ticks (`()` for a memoryless law).
    type State: Clone + Default + Send + Sync + 'static;
    /// The law's parameter set, as replaced by a `set-law-parameters` event (already validated by the
    /// scenario layer when the scenario was loaded).
    type Parameters: Send + Sync + 'static;

    /// Registry name of the law (as written in scenario files).
    fn name(&self) -> &'static str;

    /// What [`GuidanceLaw::command`] returns. Default: an acceleration. The engine refuses a velocity law
    /// on a dynamic model and an acceleration law on the kinematic model.
    fn command_kind(&self) -> CommandKind {
        CommandKind::Acceleration
    }

    /// Called once before the run starts, and again when the law is switched in by an event, with the
    /// whole swarm and every satellite's state (all `Default` on entry). Default: nothing to do.
    fn initialise(
        &mut self,
        _swarm: &SwarmView<'_>,
        _states: &mut [Self::State],
    ) -> Result<(), LawError> {
        Ok(())
    }

    /// Satellite `satellite.id()`'s new state, from what it senses now, its own previous state and what
    /// its neighbours broadcast at the previous tick. Default: the state is kept.
    fn update_state(
        &self,
        _satellite: &SatelliteView<'_>,
        broadcast: &Broadcast<'_, Self::State>,
        _context: &LawContext,
    ) -> Self::State {
        broadcast.own().clone()
    }

    /// [`GuidanceLaw::update_state`] written into `state`, which on entry holds an outdated state (of
    /// this or another satellite) whose allocations the law may reuse: the engine calls this one, so a
    /// law with heap-backed states can avoid allocating every tick. It must leave exactly the value
    /// `update_state` returns, whatever `state` held. Default: `*state = self.update_state(..)`.
    fn update_state_into(
        &self,
        satellite: &SatelliteView<'_>,
        broadcast: &Broadcast<'_, Self::State>,
        context: &LawContext,
        state: &mut Self::State,
    ) {
        *state = self.update_state(satellite, broadcast, context);
    }

    /// The command of one satellite, Hill frame: an acceleration \[m/s^2\] before actuator limits, or a
    /// velocity \[m/s\] for a kinematic law (see [`GuidanceLaw::command_kind`]).
    fn command(
        &self,
        satellite: &SatelliteView<'_>,
        state: &Self::State,
        context: &LawContext,
    ) -> Vector3<f64>;

    /// Replaces the parameters (an event of the timeline; the scenario layer has merged the event's keys
    /// with the current values and validated the result).
    fn set_parameters(&mut self, parameters: &Self::Parameters) -> Result<(), LawError>;

    /// A hint that the engine is about to evaluate satellite `id` (its state update or command): a law
    /// that reads data of its own by satellite id may start loading it now (the engine evaluates the
    /// satellites in the sensing grid's cell order, in which their ids are scattered, and hints a
    /// batch of satellites before evaluating them). Must not change anything the law computes;
    /// default: nothing.
    fn prefetch(&self, _id: usize) {}

    /// Whether the law reads neighbours (the view's neighbour queries through the sensing grid, or
    /// the ring); default `true`. A law that never does returns `false`, and the engine then skips
    /// building the sensing grid for its evaluations (the view's neighbour queries find nothing).
    fn senses_neighbours(&self) -> bool {
        true
    }

    /// Whether the state update reads what neighbours broadcast ([`Broadcast::of`]); default `true`.
    /// A law whose update reads only its own previous state ([`Broadcast::own`]) returns `false`, and
    /// the engine then keeps one state per satellite instead of two, updating each in place (the
    /// same states, in less memory and without the pass that moves the new states to their
    /// satellites). Such a law must not call [`Broadcast::of`]: it panics for it.
    fn reads_neighbour_broadcasts(&self) -> bool {
        true
    }

    /// Whether every command of the law is zero whatever it senses (a law that only drifts); default
    /// `false`. A stateless law that returns `true` is not evaluated in sampled control: the engine
    /// builds no view for it and holds a zero command (with process noise the tick runs as usual).
    fn commands_nothing(&self) -> bool {
        false
    }

    /// Checks the law against the swarm it will steer (sensing range, satellite count, threats) without
    /// running it. The scenario layer calls it for the law at t = 0 and for every law an event sets, so a
    /// mismatch is refused when the scenario loads; a law calls it from its own
    /// [`GuidanceLaw::initialise`] and [`GuidanceLaw::set_parameters`] too. Default: nothing to check.
    fn check_swarm(&self, _swarm: &SwarmFacts) -> Result<(), LawError> {
        Ok(())
    }

    /// The fastest closed-loop rate \[1/s\] the law can impose on a satellite of the given mass, if it has
    /// one: the engine refuses a control period or a fixed integration step too long to resolve it.
    fn fastest_rate_per_s(&self, _mass_kg: f64) -> Option<f64> {
        None
    }

    /// The law as a [`Centralised`] law, if it is one (written by [`capabilities!`](crate::capabilities);
    /// default `None`).
    fn as_centralised(&mut self) -> Option<&mut dyn Centralised> {
        None
    }

    /// The law as a [`Reports`] law, if it is one (written by [`capabilities!`](crate::capabilities);
    /// default `None`).
    fn as_reports(&self) -> Option<&dyn SerialisedReports<Self::State>> {
        None
    }

    /// The law as a [`Diagnostics`] law, if it is one (written by
    /// [`capabilities!`](crate::capabilities); default `None`).
    fn as_diagnostics(&self) -> Option<&dyn Diagnostics<Self::State>> {
        None
    }

    /// [`GuidanceLaw::as_diagnostics`], mutable (to record metrics).
    fn as_diagnostics_mut(&mut self) -> Option<&mut dyn Diagnostics<Self::State>> {
        None
    }

    /// The law as a [`TargetFormation`] law, if it is one (written by
    /// [`capabilities!`](crate::capabilities); default `None`).
    fn as_target_formation(&self) -> Option<&dyn TargetFormation> {
        None
    }

    /// The law as a [`CommandsDrag`] law, if it is one (written by
    /// [`capabilities!`](crate::capabilities); default `None`).
    fn as_commands_drag(&self) -> Option<&dyn CommandsDrag<Self::State>> {
        None
    }
}
