//! Propagation of one or a few orbits (no control), with outputs at exact multiples of an output step,
//! and the frames the states are given out in ([`OutputFrame`]): the library side of `satflock
//! propagate` and of the Python package's `satflock.propagate`.

use std::sync::Arc;

use thiserror::Error;

use crate::dynamics::{ForceSet, PhysicalProperties};
use crate::integrate::{IntegrateError, IntegratorMethod, Stepper, Tolerances};

use crate::orbit::{hill_to_gao, CartesianState, EarthModel, LvlhFrame};

/// How to propagate.
#[derive(Clone, Debug)]
pub struct PropagationSettings {
    /// Earth constants (those the force set was built with).
    pub earth: EarthModel,
    /// The forces, the same set the engine uses for inertial truth (its epoch is `t = 0`).
    pub forces: Arc<ForceSet>,
    /// The physical properties of every propagated orbit (read by drag and SRP).
    pub properties: PhysicalProperties,
    /// Integrator.
    pub integrator: IntegratorMethod,
    /// RK4 step, or longest step of the adaptive method \[s\].
    pub step_s: f64,
    /// Tolerances of the adaptive method.
    pub tolerances: Tolerances,
    /// Length of the propagation \[s\].
    pub duration_s: f64,
    /// Output spacing \[s\]; outputs at k · output_step_s for k = 0, 1, … up to the duration.
    pub output_step_s: f64,
}

/// A propagation that could not run.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum PropagateError {
    /// A setting is out of range.
    #[error("{setting} = {value} is out of range (allowed: {allowed})")]
    InvalidSetting {
        /// The setting's name.
        setting: &'static str,
        /// Its value.
        value: f64,
        /// The allowed range.
        allowed: &'static str,
    },
    /// An initial orbit is not one to propagate: not finite, hyperbolic, or with its perigee below
    /// `MIN_PERIGEE_ALTITUDE_M` (inside or grazing the atmosphere: most often kilometres given as metres).
    #[error(
        "orbit {index}: {reason} (allowed: a closed orbit with perigee altitude >= {} km; were \
         kilometres given as metres?)",
        MIN_PERIGEE_ALTITUDE_M / 1e3
    )]
    InvalidOrbit {
        /// Index of the orbit among those propagated.
        index: usize,
        /// What is wrong, with the numbers.
        reason: String,
    },
    /// The integrator failed.
    #[error(transparent)]
    Integration(#[from] IntegrateError),
    /// An orbit's density altitude fell below the atmosphere model's floor (re-entry).
    #[error(
        "orbit {index} at t = {time_s} s: density altitude {:.3} km is below the atmosphere \
         model's floor of {:.1} km (re-entry: drag no longer applies)",
        altitude_m / 1e3,
        floor_m / 1e3
    )]
    BelowAtmosphere {
        /// Which orbit (0 the first).
        index: usize,
        /// Time of detection, at an output time \[s\].
        time_s: f64,
        /// Its density altitude \[m\].
        altitude_m: f64,
        /// The atmosphere's floor \[m\].
        floor_m: f64,
    },
}

/// Lowest perigee altitude accepted \[m\]: below about 100 km the atmosphere, which is not modelled,
/// ends an orbit within a revolution.
pub const MIN_PERIGEE_ALTITUDE_M: f64 = 100e3;

/// Most fixed (RK4) steps accepted over the duration: the scenarios' bound on satellite-steps
/// (`[output] allow_large`); beyond, a too small step is likely a unit mistake.
pub const MAX_RK4_STEPS: f64 = 1e10;

/// Most output times accepted (each a row of every orbit): beyond, a too small output step is likely a
/// unit mistake.
pub const MAX_OUTPUTS: f64 = 1e7;

