//! What a law may use besides its sensing view: its own random stream, the control timing and its
//! satellite's actuator.

use crate::random::{Purpose, RandomStream};
use crate::swarm::actuator::{Actuator, LimitKind};

/// The context of one satellite's law evaluation at one tick.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LawContext {
    /// Time of the tick, seconds since the scenario start \[s\].
    pub time_s: f64,
    /// Index of the tick (control tick in sampled mode, integration step in continuous mode), from 0.
    pub tick: u64,
    /// Control period (sampled mode) or integration step (continuous mode) \[s\].
    pub period_s: f64,
    /// The satellite's thrusters (limit, limit kind, working axes) as they are now.
    pub actuator: Actuator,
    satellite: usize,
    seed: u64,
    purpose: Purpose,
}

impl LawContext {
    /// The context of satellite `satellite` at tick `tick` (time `time_s` \[s\]) of a run seeded `seed`,
    /// with control period `period_s` \[s\] and the satellite's actuator. The engine builds these; tests
    /// and tools that call a law directly can too.
    pub fn new(
        time_s: f64,
        tick: u64,
        period_s: f64,
        actuator: Actuator,
        satellite: usize,
        seed: u64,
    ) -> Self {
        Self {
            time_s,
            tick,
            period_s,
            actuator,
            satellite,
            seed,
            purpose: Purpose::LawUpdate,
        }
    }

    /// The same context for the command, whose random stream is independent of the state update's.
    pub(crate) fn for_command(self) -> Self {
        Self {
            purpose: Purpose::LawCommand,
            ..self
        }
    }

    /// This satellite's random stream for this tick, derived from (scenario seed, purpose, satellite,
    /// tick): the same draws on any thread count and in every call during the tick (take it once and
    /// draw from it; a second call starts the same sequence again). The state update and the command
    /// get independent streams; the command's is the same at every Runge–Kutta stage of a step.
    pub fn random(&self) -> RandomStream {
        RandomStream::new(self.seed, self.purpose, self.satellite as u64, self.tick)
    }

    /// The satellite's acceleration limit \[m/s^2\] (`f64::INFINITY` when unlimited).
    pub fn max_accel_m_s2(&self) -> f64 {
        self.actuator.max_accel_m_s2
    }

    /// How the satellite's acceleration limit applies (norm or per Hill axis).
    pub fn limit_kind(&self) -> LimitKind {
        self.actuator.limit
    }
}
