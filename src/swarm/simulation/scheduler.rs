//! The run loop. Time advances in segments whose ends are the control ticks (or integration steps), the
//! recording times, the event times, the end of the run and the time a caller asked for; every one of
//! them is hit exactly. At a tick: the centralised step if due, new noise draws, the law-state update
//! and (sampled mode) the held command; then the segment is integrated, the truth monitors run, due
//! timed events apply, at a tick's end the condition events are evaluated and those that hold fire,
//! and the recorder gets a snapshot if it is a recording time (or a `record-snapshot` fired, or a
//! `stop-run`, which ends the run there).

use std::sync::atomic::Ordering;
use std::time::Instant;

use nalgebra::Vector3;
use rayon::prelude::*;

use crate::dynamics::ForceModel;
use crate::orbit::LvlhFrame;
use crate::random::{Purpose, RandomStream};
use crate::swarm::dynamics::DynamicsModel;
use crate::swarm::recorder::Recorder;
use crate::swarm::simulation::monitors::{bad_command, bad_command_error, check_commands};
use crate::swarm::simulation::propagation::{CoupledSwarm, SampledSegment};
use crate::swarm::simulation::satellites::Satellites;
use crate::swarm::simulation::sensing::{Plant, CHUNK};
use crate::swarm::simulation::{Integration, RunTotals, SimError, Simulation, SimulationConfig};
use crate::swarm::state::{satellite_index, satellite_of};

/// Where the run loop is.
#[derive(Clone, Copy, Debug)]
pub(super) struct Clock {
    /// Simulated time \[s\] since the epoch.
    pub time_s: f64,
    /// Ticks started so far (the index of the next tick).
    pub tick: u64,
    /// Base steps completed (the scheduler's tick grid).
    pub step_count: u64,
    /// Index of the next recording time (the first, t = 0, is `started`).
    pub record_count: u64,
    /// Whether the snapshot at t = 0 has been recorded.
    pub started: bool,
}

impl Clock {
    /// At t = 0, before the first tick; the next recording after t = 0 is the first multiple of the
    /// recording interval.
    pub fn start() -> Self {
        Self {
            time_s: 0.0,
            tick: 0,
            step_count: 0,
            record_count: 1,
            started: false,
        }
    }
}

impl Simulation {
    /// Runs from the current time to the end of the run, recording at the cadence (and at t = 0 if not
    /// yet recorded). `progress` is called with the simulated time after every segment. On divergence
    /// the recorder has received every snapshot up to the last good one. A `stop-run` event ends the
    /// run early, with a last snapshot at its time ([`Simulation::stopped_by`] names it); later calls
    /// then advance no further.
    pub fn run(
        &mut self,
        recorder: &mut dyn Recorder,
        progress: &mut dyn FnMut(f64),
    ) -> Result<RunTotals, SimError> {
        self.advance_with_progress(self.config.duration_s, Some(recorder), progress)?;
        Ok(self.totals.clone())
    }

    /// Advances to `time_s` (at most the end of the run) through the same scheduler as [`Simulation::run`]:
    /// events, records and the end of the run happen exactly as in an uninterrupted run. The result is
    /// bitwise identical to an uninterrupted run when every `time_s` asked for is a tick or recording
    /// time (otherwise the extra segment end changes the integrator's steps, within its accuracy).
    pub fn advance_to(&mut self, time_s: f64, recorder: &mut dyn Recorder) -> Result<(), SimError> {
        self.advance_with_progress(time_s, Some(recorder), &mut |_| {})
    }

