//! # satflock
//!
//! Simulate and steer satellite swarms and clusters in Earth orbit under J2 (and, when asked, zonal
//! harmonics, drag, solar radiation pressure, Sun and Moon), each satellite running a distributed
//! guidance law.
//!
//! Start with [`prelude`]: `use satflock::prelude::*;` brings the scenario loader, the engine, the law
//! interface and the physics types a user needs.
//!
//! The crate is layered; data flows one way and no module imports one above it (see `DESIGN.md`):
//!
//! | layer | module | holds |
//! | --- | --- | --- |
//! | base | [`input_file`] | the one bounded reader of every file satflock is given: regular files only, a stated size limit |
//! | base | [`invalid`] | the one typed error of a value that is not allowed: key, value, problem, what is allowed |
//! | physics | [`orbit`] | Earth constants, Keplerian elements <-> Cartesian, point-mass + J2 gravity, LVLH frames |
//! | physics | [`orbit_files`] | CCSDS OEM, OMM (KVN, XML, JSON) and TLE readers giving EME2000 states; SGP4; TEME and GCRF to EME2000 |
//! | physics | [`dynamics`] | force models behind one trait: gravity (point mass, J2, zonal), drag and atmospheres, SRP, Sun and Moon; the force set of a run |
//! | physics | [`integrate`] | RK4, adaptive RKF7(8) and DOP853 over state vectors of any length; a run-time [`integrate::Stepper`] |
//! | physics | [`relative`] | Hill-Clohessy-Wiltshire, J2-linearised (Schweighart-Sedwick) and averaged-J2 relative motion |
//! | support | [`random`] | every random draw of a run: one stream per (seed, purpose, satellite, tick) |
//! | support | [`grid`] | the cell-list neighbour grid (radius and nearest queries) |
//! | support | [`environment`] | threats, obstacles and the continuous closest-approach geometry |
//! | support | [`metrics`] | five-element cluster characterisation, separation and collision counts |
//! | support | [`time`] | the scenario epoch, UTC output times and time-scale offsets (hifitime) |
//! | engine | [`swarm`] | the law interface, the simulation (sensing, propagation, scheduler, events, monitors, snapshots) |
//! | laws | [`guidance`] | the guidance laws and their registry |
//! | input | [`scenario`] | TOML scenario files: schema, validation, built-in scenarios, initial distributions |
//! | output | [`output`] | streamed CSV recorder, JSON run summary, run-directory reader, CCSDS OEM and CZML exports |
//! | front | [`propagate`], [`run`] | single-orbit propagation; a scenario end to end |
//! | front | [`budget`] | the perturbation budget of a satellite pair: each force's absolute and differential acceleration and the along-track drift it causes |
//! | front | [`campaign`] | many runs of a scenario over seeds and parameters, in a bounded pool of whole runs; manifest, Parquet table, statistics |
//!
//! Units are SI everywhere inside (m, s, kg, rad). Every vector's frame is in its type or its name.
#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod budget;
pub mod campaign;
pub mod conjunction;
pub mod dynamics;
pub mod environment;
pub mod grid;
pub mod guidance;
pub mod input_file;
pub mod integrate;
pub mod invalid;
pub mod metrics;
pub mod orbit;
pub mod orbit_files;
pub mod output;
mod prefetch;
pub mod propagate;
pub mod random;
pub mod relative;
pub mod run;
pub mod scenario;
pub mod swarm;
pub mod time;

/// What most users need, in one import: `use satflock::prelude::*;`.
pub mod prelude {
    pub use crate::capabilities;
    pub use crate::environment::{Obstacle, Threat};
    pub use crate::guidance::LawConfig;
    pub use crate::orbit::{
        CartesianState, EarthModel, GravityModel, KeplerianElements, RelativeStateHill,
    };
    pub use crate::random::{Purpose, RandomStream};
    pub use crate::run::{build_simulation, run_scenario, RunError};
    pub use crate::scenario::{Scenario, ScenarioError};
    pub use crate::swarm::{
        Actuator, Better, Broadcast, Centralised, CommandKind, CommandsDrag, ControlTiming,
        Diagnostics, DynamicsModel, GuidanceLaw, Headline, Law, LawContext, LawError, LimitKind,
        NullRecorder, Recorder, Reports, SatelliteInit, SatelliteView, SimError, Simulation,
        SimulationConfig, Snapshot, SwarmView, TargetFormation,
    };
}
