//! The swarm engine: structure-of-arrays state, neighbour grid, truth dynamics, actuators, the event
//! timeline, the guidance-law interface and the simulation loop that ties them together.
//!
//! Data flows one way: the loop builds a read-only view of what each satellite senses, the law returns
//! commanded accelerations, the actuators limit them, the integrator propagates the truth. A law never
//! touches the integrator; the integrator never knows which law runs.

/// Smallest number of satellites per parallel work item of the engine's per-satellite passes (rayon's
/// `with_min_len`; the exact chunk where work is split with `par_chunks`). Results never depend on the
/// split: every satellite's result is computed on its own and written to its own slot.
const CHUNK: usize = 256;

mod actuator;
mod drag_attitude;
mod dynamics;
mod events;
mod law;
mod recorder;
mod simulation;
mod state;
mod storage_order;

pub use actuator::{Actuator, LimitKind};
pub use drag_attitude::{DragAttitudeError, DragAttitudes, DragCommand, MAX_DRAG_MODES};
pub use dynamics::DynamicsModel;
pub use events::{
    Bound, Condition, ConditionTest, Event, EventAction, Firing, Selection, ThrustAxis, Trigger,
    SHAPE_REACHED,
};
pub use law::{
    Better, Broadcast, Centralised, CommandKind, CommandsDrag, Diagnostics, EnvironmentView,
    GuidanceLaw, Headline, Law, LawContext, LawError, LawParameters, Neighbour, Reports,
    SatelliteView, SensedObstacle, SensedThreat, SerialisedReports, SharedInfo, SwarmFacts,
    SwarmView, TargetFormation,
};
pub use recorder::{EnvironmentSnapshot, NullRecorder, Recorder, Snapshot};
pub use simulation::{
    check_law_fits, hill_state_at_start, ControlTiming, Divergence, EnvironmentObject, Origin,
    RunTotals, SatelliteInit, Sensing, SimError, Simulation, SimulationConfig, StageTimings,
    TrackedObject, TrackedOrbit, TIME_EPSILON,
};
pub use state::SwarmState;