    /// The scheduler. Without a recorder, recording times are passed (and counted) but no snapshot is
    /// built.
    fn advance_with_progress(
        &mut self,
        time_s: f64,
        mut recorder: Option<&mut dyn Recorder>,
        progress: &mut dyn FnMut(f64),
    ) -> Result<(), SimError> {
        let base = self.config.base_step_s();
        let record = self.config.record_interval_s;
        let duration = self.config.duration_s;
        let end = time_s.min(duration);
        let eps = self.config.time_epsilon_s();
        if !self.clock.started {
            self.clock.started = true;
            self.timeline.snapshot_requested = false;
            if let Some(recorder) = recorder.as_deref_mut() {
                let clock = Instant::now();
                self.record(recorder)?;
                self.timings.recording_s += clock.elapsed().as_secs_f64();
            }
        }
        if let Some(recorder) = recorder.as_deref_mut() {
            self.send_firings(recorder)?;
        }
        while self.clock.time_s < end - eps && self.timeline.stop.is_none() {
            let next_step = ((self.clock.step_count + 1) as f64 * base).min(duration);
            let next_record = (self.clock.record_count as f64 * record).min(duration);
            let next_event = self.timeline.next_time_s();
            let mut t1 = next_step
                .min(next_record)
                .min(next_event.max(self.clock.time_s));
            if end < t1 - eps {
                t1 = end;
            }
            let at_tick = (self.clock.time_s - self.clock.step_count as f64 * base).abs() <= eps;
            let t0 = self.clock.time_s;
            if t1 > self.clock.time_s + eps {
                self.advance_segment(self.clock.time_s, t1, at_tick)?;
            }
            self.clock.time_s = t1;
            let tick_end = (t1 - next_step).abs() <= eps;
            if tick_end {
                self.clock.step_count += 1;
            }
            let clock = Instant::now();
            self.monitor(t0)?;
            self.timings.monitors_s += clock.elapsed().as_secs_f64();
            self.apply_due_events()?;
            if tick_end {
                self.apply_condition_events()?;
            }
            if let Some(recorder) = recorder.as_deref_mut() {
                self.send_firings(recorder)?;
            }
            let cadence = (t1 - next_record).abs() <= eps;
            if cadence {
                self.clock.record_count += 1;
            }
            // A recording time, a `record-snapshot`, or the last snapshot of a `stop-run`.
            let snapshot =
                cadence || self.timeline.snapshot_requested || self.timeline.stop.is_some();
            self.timeline.snapshot_requested = false;
            if let (true, Some(recorder)) = (snapshot, recorder.as_deref_mut()) {
                let clock = Instant::now();
                self.record(recorder)?;
                self.timings.recording_s += clock.elapsed().as_secs_f64();
            }
            progress(self.clock.time_s);
            if self
                .cancel
                .as_ref()
                .is_some_and(|flag| flag.load(Ordering::Relaxed))
            {
                self.totals.time_s = self.clock.time_s;
                return Err(SimError::Interrupted {
                    time_s: self.clock.time_s,
                });
            }
        }
        self.totals.time_s = self.clock.time_s;
        Ok(())
    }

    /// Hands the recorder the firings it has not had yet (kept until there is a recorder).
    fn send_firings(&mut self, recorder: &mut dyn Recorder) -> Result<(), SimError> {
        for firing in &self.timeline.fired[self.timeline.fired_sent..] {
            recorder.event_fired(firing)?;
        }
        self.timeline.fired_sent = self.timeline.fired.len();
        Ok(())
    }

    /// Advances to the next tick (control period, or integration step in continuous mode; at most the
    /// end of the run) through the same scheduler as [`Simulation::run`], with the monitors and due
    /// events, but no recording. For callers that drive the loop themselves (benchmarks); it mixes
    /// freely with [`Simulation::advance_to`] and [`Simulation::run`].
    pub fn step(&mut self) -> Result<(), SimError> {
        self.advance_with_progress(self.next_tick_s(), None, &mut |_| {})
    }

    /// The time of the next tick \[s\] (control tick, or integration step in continuous mode; past the
    /// end of the run once it is reached): `advance_to(next_tick_s())` is [`Simulation::step`] with
    /// recording.
    pub fn next_tick_s(&self) -> f64 {
        (self.clock.step_count + 1) as f64 * self.config.base_step_s()
    }

