//! Propagation of one segment: the coupled swarm as one ODE with the law inside its right-hand side
//! (continuous control timing), or every satellite alone under its held command (sampled timing,
//! satellites in parallel), and the reference orbit.

use std::sync::Mutex;

use nalgebra::Vector3;
use rayon::prelude::*;

use crate::integrate::{
    FusedRk4, IntegrateError, IntegratorMethod, OdeSystem, SegmentInputs, Stepper, Tolerances,
};
use crate::orbit::RelativeStateHill;
use crate::swarm::dynamics::DynamicsModel;
use crate::swarm::law::Law;
use crate::swarm::simulation::satellites::Fleet;
use crate::swarm::simulation::scheduler::process_noise_of;
use crate::swarm::simulation::sensing::{Plant, Sensed, CHUNK};
use crate::swarm::state::{
    ledger_index, reference_of, satellite_index, satellite_of, LEDGER_COMPONENTS,
    SATELLITE_COMPONENTS,
};

/// State components of one satellite propagated alone: position, velocity, delta-v ledger.
const SOLO: usize = SATELLITE_COMPONENTS + LEDGER_COMPONENTS;

/// Buffers of one right-hand-side evaluation of the coupled swarm (continuous mode only).
pub(super) struct StageScratch {
    truth: Vec<RelativeStateHill>,
    sensed: Sensed,
    applied_hill: Vec<Vector3<f64>>,
    per_satellite: Vec<[f64; SOLO]>,
}

impl StageScratch {
    /// The applied commands of the last right-hand-side evaluation, by storage index.
    pub fn applied_hill(&self) -> &[Vector3<f64>] {
        &self.applied_hill
    }

    pub fn new(n: usize) -> Self {
        Self {
            truth: vec![RelativeStateHill::default(); n],
            // Continuous control builds the grid whatever the law reads.
            sensed: Sensed::new(true),
            applied_hill: vec![Vector3::zeros(); n],
            per_satellite: vec![[0.0; SOLO]; n],
        }
    }
}

/// The coupled swarm as one ODE (continuous control timing): reference, satellites and ledgers.
pub(super) struct CoupledSwarm<'a> {
    pub plant: Plant<'a>,
    pub law: &'a Law,
    pub tick: u64,
    /// Navigation noise held over the step (None when there is none).
    pub navigation_noise: Option<&'a [[f64; 6]]>,
    /// Process noise held over the step, Hill frame \[m/s^2\].
    pub process_noise_hill: &'a [Vector3<f64>],
    pub scratch: &'a Mutex<StageScratch>,
}

impl OdeSystem for CoupledSwarm<'_> {
    fn derivative(&self, t_s: f64, state: &[f64], derivative: &mut [f64]) {
        let plant = &self.plant;
        let config = plant.config;
        let n = plant.n();
        let mut guard = self.scratch.lock().unwrap_or_else(|e| e.into_inner());
        let StageScratch {
            truth,
            sensed,
            applied_hill,
            per_satellite,
        } = &mut *guard;
        // Reference orbit: uncontrolled.
        let (rp, rv) = reference_of(state);
        let ra = plant.reference_acceleration(t_s, &rp, &rv);
        derivative[0..3].copy_from_slice(rv.as_slice());
        derivative[3..6].copy_from_slice(ra.as_slice());

        let frame = plant.truth_relative(t_s, state, truth);
        let view = plant.view(t_s, truth, self.navigation_noise, sensed);
        plant.commands(self.law, &view, self.tick, applied_hill);
        let kinematic = matches!(config.dynamics, DynamicsModel::Kinematic);
        per_satellite
            .par_iter_mut()
            .with_min_len(CHUNK)
            .enumerate()
            .for_each(|(i, d)| {
                if !plant.fleet.active[i] {
                    *d = [0.0; SOLO];
                    return;
                }
                let (p, v) = satellite_of(state, n, i);
                let u = applied_hill[i];
                let (control, ledger) = if kinematic {
                    (u, Vector3::zeros())
                } else {
                    let total = u + process_noise_of(self.process_noise_hill, i);
                    let control = match &frame {
                        Some(f) => f.vector_hill_to_eci(&total),
                        None => total,
                    };
                    (control, u)
                };
                let properties = plant.fleet.properties(i);
                let (dp, dv) =
                    config
                        .dynamics
                        .satellite_derivative(t_s, &p, &v, &properties, &control);
                *d = ledger_derivative(&dp, &dv, &ledger);
            });
        scatter(per_satellite, n, derivative);
    }
}

