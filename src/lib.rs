//! # satflock
//!
//! Simulate and steer satellite swarms and clusters in Earth orbit under J2, each satellite running a
//! distributed guidance law.
//!
//! The crate is layered; data flows one way (see `DESIGN.md`):
//!
//! | module | holds |
//! | --- | --- |
//! | [`orbit`] | Earth constants, Keplerian elements <-> Cartesian, point-mass + J2 gravity, LVLH frames |
//! | [`integrate`] | fixed-step RK4, adaptive RKF7(8) and DOP853 over state vectors of any length |
//! | [`relative`] | Hill-Clohessy-Wiltshire and J2-linearised (Schweighart-Sedwick) relative motion |
//! | [`swarm`] | the engine: SoA state, neighbour grid, dynamics, actuators, events, law interface, loop |
//! | [`guidance`] | the guidance laws and their registry |
//! | [`metrics`] | five-element cluster characterisation (N, r_o/v_o, d_max, d_min, L), separation and collision counts |
//! | [`scenario`] | TOML scenario files: schema, validation, built-in scenarios, initial distributions |
//! | [`output`] | streamed CSV recorder and the JSON run summary |
//! | [`propagate`] | propagation of single orbits with outputs at exact times (`satflock propagate`) |
//! | [`run`] | a scenario end to end: validate, simulate, write the outputs (`satflock run`) |
//! | [`validate`] | full-length reproductions against papers and analytic references (`satflock validate`) |
//!
//! Units are SI everywhere inside (m, s, kg, rad). Every vector's frame is in its type or its name.
#![forbid(unsafe_code)]

pub mod grid;
pub mod guidance;
pub mod integrate;
pub mod metrics;
pub mod orbit;
pub mod output;
pub mod propagate;
pub mod relative;
pub mod run;
pub mod scenario;
pub mod swarm;