    /// Advances the state from t0 to t1 (one segment). `at_tick`: t0 is a control tick.
    fn advance_segment(&mut self, t0: f64, t1: f64, at_tick: bool) -> Result<(), SimError> {
        if at_tick {
            self.start_tick(t0)?;
        }
        let clock = Instant::now();
        if !self.monitors.truth_previous.is_empty() {
            self.monitors
                .truth_previous
                .copy_from_slice(&self.satellites.truth);
        }
        if self.monitors.conjunctions.is_some() {
            self.monitors.origin_previous = self.origin_states();
        }
        let n = self.state.n();
        let plant = Plant::new(
            &self.config,
            &self.satellites.fleet,
            &self.timeline.threat_warnings,
            self.reference_model,
        );
        let config = &self.config;
        // Reference orbit, alone (in sampled mode; the coupled system carries it in continuous mode).
        match &mut self.integration {
            Integration::Coupled { stepper, scratch } => {
                let system = CoupledSwarm {
                    plant,
                    law: &self.law,
                    tick: self.clock.tick - 1,
                    navigation_noise: noise_if_any(config, &self.noise.navigation),
                    process_noise_hill: &self.noise.process_hill,
                    scratch,
                };
                let advanced =
                    stepper.advance(&system, t0, t1, self.state.as_mut_slice(), config.step_s);
                // A non-finite command is named before the integration failure it causes.
                let scratch = scratch.get_mut().unwrap_or_else(|e| e.into_inner());
                check_commands(
                    scratch.applied_hill(),
                    &self.satellites.fleet,
                    &self.law,
                    self.clock.tick - 1,
                    t0,
                )?;
                advanced?;
            }
            Integration::Sampled(buffers) => {
                let reference_rhs = |t: f64, y: &[f64], dy: &mut [f64]| {
                    let a = plant.reference_acceleration(
                        t,
                        &Vector3::new(y[0], y[1], y[2]),
                        &Vector3::new(y[3], y[4], y[5]),
                    );
                    dy[0..3].copy_from_slice(&y[3..6]);
                    dy[3..6].copy_from_slice(a.as_slice());
                };
                let data = self.state.as_mut_slice();
                self.reference_stepper.advance(
                    &reference_rhs,
                    t0,
                    t1,
                    &mut data[0..6],
                    config.step_s,
                )?;
                SampledSegment {
                    dynamics: &config.dynamics,
                    fleet: &self.satellites.fleet,
                    held: &self.satellites.held_control,
                    held_hill: &self.satellites.applied_hill,
                    commands_zero: self.satellites.commands_zero,
                    t0_s: t0,
                    t1_s: t1,
                    max_step_s: config.step_s,
                }
                .advance(buffers, data, n)?;
            }
        }
        if matches!(self.config.dynamics, DynamicsModel::Kinematic) {
            self.set_kinematic_velocities(t1);
        }
        let clock = {
            let now = Instant::now();
            self.timings.propagation_s += (now - clock).as_secs_f64();
            now
        };
        self.refresh_truth(t1);
        self.place_tracked_objects(t1, Some(t0))?;
        self.timings.sensing_s += clock.elapsed().as_secs_f64();
        Ok(())
    }

    /// The start of a tick at `t0`: the centralised step if due, this tick's noise draws, the law-state
    /// update on the navigation view, and in sampled mode the command held until the next tick.
    fn start_tick(&mut self, t0: f64) -> Result<(), SimError> {
        let clock = Instant::now();
        self.resort_if_due(self.clock.tick);
        self.timings.sensing_s += clock.elapsed().as_secs_f64();
        if self.law.centralised_due(t0) {
            let clock = Instant::now();
            self.with_truth_view(|law, view, _| law.centralised_update(view))?;
            self.timings.law_s += clock.elapsed().as_secs_f64();
        }
        let tick = self.clock.tick;
        self.clock.tick += 1;
        self.draw_noise(tick);
        let live = self.satellites.fleet.active.iter().filter(|a| **a).count() as u64;
        self.totals.satellite_steps += live;

        let plant = Plant::new(
            &self.config,
            &self.satellites.fleet,
            &self.timeline.threat_warnings,
            self.reference_model,
        );
        let sampled = plant.sampled();
        let stateful = self.law.is_stateful();
        let kinematic = matches!(self.config.dynamics, DynamicsModel::Kinematic);
        if !(sampled || stateful || kinematic) {
            return Ok(());
        }
        if sampled
            && !(stateful || kinematic)
            && self.config.process_noise_m_s2 == 0.0
            && self.law.commands_nothing()
        {
            // Nothing to evaluate: the held commands are zero (written once, after a law that
            // commanded something).
            if !self.satellites.commands_zero {
                self.satellites.zero_commands();
            }
            if !self.drag_commands.is_empty() {
                self.account_drag(t0);
            }
            return Ok(());
        }
        self.satellites.commands_zero = false;
        let clock = Instant::now();
        let view = plant.view(
            t0,
            &self.satellites.truth,
            noise_if_any(&self.config, &self.noise.navigation),
            &mut self.sensed,
        );
        let clock = {
            let now = Instant::now();
            self.timings.sensing_s += (now - clock).as_secs_f64();
            now
        };
        let commands = sampled || kinematic;
        // `held_control` is rewritten from `applied_hill` below: until then it is scratch.
        let fused = stateful
            && commands
            && plant.states_and_commands_in_cell_order(
                &mut self.law,
                &view,
                tick,
                &mut self.satellites.held_control,
                &mut self.satellites.applied_hill,
                &mut self.satellites.commanded_hill,
            );
        if stateful && !fused {
            self.law
                .update_states(&view, &self.satellites.fleet.active, &|i| {
                    plant.context(i, t0, tick, false)
                });
        }
        if commands {
            if !fused {
                plant.commands_in_cell_order(
                    &self.law,
                    &view,
                    tick,
                    &mut self.satellites.held_control,
                    &mut self.satellites.applied_hill,
                    &mut self.satellites.commanded_hill,
                );
            }
            let frame = self
                .config
                .dynamics
                .is_inertial()
                .then(|| plant.frame(t0, self.state.as_slice()));
            let bad = self.hold_commands(frame);
            bad_command_error(bad, &self.law, tick, t0)?;
        }
        if stateful {
            self.apply_drag_commands(t0, tick)?;
        }
        if !self.drag_commands.is_empty() {
            self.account_drag(t0);
        }
        self.timings.law_s += clock.elapsed().as_secs_f64();
        if kinematic {
            // The velocity state is the command from the start of the segment, so the monitors'
            // Hermite path over the segment starts with the velocity actually followed.
            self.set_velocities_to_commands();
            self.refresh_truth(t0);
        }
        Ok(())
    }

