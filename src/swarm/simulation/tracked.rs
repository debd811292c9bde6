//! The real objects among the threats and obstacles (an object from an OMM or a TLE, or an inertial
//! state): their inertial (EME2000) state at every segment end — by SGP4 from the element set, or by the
//! run's uncontrolled dynamics — placed in the Hill frame of the LVLH origin exactly as the satellites'
//! truth relative states are, so the views, the monitors and the conjunction screen see the object on
//! the cubic Hermite of its end states over each segment ([`crate::environment::TrackedPath`]).

use nalgebra::Vector3;

use crate::dynamics::PhysicalProperties;
use crate::environment::TrackedPath;
use crate::integrate::Stepper;
use crate::orbit::{CartesianState, RelativeStateHill};
use crate::orbit_files::Sgp4Object;
use crate::time::Epoch;

use super::sensing::Plant;
use super::{SimError, Simulation, SimulationConfig};

/// Which object of the environment a tracked orbit moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EnvironmentObject {
    /// `config.threats[k]`.
    Threat(usize),
    /// `config.obstacles[k]`.
    Obstacle(usize),
}

/// How a real object's inertial state is known during the run.
#[derive(Clone, Debug, PartialEq)]
pub enum TrackedOrbit {
    /// SGP4 from the element set, at `epoch` (the run's t = 0, UTC) plus the run time; its TEME state
    /// rotated to EME2000 ([`Sgp4Object::state_eme2000`]).
    Sgp4 {
        /// The element set and its propagator.
        elements: Box<Sgp4Object>,
        /// The run's t = 0.
        epoch: Epoch,
    },
    /// The run's uncontrolled dynamics (the force set of the virtual reference orbit) from the
    /// object's EME2000 state at t = 0 \[m, m/s\], with its own physical properties.
    Truth {
        /// State at t = 0, EME2000 \[m, m/s\].
        state_eme2000: CartesianState,
        /// Mass, areas and coefficients for drag and SRP.
        properties: PhysicalProperties,
    },
}

/// A real object of the environment: which threat or obstacle it is, and its orbit. The threat or
/// obstacle must have a tracked motion ([`crate::environment::Threat::tracked`],
/// [`crate::environment::Obstacle::tracked`]); the engine places it at t = 0 and after every segment.
#[derive(Clone, Debug, PartialEq)]
pub struct TrackedObject {
    /// The threat or obstacle.
    pub object: EnvironmentObject,
    /// Its orbit.
    pub orbit: TrackedOrbit,
}

/// The tracked objects' running inertial states (truth-propagated ones) and their stepper.
pub(super) struct TrackedStates {
    /// EME2000 state now of every tracked object (in `config.tracked_objects` order) \[m, m/s\].
    states_eme2000: Vec<CartesianState>,
    stepper: Stepper,
    /// The placements of the segment end being placed (a buffer kept across segments).
    placements: Vec<RelativeStateHill>,
}

impl TrackedStates {
    pub fn new(config: &SimulationConfig) -> Self {
        Self {
            states_eme2000: config
                .tracked_objects
                .iter()
                .map(|o| match &o.orbit {
                    TrackedOrbit::Truth { state_eme2000, .. } => *state_eme2000,
                    TrackedOrbit::Sgp4 { .. } => CartesianState::default(),
                })
                .collect(),
            stepper: Stepper::new(config.integrator, 6, config.tolerances, config.step_s),
            placements: Vec::with_capacity(config.tracked_objects.len()),
        }
    }
}

/// The name of a tracked object, for errors.
fn name_of(config: &SimulationConfig, object: EnvironmentObject) -> String {
    match object {
        EnvironmentObject::Threat(k) => format!("threat `{}`", config.threats[k].name()),
        EnvironmentObject::Obstacle(k) => format!("obstacle `{}`", config.obstacles[k].name()),
    }
}

impl Simulation {
    /// Places every tracked object in the Hill frame at `t1_s`, the end of the segment that started at
    /// `t0_s` (`None`: at t = 0, where the path starts afresh).
    pub(super) fn place_tracked_objects(
        &mut self,
        t1_s: f64,
        t0_s: Option<f64>,
    ) -> Result<(), SimError> {
        if self.config.tracked_objects.is_empty() {
            return Ok(());
        }
        let plant = Plant::new(
            &self.config,
            &self.satellites.fleet,
            &self.timeline.threat_warnings,
            self.reference_model,
        );
        let data = self.state.as_slice();
        self.tracked.placements.clear();
        for (k, tracked) in self.config.tracked_objects.iter().enumerate() {
            let fail = |message: String| SimError::TrackedObject {
                object: name_of(&self.config, tracked.object),
                time_s: t1_s,
                message,
            };
            let inertial = match &tracked.orbit {
                TrackedOrbit::Sgp4 { elements, epoch } => elements
                    .state_eme2000(crate::time::at(*epoch, t1_s))
                    .map_err(|e| fail(e.to_string()))?,
                TrackedOrbit::Truth { properties, .. } => {
                    let state = &mut self.tracked.states_eme2000[k];
                    if let Some(t0_s) = t0_s {
                        let rhs = |t: f64, y: &[f64], dy: &mut [f64]| {
                            let a = self.config.dynamics.reference_acceleration_m_s2(
                                &self.config.earth,
                                t,
                                &Vector3::new(y[0], y[1], y[2]),
                                &Vector3::new(y[3], y[4], y[5]),
                                properties,
                            );
                            dy[0..3].copy_from_slice(&y[3..6]);
                            dy[3..6].copy_from_slice(a.as_slice());
                        };
                        let mut y = [
                            state.position_m.x,
                            state.position_m.y,
                            state.position_m.z,
                            state.velocity_mps.x,
                            state.velocity_mps.y,
                            state.velocity_mps.z,
                        ];
                        self.tracked
                            .stepper
                            .advance(&rhs, t0_s, t1_s, &mut y, self.config.step_s)
                            .map_err(|e| fail(e.to_string()))?;
                        *state = CartesianState::new(
                            Vector3::new(y[0], y[1], y[2]),
                            Vector3::new(y[3], y[4], y[5]),
                        );
                    }
                    *state
                }
            };
            let hill = plant.hill_of(t1_s, data, &inertial);
            self.tracked.placements.push(hill);
        }
        for (k, hill) in self.tracked.placements.iter().enumerate() {
            let object = self.config.tracked_objects[k].object;
            let name = name_of(&self.config, object);
            let motion = match object {
                EnvironmentObject::Threat(i) => self.config.threats[i].motion_mut(),
                EnvironmentObject::Obstacle(i) => self.config.obstacles[i].motion_mut(),
            };
            let placed = match (motion.tracked_mut(), t0_s) {
                (Some(path), Some(_)) => path.advance(t1_s, hill.position_m, hill.velocity_mps),
                (Some(path), None) => TrackedPath::new(t1_s, hill.position_m, hill.velocity_mps)
                    .map(|fresh| *path = fresh),
                (None, _) => {
                    return Err(SimError::TrackedObject {
                        object: name.clone(),
                        time_s: t1_s,
                        message: "has a tracked orbit but moves on a line (build it with \
                                  Threat::tracked or Obstacle::tracked)"
                            .into(),
                    })
                }
            };
            placed.map_err(|e| SimError::TrackedObject {
                object: name.clone(),
                time_s: t1_s,
                message: e.to_string(),
            })?;
        }
        Ok(())
    }
}