impl PropagationSettings {
    /// Refuses settings out of range (each named, with its allowed range): durations and steps not
    /// finite and positive, tolerances out of range, too many RK4 steps or outputs, Earth constants that are not
    /// finite and positive (J2: >= 0). [`propagate`] applies it first.
    pub fn check(&self) -> Result<(), PropagateError> {
        let positive = |setting, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(PropagateError::InvalidSetting {
                    setting,
                    value,
                    allowed: "finite, > 0",
                })
            }
        };
        positive("duration_s", self.duration_s)?;
        positive("mu_m3_s2", self.earth.mu_m3_s2)?;
        positive("earth_radius_m", self.earth.equatorial_radius_m)?;
        if !(self.earth.j2.is_finite() && self.earth.j2 >= 0.0) {
            return Err(PropagateError::InvalidSetting {
                setting: "j2",
                value: self.earth.j2,
                allowed: "finite, >= 0",
            });
        }
        positive("output_step_s", self.output_step_s)?;
        positive("step_s", self.step_s)?;
        positive("rtol", self.tolerances.relative)?;
        positive("atol", self.tolerances.absolute)?;
        if self.tolerances.relative >= 1.0 {
            return Err(PropagateError::InvalidSetting {
                setting: "rtol",
                value: self.tolerances.relative,
                allowed: "(0, 1)",
            });
        }
        positive("mass_kg", self.properties.mass_kg)?;
        if self.forces.earth() != self.earth {
            return Err(PropagateError::InvalidSetting {
                setting: "mu_m3_s2",
                value: self.forces.earth().mu_m3_s2,
                allowed: "the force set's Earth constants equal to the settings' earth",
            });
        }
        if self.integrator == IntegratorMethod::Rk4 && self.duration_s / self.step_s > MAX_RK4_STEPS
        {
            return Err(PropagateError::InvalidSetting {
                setting: "step_s",
                value: self.step_s,
                allowed:
                    "at most 1e10 RK4 steps over the duration, as the scenarios' satellite-steps",
            });
        }
        if self.duration_s / self.output_step_s > MAX_OUTPUTS {
            return Err(PropagateError::InvalidSetting {
                setting: "output_step_s",
                value: self.output_step_s,
                allowed: "at most 1e7 output times over the duration",
            });
        }
        Ok(())
    }

    /// Refuses an initial orbit that is not finite, not closed, or whose perigee is below
    /// [`MIN_PERIGEE_ALTITUDE_M`]: the sense check for orbits a user gives (`satflock propagate` applies
    /// it; [`propagate`] itself also integrates mathematical test orbits that graze the Earth).
    pub fn check_orbit(&self, index: usize, state: &CartesianState) -> Result<(), PropagateError> {
        let invalid = |reason: String| PropagateError::InvalidOrbit { index, reason };
        let finite = state
            .position_m
            .iter()
            .chain(state.velocity_mps.iter())
            .all(|v| v.is_finite());
        if !finite {
            return Err(invalid("the state is not finite".into()));
        }
        let mu = self.earth.mu_m3_s2;
        let r = state.position_m.norm();
        let energy = 0.5 * state.velocity_mps.norm_squared() - mu / r;
        if energy.is_nan() || energy >= 0.0 {
            return Err(invalid(format!(
                "specific energy {energy:.6e} J/kg: not a closed orbit"
            )));
        }
        let a = -mu / (2.0 * energy);
        let h = state.position_m.cross(&state.velocity_mps);
        let e = (1.0 - h.norm_squared() / (mu * a)).max(0.0).sqrt();
        let perigee_altitude_m = a * (1.0 - e) - self.earth.equatorial_radius_m;
        if perigee_altitude_m < MIN_PERIGEE_ALTITUDE_M {
            return Err(invalid(format!(
                "perigee altitude {:.3} km (semi-major axis {a:.3} m, eccentricity {e:.6})",
                perigee_altitude_m / 1e3
            )));
        }
        Ok(())
    }
}

/// The frame a propagated state is given out in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputFrame {
    /// The inertial frame of the propagation (EME2000).
    Inertial,
    /// The Hill LVLH frame of a reference orbit (x radial out, y along-track, z orbit normal).
    LvlhHill,
    /// Gao's o-xyz LVLH frame of a reference orbit (x along-track, y minus orbit normal, z nadir).
    LvlhGao,
}