    /// Applies the law's drag commands of the tick (from the states just updated) to the satellites with
    /// drag attitudes: the commanded area, unless the satellite changed its area less than its minimum
    /// dwell ago; every change counted. A command the satellite cannot present stops the run.
    fn apply_drag_commands(&mut self, t0: f64, tick: u64) -> Result<(), SimError> {
        if self.drag_commands.is_empty() || !self.law.drag_commands(&mut self.drag_commands) {
            return Ok(());
        }
        let epsilon = self.config.time_epsilon_s();
        let Satellites {
            fleet,
            drag_changed_s,
            drag_switches,
            ..
        } = &mut self.satellites;
        for (index, command) in self.drag_commands.iter().enumerate() {
            let (Some(command), Some(attitudes), true) =
                (command, fleet.drag_attitudes[index], fleet.active[index])
            else {
                continue;
            };
            let Some(area) = attitudes.area_of(*command) else {
                return Err(SimError::BadDragCommand {
                    satellite: fleet.order.id_at(index),
                    tick,
                    time_s: t0,
                    law: self.law.name().to_string(),
                    command: format!("{command:?}"),
                    allowed: attitudes.describe(),
                });
            };
            if area != fleet.drag_area_m2(index)
                && t0 - drag_changed_s[index] >= attitudes.min_dwell_s - epsilon
            {
                fleet.set_drag_area_m2(index, area);
                drag_changed_s[index] = t0;
                drag_switches[index] += 1;
            }
        }
        Ok(())
    }

    /// At a tick of a run with drag attitudes: adds each such satellite's drag acceleration over the
    /// tick period to its drag Δv (left-point rule), and the live satellites' mean altitude above the
    /// equatorial radius to the orbit-averaging window. Inertial truth only (drag attitudes need a
    /// force set with drag).
    fn account_drag(&mut self, t0: f64) {
        let Some(forces) = self.config.dynamics.forces() else {
            return;
        };
        let Some(drag) = forces.drag() else {
            return;
        };
        let at = forces.instant(t0);
        let period_s = self.config.base_step_s();
        let radius_m = self.config.earth.equatorial_radius_m;
        let n = self.state.n();
        let data = self.state.as_slice();
        let fleet = &self.satellites.fleet;
        let (mut altitude_sum, mut live) = (0.0, 0usize);
        for i in 0..n {
            if !fleet.active[i] {
                continue;
            }
            let (p, v) = satellite_of(data, n, i);
            altitude_sum += p.norm() - radius_m;
            live += 1;
            if matches!(fleet.drag_attitudes.get(i), Some(Some(_))) {
                let a = drag.acceleration_eci_m_s2(&at, &p, &v, &fleet.properties(i));
                self.satellites.drag_delta_v_mps[i] += a.norm() * period_s;
            }
        }
        if live > 0 {
            self.drag_altitude.push(altitude_sum / live as f64);
        }
    }