/// Derivative of one satellite's position, velocity and delta-v ledger.
#[inline]
fn ledger_derivative(dp: &Vector3<f64>, dv: &Vector3<f64>, u_hill: &Vector3<f64>) -> [f64; SOLO] {
    [
        dp.x,
        dp.y,
        dp.z,
        dv.x,
        dv.y,
        dv.z,
        u_hill.x.abs(),
        u_hill.y.abs(),
        u_hill.z.abs(),
        u_hill.norm(),
    ]
}

/// Writes per-satellite blocks (position, velocity, ledger) into the component-major flat layout.
pub(super) fn scatter(per_satellite: &[[f64; SOLO]], n: usize, flat: &mut [f64]) {
    let body = &mut flat[satellite_index(n, 0, 0)..];
    body.par_chunks_mut(n.max(1))
        .take(SOLO)
        .enumerate()
        .for_each(|(k, component)| {
            for (i, value) in component.iter_mut().enumerate() {
                *value = per_satellite[i][k];
            }
        });
}

/// Reads per-satellite blocks out of the component-major flat layout.
pub(super) fn gather(flat: &[f64], n: usize, per_satellite: &mut [[f64; SOLO]]) {
    per_satellite
        .par_iter_mut()
        .with_min_len(CHUNK)
        .enumerate()
        .for_each(|(i, block)| {
            for (k, value) in block.iter_mut().enumerate() {
                *value = if k < SATELLITE_COMPONENTS {
                    flat[satellite_index(n, k, i)]
                } else {
                    flat[ledger_index(n, k - SATELLITE_COMPONENTS, i)]
                };
            }
        });
}

/// What sampled propagation needs: for RK4 under an inertial force set the fused kernel covers
/// ([`crate::dynamics::FastForces`]), the kernel, which steps the component-major state in place (with
/// each satellite's `C_d A / m` gathered per segment when it computes drag); otherwise one stepper per
/// chunk of satellites, the gathered blocks, and each satellite's own remembered step size (adaptive
/// methods), so that satellites sharing a stepper stay independent of each other.
pub(super) enum SampledBuffers {
    Fused {
        kernel: FusedRk4,
        drag_area_per_mass_m2_per_kg: Vec<f64>,
    },
    Generic {
        steppers: Vec<Stepper>,
        per_satellite: Vec<[f64; SOLO]>,
        step_guesses_s: Vec<Option<f64>>,
    },
}

impl SampledBuffers {
    /// The buffers for `n` satellites under `dynamics` with `integrator`.
    pub fn new(
        dynamics: &DynamicsModel,
        integrator: IntegratorMethod,
        tolerances: Tolerances,
        step_s: f64,
        n: usize,
    ) -> Self {
        let fast = dynamics.forces().and_then(|f| f.fast_forces());
        match (fast, integrator) {
            (Some(forces), IntegratorMethod::Rk4) => {
                let kernel = FusedRk4::for_forces(forces);
                SampledBuffers::Fused {
                    drag_area_per_mass_m2_per_kg: if kernel.has_drag() {
                        vec![0.0; n]
                    } else {
                        Vec::new()
                    },
                    kernel,
                }
            }
            _ => SampledBuffers::Generic {
                steppers: (0..n.div_ceil(CHUNK))
                    .map(|_| Stepper::new(integrator, SOLO, tolerances, step_s))
                    .collect(),
                per_satellite: vec![[0.0; SOLO]; n],
                step_guesses_s: vec![None; n],
            },
        }
    }

    /// The propagation path taken, as `summary.json` `timing` names it.
    pub fn path_name(&self) -> &'static str {
        match self {
            SampledBuffers::Fused { kernel, .. } if kernel.has_drag() => {
                "fused RK4 kernel (gravity + exponential drag)"
            }
            SampledBuffers::Fused { .. } => "fused RK4 kernel (gravity)",
            SampledBuffers::Generic { .. } => "generic per-satellite stepper",
        }
    }
}

/// One sampled segment: every live satellite alone from `t0_s` to `t1_s` under its held command.
pub(super) struct SampledSegment<'a> {
    pub dynamics: &'a DynamicsModel,
    pub fleet: &'a Fleet,
    /// The held command in the dynamics frame (ECI for inertial truth, Hill for the linear and
    /// kinematic models).
    pub held: &'a [Vector3<f64>],
    /// The Hill command the delta-v ledger integrates, constant over the period (ignored by the
    /// kinematic model, whose ledger stays zero).
    pub held_hill: &'a [Vector3<f64>],
    /// Every held command is zero (a law that commands nothing): the fused kernel then reads neither
    /// the commands nor the delta-v ledger, whose four components adding zero would leave unchanged.
    pub commands_zero: bool,
    pub t0_s: f64,
    pub t1_s: f64,
    pub max_step_s: f64,
}

