//! What a recorder receives at every recording time: the truth states (Hill and ECI), delta-v ledgers,
//! the five elements, separation and collisions, the law's metrics and per-satellite outputs, the
//! threat and obstacle monitors so far, and the control history when it is recorded.

use nalgebra::Vector3;

use crate::metrics::{five_elements, FiveElements, FiveElementsWorkspace};
use crate::orbit::{CartesianState, LvlhFrame, RelativeStateHill};
use crate::swarm::recorder::{EnvironmentSnapshot, Recorder, Snapshot};
use crate::swarm::simulation::monitors::live_separation;
use crate::swarm::simulation::scheduler::noise_if_any;
use crate::swarm::simulation::sensing::{FleetById, Plant};
use crate::swarm::simulation::{Integration, SimError, Simulation, SimulationConfig};
use crate::swarm::state::{reference_of, satellite_of, SwarmState};
use crate::swarm::storage_order::StorageOrder;

/// Every satellite's inertial state (ECI), by id, from the flat state (in the storage order `order`): the
/// state itself for the inertial models, the Hill state mapped through the reference orbit's frame for
/// the linear and kinematic models.
pub(super) fn inertial_states(
    config: &SimulationConfig,
    state: &SwarmState,
    order: &StorageOrder,
) -> Vec<CartesianState> {
    let n = state.n();
    let data = state.as_slice();
    let reference_frame = (!config.dynamics.is_inertial()).then(|| {
        let (p, v) = reference_of(data);
        LvlhFrame::from_reference(&CartesianState::new(p, v))
    });
    (0..n)
        .map(|id| {
            let (p, v) = satellite_of(data, n, order.index_of(id));
            match &reference_frame {
                None => CartesianState::new(p, v),
                Some(f) => f.from_hill(&RelativeStateHill {
                    position_m: p,
                    velocity_mps: v,
                }),
            }
        })
        .collect()
}

/// The five elements of the satellites `live` (`state` gives a satellite's position and velocity in
/// one frame \[m, m/s\], `radius_m` its radius), `None` with fewer than two.
pub(super) fn five_elements_of(
    live: &[usize],
    state: impl Fn(usize) -> (Vector3<f64>, Vector3<f64>),
    radius_m: impl Fn(usize) -> f64,
    workspace: &mut FiveElementsWorkspace,
) -> Option<FiveElements> {
    if live.len() < 2 {
        return None;
    }
    let (positions, velocities): (Vec<[f64; 3]>, Vec<[f64; 3]>) = live
        .iter()
        .map(|&i| {
            let (p, v) = state(i);
            (<[f64; 3]>::from(p), <[f64; 3]>::from(v))
        })
        .unzip();
    let radii: Vec<f64> = live.iter().map(|&i| radius_m(i)).collect();
    five_elements(&positions, &velocities, Some(&radii), workspace).ok()
}