    /// Holds the tick's applied commands (plus process noise) in the dynamics frame until the next tick,
    /// and returns the live satellite of smallest id whose applied command is not finite, if any
    /// (the check of [`check_commands`], in the same pass).
    pub(super) fn hold_commands(
        &mut self,
        frame: Option<LvlhFrame>,
    ) -> Option<(usize, Vector3<f64>)> {
        let kinematic = matches!(self.config.dynamics, DynamicsModel::Kinematic);
        let process_hill = &self.noise.process_hill;
        let (fleet, applied_hill) = (&self.satellites.fleet, &self.satellites.applied_hill);
        // In parallel over fixed chunks, each a plain loop (a rotation and a root per satellite are a
        // serial millisecond or more on a large swarm). The smallest id is unique, so the answer does
        // not depend on the split.
        self.satellites
            .held_control
            .par_chunks_mut(CHUNK)
            .enumerate()
            .filter_map(|(chunk, held)| {
                let first = chunk * CHUNK;
                let mut smallest: Option<(usize, Vector3<f64>)> = None;
                for (k, held) in held.iter_mut().enumerate() {
                    let i = first + k;
                    let u = &applied_hill[i];
                    let total = if kinematic {
                        *u
                    } else {
                        u + process_noise_of(process_hill, i)
                    };
                    *held = match &frame {
                        Some(f) => f.vector_hill_to_eci(&total),
                        None => total,
                    };
                    if let Some(bad) = bad_command(fleet, i, u) {
                        if smallest.is_none_or(|(id, _)| bad.0 < id) {
                            smallest = Some(bad);
                        }
                    }
                }
                smallest
            })
            .min_by_key(|(id, _)| *id)
    }

    /// Kinematic model, continuous mode: after a segment each satellite's velocity state is the command
    /// evaluated at its end state (in sampled mode the held command, set at the tick, stays).
    fn set_kinematic_velocities(&mut self, t1: f64) {
        if matches!(self.integration, Integration::Sampled(_)) {
            return;
        }
        self.refresh_truth(t1);
        let plant = Plant::new(
            &self.config,
            &self.satellites.fleet,
            &self.timeline.threat_warnings,
            self.reference_model,
        );
        let view = plant.view(
            t1,
            &self.satellites.truth,
            noise_if_any(&self.config, &self.noise.navigation),
            &mut self.sensed,
        );
        plant.commands(
            &self.law,
            &view,
            self.clock.tick - 1,
            &mut self.satellites.applied_hill,
        );
        self.set_velocities_to_commands();
    }

    /// Kinematic model: writes the applied commands (Hill velocities) into the live satellites' velocity
    /// states.
    fn set_velocities_to_commands(&mut self) {
        let n = self.state.n();
        let data = self.state.as_mut_slice();
        for (i, v) in self.satellites.applied_hill.iter().enumerate() {
            if self.satellites.fleet.active[i] {
                for k in 0..3 {
                    data[satellite_index(n, 3 + k, i)] = v[k];
                }
            }
        }
    }

    /// Draws the navigation and process noise held during tick `tick`, from each satellite's own streams
    /// (by id; stored by storage index).
    fn draw_noise(&mut self, tick: u64) {
        let sensing = self.config.sensing;
        let seed = self.config.seed;
        let order = &self.satellites.fleet.order;
        if sensing.has_navigation_noise() {
            self.noise
                .navigation
                .par_iter_mut()
                .with_min_len(CHUNK)
                .enumerate()
                .for_each(|(i, e)| {
                    let id = order.id_at(i) as u64;
                    let mut stream = RandomStream::new(seed, Purpose::NavigationNoise, id, tick);
                    for (k, value) in e.iter_mut().enumerate() {
                        let sigma = if k < 3 {
                            sensing.position_noise_m
                        } else {
                            sensing.velocity_noise_mps
                        };
                        *value = sigma * stream.standard_normal();
                    }
                });
        }
        let sigma = self.config.process_noise_m_s2;
        if sigma > 0.0 {
            self.noise
                .process_hill
                .par_iter_mut()
                .with_min_len(CHUNK)
                .enumerate()
                .for_each(|(i, a)| {
                    let id = order.id_at(i) as u64;
                    let mut stream = RandomStream::new(seed, Purpose::ProcessNoise, id, tick);
                    *a = Vector3::from_fn(|_, _| sigma * stream.standard_normal());
                });
        }
    }
}

/// Satellite `i`'s process noise of the tick, Hill frame \[m/s^2\]: zero when the scenario has none (its
/// buffer is then empty), added all the same so that a command's bits do not depend on the buffer.
pub(super) fn process_noise_of(process_noise_hill: &[Vector3<f64>], i: usize) -> Vector3<f64> {
    process_noise_hill
        .get(i)
        .copied()
        .unwrap_or_else(Vector3::zeros)
}

/// The navigation noise of the tick, if the scenario has any.
pub(super) fn noise_if_any<'a>(
    config: &SimulationConfig,
    navigation_noise: &'a [[f64; 6]],
) -> Option<&'a [[f64; 6]]> {
    config
        .sensing
        .has_navigation_noise()
        .then_some(navigation_noise)
}