impl SampledSegment<'_> {
    /// Propagates the segment on the flat state `data` of `n` satellites.
    pub fn advance(
        &self,
        buffers: &mut SampledBuffers,
        data: &mut [f64],
        n: usize,
    ) -> Result<(), IntegrateError> {
        let Self {
            dynamics,
            fleet,
            held,
            held_hill,
            commands_zero,
            t0_s,
            t1_s,
            max_step_s,
        } = *self;
        let active = &fleet.active[..];
        let (steppers, per_satellite, step_guesses_s) = match buffers {
            SampledBuffers::Fused {
                kernel,
                drag_area_per_mass_m2_per_kg,
            } => {
                if kernel.has_drag() {
                    fleet.drag_areas_per_mass_into(drag_area_per_mass_m2_per_kg);
                }
                let inputs = SegmentInputs {
                    control_eci_m_s2: (!commands_zero).then_some(held),
                    ledger_command_hill_m_s2: (!commands_zero).then_some(held_hill),
                    active: Some(active),
                    drag_area_per_mass_m2_per_kg: kernel
                        .has_drag()
                        .then_some(&drag_area_per_mass_m2_per_kg[..]),
                };
                let body = &mut data[satellite_index(n, 0, 0)..];
                // Without the ledger, the kernel sees the position and velocity columns only.
                let body = if commands_zero {
                    &mut body[..6 * n]
                } else {
                    body
                };
                return Ok(kernel.advance(body, n, &inputs, t0_s, t1_s, max_step_s)?);
            }
            SampledBuffers::Generic {
                steppers,
                per_satellite,
                step_guesses_s,
            } => (steppers, per_satellite, step_guesses_s),
        };
        let kinematic = matches!(dynamics, DynamicsModel::Kinematic);
        gather(data, n, per_satellite);
        per_satellite
            .par_chunks_mut(CHUNK)
            .zip(step_guesses_s.par_chunks_mut(CHUNK))
            .zip(steppers.par_iter_mut())
            .enumerate()
            .try_for_each(
                |(c, ((blocks, guesses), stepper))| -> Result<(), IntegrateError> {
                    for (offset, (block, guess)) in
                        blocks.iter_mut().zip(guesses.iter_mut()).enumerate()
                    {
                        let i = c * CHUNK + offset;
                        if !active[i] {
                            continue;
                        }
                        let control = held[i];
                        let properties = fleet.properties(i);
                        let u = if kinematic {
                            Vector3::zeros()
                        } else {
                            held_hill[i]
                        };
                        let hill = [u.x.abs(), u.y.abs(), u.z.abs(), u.norm()];
                        let rhs = |t: f64, y: &[f64], dy: &mut [f64]| {
                            let p = Vector3::new(y[0], y[1], y[2]);
                            let v = Vector3::new(y[3], y[4], y[5]);
                            let (dp, dv) =
                                dynamics.satellite_derivative(t, &p, &v, &properties, &control);
                            dy[0..3].copy_from_slice(dp.as_slice());
                            dy[3..6].copy_from_slice(dv.as_slice());
                            dy[6..10].copy_from_slice(&hill);
                        };
                        stepper.set_step_guess_s(*guess);
                        stepper.advance(&rhs, t0_s, t1_s, block, max_step_s)?;
                        *guess = stepper.step_guess_s();
                    }
                    Ok(())
                },
            )?;
        scatter(per_satellite, n, data);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::{ForceSet, ForcesConfig, PhysicalProperties};
    use crate::orbit::{EarthModel, GravityModel};
    use crate::swarm::storage_order::StorageOrder;
    use crate::swarm::Actuator;

    /// The fused kernel and the generic per-satellite RK4 give the same bits on the engine's layout,
    /// with commands, ledger and inactive satellites, for 1 and 2 threads, under gravity alone and
    /// with exponential drag (co-rotating or not; satellites of different ballistic coefficients); and
    /// with zero commands the fused kernel told so (reading neither commands nor ledger) gives the
    /// generic path's bits, ledger included.
    #[test]
    fn fused_sampled_path_equals_the_generic_one() {
        let earth = EarthModel::WGS84_EGM96;
        let n = 700;
        let mut data = vec![0.0; crate::swarm::state::SwarmState::len_for(n)];
        for i in 0..n {
            let phase = i as f64 * 0.37;
            let r = 6.9e6 + 1e3 * i as f64;
            let p = [
                r * phase.cos(),
                r * phase.sin() * 0.6,
                r * phase.sin() * 0.8,
            ];
            let v = [
                -7.5e3 * phase.sin(),
                7.5e3 * phase.cos() * 0.6,
                7.5e3 * phase.cos() * 0.8,
            ];
            for k in 0..3 {
                data[satellite_index(n, k, i)] = p[k];
                data[satellite_index(n, k + 3, i)] = v[k];
            }
            for k in 0..LEDGER_COMPONENTS {
                data[ledger_index(n, k, i)] = 0.01 * (i + k) as f64;
            }
        }
        let active: Vec<bool> = (0..n).map(|i| i % 9 != 4).collect();
        let held: Vec<Vector3<f64>> = (0..n)
            .map(|i| Vector3::new(1e-4 * i as f64, -2e-4, 3e-5 * (i % 3) as f64))
            .collect();
        let held_hill: Vec<Vector3<f64>> =
            held.iter().map(|u| Vector3::new(u.z, -u.x, u.y)).collect();
        let properties: Vec<PhysicalProperties> = (0..n)
            .map(|i| PhysicalProperties {
                mass_kg: 4.0 + (i % 7) as f64,
                drag_area_m2: 0.01 + 0.003 * (i % 11) as f64,
                drag_coefficient: 2.2,
                srp_area_m2: 0.0,
                reflectivity_coefficient: 0.0,
            })
            .collect();
        let fleet = Fleet {
            masses_kg: properties.iter().map(|p| p.mass_kg).collect(),
            surfaces: Fleet::surfaces_of(properties.iter().copied(), true),
            radii_m: vec![0.0; n],
            actuators: vec![Actuator::new(f64::INFINITY, crate::swarm::LimitKind::Norm); n],
            drag_attitudes: Vec::new(),
            active,
            links_up: vec![true; n],
            order: StorageOrder::identity(n),
        };
        let epoch = crate::time::parse_epoch_utc("2026-03-20T12:00:00Z").unwrap();
        let drag = |corotation: bool| {
            let text = format!(
                "[drag]\natmosphere = \"exponential\"\nreference_density_kg_per_m3 = 3.725e-12\n\
                 reference_altitude_m = 400e3\nscale_height_m = 58515.0\ncorotation = {corotation}\n"
            );
            let config: ForcesConfig = toml::from_str(&text).unwrap();
            DynamicsModel::Inertial(std::sync::Arc::new(
                ForceSet::from_config(&config, &earth, epoch).unwrap(),
            ))
        };
        let models = [
            DynamicsModel::inertial(GravityModel::J2, earth),
            DynamicsModel::inertial(GravityModel::TwoBody, earth),
            drag(true),
            drag(false),
        ];
        for dynamics in &models {
            let name = dynamics.forces().unwrap().summary().models.join(" + ");
            let run = |fused: bool,
                       threads: usize,
                       (held, held_hill, commands_zero): (
                &[Vector3<f64>],
                &[Vector3<f64>],
                bool,
            )| {
                let mut buffers = SampledBuffers::new(
                    dynamics,
                    IntegratorMethod::Rk4,
                    Tolerances::default(),
                    1.0,
                    n,
                );
                assert!(matches!(buffers, SampledBuffers::Fused { .. }));
                if !fused {
                    buffers = SampledBuffers::Generic {
                        steppers: (0..n.div_ceil(CHUNK))
                            .map(|_| {
                                Stepper::new(
                                    IntegratorMethod::Rk4,
                                    SOLO,
                                    Tolerances::default(),
                                    1.0,
                                )
                            })
                            .collect(),
                        per_satellite: vec![[0.0; SOLO]; n],
                        step_guesses_s: vec![None; n],
                    };
                }
                let mut state = data.clone();
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let segment = SampledSegment {
                    dynamics,
                    fleet: &fleet,
                    held,
                    held_hill,
                    commands_zero,
                    t0_s: 2.0,
                    t1_s: 32.5,
                    max_step_s: 1.0,
                };
                pool.install(|| segment.advance(&mut buffers, &mut state, n))
                    .unwrap();
                state
            };
            let zeros = vec![Vector3::zeros(); n];
            // Held commands; then zero commands, which the fused kernel is told are zero (it then
            // skips the commands and the ledger) and the generic path integrates as given.
            for (commands, told) in [((&held, &held_hill), false), ((&zeros, &zeros), true)] {
                let generic = run(false, 1, (commands.0, commands.1, false));
                assert_ne!(generic, data);
                for threads in [1, 2] {
                    let fused = run(true, threads, (commands.0, commands.1, told));
                    for (i, (a, b)) in fused.iter().zip(&generic).enumerate() {
                        assert_eq!(
                            a.to_bits(),
                            b.to_bits(),
                            "{name}, commands told zero {told}: element {i}: {a} != {b}"
                        );
                    }
                }
            }
        }
    }
}