impl Simulation {
    /// Builds the snapshot of now and hands it to the recorder.
    pub(super) fn record(&mut self, recorder: &mut dyn Recorder) -> Result<(), SimError> {
        // Everything the recorder gets is by id (the engine's arrays are in storage order). What needs
        // scratch of its own comes first (the law's metrics read a by-id view; the five elements
        // copy the live states), so that its scratch is freed before the by-id copies below are
        // made: a recording's peak memory is the copies, not the copies and the scratch.
        let law_metric_names = self.law.metric_names();
        let mut law_metrics = vec![0.0; law_metric_names.len()];
        if !law_metrics.is_empty() {
            let plant = Plant::new(
                &self.config,
                &self.satellites.fleet,
                &self.timeline.threat_warnings,
                self.reference_model,
            );
            let mut by_id = FleetById::default();
            let view = plant.view_by_id(
                self.clock.time_s,
                &self.satellites.truth,
                &mut self.sensed,
                &mut by_id,
            );
            self.law.record_metrics(
                &view,
                &mut law_metrics,
                self.satellites.fleet.order.placement(),
            );
        }
        let (min_separation_m, collisions) = live_separation(
            &self.satellites.truth,
            &self.satellites.fleet.active,
            &self.satellites.fleet.radii_m,
            &mut self.monitors.live,
        );
        let n = self.state.n();
        let order = &self.satellites.fleet.order;
        let inertial = inertial_states(&self.config, &self.state, order);
        let active = order.by_id(&self.satellites.fleet.active);
        let radii_m = &self.satellites.fleet.radii_m;
        let elements = five_elements_of(
            &(0..n).filter(|&id| active[id]).collect::<Vec<_>>(),
            |i| (inertial[i].position_m, inertial[i].velocity_mps),
            |i| radii_m[order.index_of(i)],
            &mut self.monitors.live.workspace,
        );
        self.totals.final_five_elements = elements;
        let (axes, norms): (Vec<[f64; 3]>, Vec<f64>) = (0..n)
            .map(|id| self.state.ledger(order.index_of(id)))
            .unzip();
        let relative_states = order.by_id(&self.satellites.truth);
        let law_output_names = self.law.output_names();
        let law_outputs = self.law_outputs();
        let environment = EnvironmentSnapshot {
            threats: self.config.threats.len(),
            obstacles: self.config.obstacles.len(),
            min_threat_distance_m: self
                .monitors
                .approach
                .swarm_threat_minimum()
                .map(|m| m.minimum.distance_m),
            min_obstacle_clearance_m: self
                .monitors
                .approach
                .swarm_obstacle_minimum()
                .map(|m| m.minimum.clearance_m),
            threat_incursions: self.monitors.approach.total_threat_incursions(),
            obstacle_incursions: self.monitors.approach.total_obstacle_incursions(),
        };
        let drag_areas_m2 = self.drag_areas_m2().unwrap_or_default();
        let drag_switches = self.satellites.drag_switches.iter().sum();
        let (commanded_hill, applied_hill) = self.control_history();
        let snapshot = Snapshot {
            time_s: self.clock.time_s,
            relative_states: &relative_states,
            inertial_states: &inertial,
            active: &active,
            delta_v_axes_mps: &axes,
            delta_v_mps: &norms,
            five_elements: elements,
            min_separation_m,
            collisions,
            law_metric_names,
            law_metrics: &law_metrics,
            law_output_names,
            law_outputs: &law_outputs,
            environment,
            drag_areas_m2: &drag_areas_m2,
            drag_switches,
            commanded_hill_mps2: &commanded_hill,
            applied_hill_mps2: &applied_hill,
        };
        recorder.record(&snapshot)?;
        Ok(())
    }

    /// The control history now, by id: every satellite's commanded and applied acceleration, Hill
    /// frame \[m/s^2\] (both empty when it is not recorded). Sampled control holds the tick's
    /// commands; continuous control evaluates the law at the current state (the navigation noise and
    /// random stream of the last integration step, as its right-hand side would at this instant),
    /// which reads the law and changes nothing of the run.
    fn control_history(&mut self) -> (Vec<Vector3<f64>>, Vec<Vector3<f64>>) {
        if !self.records_control_history() {
            return (Vec::new(), Vec::new());
        }
        if matches!(self.integration, Integration::Coupled { .. }) {
            let plant = Plant::new(
                &self.config,
                &self.satellites.fleet,
                &self.timeline.threat_warnings,
                self.reference_model,
            );
            let view = plant.view(
                self.clock.time_s,
                &self.satellites.truth,
                noise_if_any(&self.config, &self.noise.navigation),
                &mut self.sensed,
            );
            plant.commands_with_history(
                &self.law,
                &view,
                self.clock.tick.saturating_sub(1),
                &mut self.satellites.commanded_hill,
                &mut self.satellites.applied_hill,
            );
        }
        let order = &self.satellites.fleet.order;
        (
            order.by_id(&self.satellites.commanded_hill),
            order.by_id(&self.satellites.applied_hill),
        )
    }
}