impl OutputFrame {
    /// Whether the frame is a reference orbit's (needs a reference state).
    pub fn needs_reference(self) -> bool {
        self != OutputFrame::Inertial
    }

    /// `satellite` (inertial) in this frame, as `[x, y, z, vx, vy, vz]` \[m, m/s\]: as it is, or
    /// relative to `reference` (inertial, at the same time) with the velocity seen in the rotating
    /// frame ([`LvlhFrame::to_hill`]). `reference` is not used by [`OutputFrame::Inertial`]; the LVLH
    /// frames without one give the inertial state.
    pub fn express(
        self,
        satellite: &CartesianState,
        reference: Option<&CartesianState>,
    ) -> [f64; 6] {
        let (p, v) = match (self, reference) {
            (OutputFrame::LvlhHill | OutputFrame::LvlhGao, Some(reference)) => {
                let rel = LvlhFrame::from_reference(reference).to_hill(satellite);
                if self == OutputFrame::LvlhHill {
                    (rel.position_m, rel.velocity_mps)
                } else {
                    (hill_to_gao(&rel.position_m), hill_to_gao(&rel.velocity_mps))
                }
            }
            _ => (satellite.position_m, satellite.velocity_mps),
        };
        [p.x, p.y, p.z, v.x, v.y, v.z]
    }
}

/// Propagates `initial` orbits together under the same force set and calls `visit(t, states)` at t = 0 and
/// at every multiple of the output step up to the duration (the last output lands on the duration when it
/// is not a multiple). The integrator lands exactly on every output time.
pub fn propagate(
    initial: &[CartesianState],
    settings: &PropagationSettings,
    mut visit: impl FnMut(f64, &[CartesianState]),
) -> Result<(), PropagateError> {
    settings.check()?;
    let m = initial.len();
    let mut y: Vec<f64> = initial
        .iter()
        .flat_map(|s| s.position_m.iter().chain(s.velocity_mps.iter()).copied())
        .collect();
    let forces = &settings.forces;
    let properties = settings.properties;
    let rhs = move |t: f64, y: &[f64], dy: &mut [f64]| {
        let at = forces.instant(t);
        for (state, d) in y.chunks_exact(6).zip(dy.chunks_exact_mut(6)) {
            let r = nalgebra::Vector3::new(state[0], state[1], state[2]);
            let v = nalgebra::Vector3::new(state[3], state[4], state[5]);
            let a = forces.acceleration_eci_m_s2(&at, &r, &v, &properties);
            d[0..3].copy_from_slice(&state[3..6]);
            d[3..6].copy_from_slice(a.as_slice());
        }
    };
    let mut states = initial.to_vec();
    let unpack = |y: &[f64], states: &mut [CartesianState]| {
        for (s, c) in states.iter_mut().zip(y.chunks_exact(6)) {
            *s = CartesianState::new(
                nalgebra::Vector3::new(c[0], c[1], c[2]),
                nalgebra::Vector3::new(c[3], c[4], c[5]),
            );
        }
    };
    visit(0.0, &states);
    let mut stepper = Stepper::new(
        settings.integrator,
        6 * m,
        settings.tolerances,
        settings.step_s,
    );
    let outputs = (settings.duration_s / settings.output_step_s).floor() as u64;
    let mut t = 0.0;
    let mut k = 1;
    loop {
        // Output times are computed from their index, never accumulated, so they are exact multiples.
        let next = if k <= outputs {
            k as f64 * settings.output_step_s
        } else {
            settings.duration_s
        };
        if next <= t {
            break;
        }
        stepper.advance(&rhs, t, next, &mut y, settings.step_s)?;
        t = next;
        unpack(&y, &mut states);
        for (index, s) in states.iter().enumerate() {
            if let Some((altitude_m, floor_m)) = forces.below_floor(&s.position_m) {
                return Err(PropagateError::BelowAtmosphere {
                    index,
                    time_s: t,
                    altitude_m,
                    floor_m,
                });
            }
        }
        visit(t, &states);
        k += 1;
    }
    Ok(())
}
