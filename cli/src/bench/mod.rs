//! `satflock bench`: performance measurements of the engine.

pub mod suite;
