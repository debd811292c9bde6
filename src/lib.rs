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
//! | [`integrate`] | fixed-step RK4 and adaptive embedded Runge-Kutta 7(8) over state vectors of any length |
//! | [`relative`] | Hill-Clohessy-Wiltshire and J2-linearised (Schweighart-Sedwick) relative motion |
//! | [`swarm`] | swarm-wide machinery: the cell-list neighbour grid ([`swarm::neighbours`]) |
//! | [`metrics`] | five-element cluster characterisation (N, r_o/v_o, d_max, d_min, L), separation and collision counts |
//!
//! Units are SI everywhere inside (m, s, kg, rad). Every vector's frame is in its type or its name.
#![forbid(unsafe_code)]

pub mod integrate;
pub mod metrics;
pub mod orbit;
pub mod relative;
pub mod swarm;
