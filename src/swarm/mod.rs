//! The swarm engine: structure-of-arrays state, neighbour grid, truth dynamics, actuators, the event
//! timeline, the guidance-law interface and the simulation loop that ties them together.
//!
//! Data flows one way: the loop builds a read-only view of what each satellite senses, the law returns
//! commanded accelerations, the actuators limit them, the integrator propagates the truth. A law never
//! touches the integrator; the integrator never knows which law runs.

pub mod actuator;
pub mod dynamics;
pub mod events;
pub mod law;

pub mod recorder;
pub mod simulation;
pub mod state;

pub use crate::grid::NeighbourGrid;
pub use actuator::{Actuator, LimitKind};
pub use dynamics::DynamicsModel;
pub use events::{Event, EventAction, Selection, ThrustAxis};
pub use law::{GuidanceLaw, LawError, Neighbour, SatelliteView, SharedInfo, SwarmView};
pub use recorder::{NullRecorder, Recorder, Snapshot};
pub use simulation::{
    ControlTiming, Origin, RunTotals, SatelliteInit, Sensing, SimError, Simulation,
    SimulationConfig,
};
pub use state::SwarmState;
