//! The read-only sensing views the engine builds for a law: [`SwarmView`] (the whole swarm, for the
//! whole-swarm hooks), [`SatelliteView`] (what one satellite senses: own state, reachable neighbours,
//! threats and obstacles within range, ground messages in force) and [`Broadcast`] (what the neighbours
//! broadcast at the previous tick: their law states).
//!
//! Every vector is in the Hill frame (x radial out, y along-track, z orbit normal) relative to the LVLH
//! origin \[m, m/s\].

use nalgebra::Vector3;

use crate::environment::{Obstacle, Threat};
use crate::grid::{NeighbourGrid, RingOrder};
use crate::orbit::RelativeStateHill;
use crate::relative::SchweighartSedwick;
use crate::swarm::storage_order::Placement;

/// Swarm-level information granted to every satellite (ground warnings, broadcast quantities).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SharedInfo {
    /// Simulation time since the scenario start \[s\].
    pub time_s: f64,
    /// Mean motion of the reference orbit \[rad/s\] (for CW/HCW feed-forward terms).
    pub mean_motion_rad_s: f64,
    /// Range of every satellite's sensors and links \[m\]: neighbours farther away are never visited.
    pub sensing_range_m: f64,
    /// Schweighart–Sedwick J2-linearised model of the reference orbit at t = 0 (radius and osculating
    /// inclination of the LVLH origin's initial state; the model itself for `J2Linear` dynamics, J2 = 0
    /// for the J2-free models), for laws built on averaged J2 constants.
    pub reference_model: SchweighartSedwick,
}

/// What a satellite senses of a threat within its sensing range (or the threat's own detection range).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SensedThreat {
    /// The threat's index in the scenario.
    pub id: usize,
    /// The threat's position relative to the LVLH origin, Hill frame \[m\].
    pub position_hill_m: Vector3<f64>,
    /// The threat's velocity relative to the rotating Hill frame \[m/s\].
    pub velocity_hill_mps: Vector3<f64>,
    /// Threat position minus own position, Hill frame \[m\].
    pub offset_m: Vector3<f64>,
    /// Distance from the satellite to the threat \[m\].
    pub distance_m: f64,
    /// Radius of the threat's danger sphere \[m\].
    pub danger_radius_m: f64,
}

/// What a satellite senses of an obstacle within its sensing range (or the obstacle's detection range).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SensedObstacle {
    /// The obstacle's index in the scenario.
    pub id: usize,
    /// Centre of the sphere relative to the LVLH origin, Hill frame \[m\].
    pub center_hill_m: Vector3<f64>,
    /// Radius of the sphere \[m\].
    pub radius_m: f64,
    /// Centre minus own position, Hill frame \[m\].
    pub offset_m: Vector3<f64>,
    /// Distance from the satellite to the centre \[m\] (the surface is `radius_m` closer).
    pub distance_m: f64,
}

/// What satellite `i` knows of a neighbour `j` within sensing range. Only the engine makes these
/// (`non_exhaustive`): a law reads a neighbour's broadcast through a `Neighbour` its view gave it, so it
/// cannot forge one for a satellite out of reach.
///
/// Outside the crate a `Neighbour` cannot be built, even with every public field given (regression
/// test: a law used to forge one to read the broadcast of any satellite):
///
/// ```compile_fail
/// use nalgebra::Vector3;
/// use satflock::orbit::RelativeStateHill;
///
/// let forged = satflock::swarm::Neighbour {
///     id: 1,
///     state: RelativeStateHill::default(),
///     offset_m: Vector3::zeros(),
///     distance_m: 0.0,
/// };
/// # let _ = forged;
/// ```
#[derive(Clone, Copy)]
#[non_exhaustive]
pub struct Neighbour {
    /// The neighbour's id.
    pub id: usize,
    /// The neighbour's state relative to the LVLH origin, Hill frame \[m, m/s\].
    pub state: RelativeStateHill,
    /// Neighbour position minus own position, Hill frame \[m\].
    pub offset_m: Vector3<f64>,
    /// Distance between the two satellites \[m\].
    pub distance_m: f64,
    /// The neighbour's entry in the view's slices (the engine's storage order), where its broadcast
    /// is.
    index: usize,
}

// By hand, without the storage index: nothing a law can observe depends on the engine's storage order.
impl PartialEq for Neighbour {
    fn eq(&self, other: &Self) -> bool {
        (self.id, self.state, self.offset_m, self.distance_m)
            == (other.id, other.state, other.offset_m, other.distance_m)
    }
}

impl std::fmt::Debug for Neighbour {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Neighbour")
            .field("id", &self.id)
            .field("state", &self.state)
            .field("offset_m", &self.offset_m)
            .field("distance_m", &self.distance_m)
            .finish()
    }
}

/// The whole swarm as the engine sees it at one right-hand-side evaluation: navigation states relative to
/// the LVLH origin (Hill frame), who is alive and linked, and the neighbour grid over those positions.
/// Laws get a [`SatelliteView`] of it, never the whole view, except in the whole-swarm hooks of
/// [`crate::swarm::GuidanceLaw`] (`initialise`, `centralised_update`, `record_metrics`, `results`), whose
/// views hold satellite `i` at index `i` of every slice. (The engine's own per-tick views are in its
/// storage order, sorted by grid cell; laws only see those through [`SatelliteView`].)
#[derive(Clone, Copy)]
pub struct SwarmView<'a> {
    /// Relative states, Hill frame, one per satellite (navigation solution: truth plus any noise).
    pub relative_states: &'a [RelativeStateHill],
    /// Masses \[kg\].
    pub masses_kg: &'a [f64],
    /// `false` for satellites removed from the swarm.
    pub active: &'a [bool],
    /// `false` for satellites whose links are cut: they neither see nor are seen.
    pub links_up: &'a [bool],
    /// Grid over the navigation positions, built with the sensing range as its radius (empty if a
    /// position was not finite; the divergence check then stops the run after the step). The engine
    /// masks it ([`NeighbourGrid::mask`]) with `active && links_up`; an unmasked grid works too (the
    /// views then check the flags of every neighbour).
    pub grid: &'a NeighbourGrid,
    /// Swarm-level information.
    pub shared: SharedInfo,
    /// Threats, obstacles and ground messages.
    pub environment: EnvironmentView<'a>,
    /// Which satellite each entry of the slices holds when the engine stores its satellites in an
    /// order of its own (`None`: entry `i` is satellite `i`). Views a law's whole-swarm hooks get are
    /// always by id.
    placement: Option<Placement<'a>>,
    /// The ring neighbourhood (`[sensing] ring_neighbours`), over the same entries as the slices: when
    /// present, a satellite senses its ring neighbours instead of the satellites within range.
    ring: Option<&'a RingOrder>,
}

/// What a law may check about the swarm it will steer before it runs: the same facts at load time (from
/// the scenario) and at start (from the view), so a law set by an event is checked when the scenario
/// loads, not when the event fires.
#[derive(Clone, Debug, PartialEq)]
pub struct SwarmFacts {
    /// Range of sensors and links \[m\].
    pub sensing_range_m: f64,
    /// Number of satellites.
    pub count: usize,
    /// Velocity of every scenario threat, Hill frame \[m/s\].
    pub threat_velocities_hill_mps: Vec<Vector3<f64>>,
}

impl SwarmFacts {
    /// The facts of a running swarm.
    pub fn of(swarm: &SwarmView<'_>) -> Self {
        Self {
            sensing_range_m: swarm.shared.sensing_range_m,
            count: swarm.len(),
            threat_velocities_hill_mps: swarm
                .environment
                .threats
                .iter()
                .map(|t| t.velocity_hill_mps(swarm.shared.time_s))
                .collect(),
        }
    }
}

/// The environment a view senses: the scenario's threats and obstacles, and the ground messages in force.
#[derive(Clone, Copy, Debug, Default)]
pub struct EnvironmentView<'a> {
    /// Kinematic threats (straight lines in the Hill frame).
    pub threats: &'a [Threat],
    /// Static spheres in the Hill frame.
    pub obstacles: &'a [Obstacle],
    /// Per threat: whether a ground warning about it is in force.
    pub threat_warnings: &'a [bool],
}

impl<'a> SwarmView<'a> {
    /// A view of the swarm whose per-satellite slices hold satellite `i` at index `i` (one entry per
    /// satellite each), over `grid` built on those positions (see the fields).
    pub fn new(
        relative_states: &'a [RelativeStateHill],
        masses_kg: &'a [f64],
        active: &'a [bool],
        links_up: &'a [bool],
        grid: &'a NeighbourGrid,
        shared: SharedInfo,
        environment: EnvironmentView<'a>,
    ) -> Self {
        Self {
            relative_states,
            masses_kg,
            active,
            links_up,
            grid,
            shared,
            environment,
            placement: None,
            ring: None,
        }
    }

    /// This view with a ring neighbourhood over its entries (built over the same navigation states):
    /// each satellite then senses its ring neighbours, whatever their distance, instead of the grid's
    /// satellites within range.
    pub fn with_ring(self, ring: &'a RingOrder) -> Self {
        Self {
            ring: Some(ring),
            ..self
        }
    }

    /// This view with its slices (and its grid's indices) in the storage order `placement`.
    pub(crate) fn in_storage_order(self, placement: Option<Placement<'a>>) -> Self {
        Self { placement, ..self }
    }

    /// This view over another grid (built over the same positions, in the same storage order).
    #[cfg(test)]
    pub(crate) fn with_grid(self, grid: &'a NeighbourGrid) -> Self {
        Self { grid, ..self }
    }

    /// The satellite id held at entry `index` of the slices.
    #[inline]
    pub(crate) fn id_at(&self, index: usize) -> usize {
        match self.placement {
            Some(p) => p.id_of[index] as usize,
            None => index,
        }
    }

    /// The entry of the slices that holds satellite `id`.
    #[inline]
    pub(crate) fn index_of(&self, id: usize) -> usize {
        match self.placement {
            Some(p) => p.index_of[id] as usize,
            None => id,
        }
    }

    /// Number of satellites (including removed ones, whose `active` flag is false).
    pub fn len(&self) -> usize {
        self.relative_states.len()
    }

    /// Whether the swarm has no satellites.
    pub fn is_empty(&self) -> bool {
        self.relative_states.is_empty()
    }

    /// The view satellite `id` is allowed to have.
    pub fn satellite(&self, id: usize) -> SatelliteView<'a> {
        self.satellite_at(self.index_of(id))
    }

    /// The view of the satellite held at entry `index` of the slices.
    pub(crate) fn satellite_at(&self, index: usize) -> SatelliteView<'a> {
        SatelliteView {
            id: self.id_at(index),
            index,
            own: None,
            sensed: None,
            swarm: *self,
        }
    }

    /// The view of satellite `own.id` with its own data already at hand (copied from this view by the
    /// engine, so the same values): a law evaluated in the grid's cell order then reads nothing of its
    /// own satellite from the view's slices (scattered in memory on a large swarm).
    pub(crate) fn satellite_with(&self, own: OwnSample) -> SatelliteView<'a> {
        SatelliteView {
            id: own.id,
            index: own.index,
            own: Some(own),
            sensed: None,
            swarm: *self,
        }
    }

    /// [`Self::satellite_with`] whose neighbour walks replay `neighbours`, the satellite's full walk
    /// (as [`SatelliteView::collect_neighbours`] gives it): the same neighbours in the same order with
    /// the same values, so a law that walks its neighbours several times queries the grid once.
    pub(crate) fn satellite_sensing<'b>(
        &self,
        own: OwnSample,
        neighbours: &'b [Neighbour],
    ) -> SatelliteView<'b>
    where
        'a: 'b,
    {
        SatelliteView {
            id: own.id,
            index: own.index,
            own: Some(own),
            sensed: Some(neighbours),
            swarm: *self,
        }
    }
}

/// A satellite's own data in a [`SwarmView`], copied out: its navigation state, mass and grid slot.
#[derive(Clone, Copy, Debug)]
pub(crate) struct OwnSample {
    /// The satellite's id.
    pub id: usize,
    /// Its entry in the view's slices.
    pub index: usize,
    /// Its storage slot in the view's grid.
    pub slot: usize,
    /// Its navigation state, Hill frame \[m, m/s\].
    pub state: RelativeStateHill,
    /// Its mass \[kg\].
    pub mass_kg: f64,
    /// Whether its links are up.
    pub links_up: bool,
}

impl OwnSample {
    /// The data of the satellite at entry `index` of `swarm`'s slices, whose grid holds it in storage
    /// slot `slot`.
    pub fn of(swarm: &SwarmView<'_>, index: usize, slot: usize) -> Self {
        Self {
            id: swarm.id_at(index),
            index,
            slot,
            state: swarm.relative_states[index],
            mass_kg: swarm.masses_kg[index],
            links_up: swarm.links_up[index],
        }
    }
}

/// What one satellite senses: its own state, its reachable neighbours and the shared information.
#[derive(Clone, Copy)]
pub struct SatelliteView<'a> {
    id: usize,
    /// The satellite's entry in the view's slices.
    index: usize,
    /// The satellite's own data when the engine copied it out (else read from `swarm` at `index`).
    own: Option<OwnSample>,
    /// The satellite's neighbours within sensing range, in walk order, when the engine already walked
    /// the grid for it (else walked on every visit).
    sensed: Option<&'a [Neighbour]>,
    swarm: SwarmView<'a>,
}

impl SatelliteView<'_> {
    /// This satellite's id (its index in the scenario).
    pub fn id(&self) -> usize {
        self.id
    }

    /// This satellite's entry in the view's slices (the engine's storage order).
    pub(crate) fn index(&self) -> usize {
        self.index
    }

    /// Own state relative to the LVLH origin, Hill frame \[m, m/s\].
    pub fn own_state(&self) -> RelativeStateHill {
        match &self.own {
            Some(own) => own.state,
            None => self.swarm.relative_states[self.index],
        }
    }

    /// Own mass \[kg\].
    pub fn mass_kg(&self) -> f64 {
        match &self.own {
            Some(own) => own.mass_kg,
            None => self.swarm.masses_kg[self.index],
        }
    }

    /// Swarm-level information.
    pub fn shared(&self) -> &SharedInfo {
        &self.swarm.shared
    }

    /// Visits every live, linked neighbour within sensing range, in a deterministic order; with a ring
    /// neighbourhood (`[sensing] ring_neighbours = k`), the k live, linked satellites nearest ahead
    /// along the orbit and the k nearest behind, at any distance (ahead first, nearest first).
    /// A satellite whose own links are cut sees nobody; nor does anyone while the grid is empty (a
    /// non-finite navigation position left it unbuilt; the divergence check then stops the run).
    pub fn for_each_neighbour(&self, visit: impl FnMut(&Neighbour)) {
        let reach_m = match self.swarm.ring {
            Some(_) => f64::INFINITY,
            None => self.swarm.grid.radius_m(),
        };
        self.for_each_neighbour_within(reach_m, visit);
    }

    /// [`Self::for_each_neighbour`] restricted to the neighbours within `reach_m` \[m\] (capped at the
    /// sensing range, the radius of the view's grid, unless the view has a ring neighbourhood): the
    /// same neighbours, in the same order, as filtering that walk by
    /// `distance_m <= reach_m`, but a reach well below the sensing range lets the grid skip whole
    /// cells. For a law whose neighbour terms vanish beyond a radius of its own.
    pub fn for_each_neighbour_within(&self, reach_m: f64, mut visit: impl FnMut(&Neighbour)) {
        let s = &self.swarm;
        // (A NaN reach stays NaN: nobody is within it.)
        let reach_m = if s.ring.is_none() && reach_m > s.grid.radius_m() {
            s.grid.radius_m()
        } else {
            reach_m
        };
        if let Some(sensed) = self.sensed {
            // The grid's inclusion rule, on the distances it computed.
            sensed
                .iter()
                .filter(|nb| nb.distance_m <= reach_m)
                .for_each(visit);
            return;
        }
        let links_up = self
            .own
            .map_or_else(|| s.links_up[self.index], |own| own.links_up);
        if !links_up || self.index >= s.grid.len() {
            return;
        }
        if let Some(ring) = s.ring {
            let own = self.own_state().position_m;
            ring.for_each_neighbour(self.index, |index| {
                let state = s.relative_states[index];
                let offset_m = state.position_m - own;
                let distance_m = offset_m.norm();
                if distance_m <= reach_m {
                    visit(&Neighbour {
                        index,
                        id: s.id_at(index),
                        state,
                        offset_m,
                        distance_m,
                    });
                }
            });
            return;
        }
        let mut report = |nb: crate::grid::Neighbour| {
            visit(&Neighbour {
                index: nb.index,
                id: s.id_at(nb.index),
                state: s.relative_states[nb.index],
                offset_m: Vector3::new(nb.dx_m, nb.dy_m, nb.dz_m),
                distance_m: nb.distance_m,
            })
        };
        if s.grid.is_masked() {
            // The engine's grid hides removed and unlinked satellites itself: no per-neighbour lookup
            // of the flags (by storage index, scattered in memory).
            match &self.own {
                Some(own) => s.grid.for_each_within_slot(own.slot, reach_m, report),
                None => s.grid.for_each_within(self.index, reach_m, report),
            }
        } else {
            s.grid.for_each_within(self.index, reach_m, |nb| {
                if s.active[nb.index] && s.links_up[nb.index] {
                    report(nb);
                }
            });
        }
    }

    /// Replaces `out` with this satellite's neighbours within sensing range, in walk order (for
    /// [`SwarmView::satellite_sensing`]).
    pub(crate) fn collect_neighbours(&self, out: &mut Vec<Neighbour>) {
        out.clear();
        self.for_each_neighbour(|nb| out.push(*nb));
    }

    /// Visits every threat within sensing range (the threat's detection range where the scenario gives
    /// one, else the satellite's sensing range), in scenario order. Threats are sensed by the satellite's
    /// own sensors: a satellite whose links are cut still sees them.
    pub fn for_each_threat(&self, mut visit: impl FnMut(&SensedThreat)) {
        let s = &self.swarm;
        let own = self.own_state().position_m;
        for (id, threat) in s.environment.threats.iter().enumerate() {
            let position = threat.position_hill_m(s.shared.time_s);
            let offset_m = position - own;
            let distance_m = offset_m.norm();
            let range = threat
                .detection_range_m()
                .unwrap_or(s.shared.sensing_range_m);
            if distance_m <= range {
                visit(&SensedThreat {
                    id,
                    position_hill_m: position,
                    velocity_hill_mps: threat.velocity_hill_mps(s.shared.time_s),
                    offset_m,
                    distance_m,
                    danger_radius_m: threat.danger_radius_m(),
                });
            }
        }
    }

    /// Visits every obstacle within sensing range (the obstacle's detection range where the scenario
    /// gives one, else the satellite's sensing range; measured to the surface), in scenario order.
    pub fn for_each_obstacle(&self, mut visit: impl FnMut(&SensedObstacle)) {
        let s = &self.swarm;
        let own = self.own_state().position_m;
        for (id, obstacle) in s.environment.obstacles.iter().enumerate() {
            let center = obstacle.center_hill_m(s.shared.time_s);
            let offset_m = center - own;
            let distance_m = offset_m.norm();
            let range = obstacle
                .detection_range_m()
                .unwrap_or(s.shared.sensing_range_m);
            if distance_m - obstacle.radius_m() <= range {
                visit(&SensedObstacle {
                    id,
                    center_hill_m: center,
                    radius_m: obstacle.radius_m(),
                    offset_m,
                    distance_m,
                });
            }
        }
    }

    /// Whether a ground warning about threat `threat` is in force (a ground message: it reaches the
    /// satellite whatever its links).
    pub fn threat_warning(&self, threat: usize) -> bool {
        self.swarm
            .environment
            .threat_warnings
            .get(threat)
            .copied()
            .unwrap_or(false)
    }

    /// The ground's track of threat `threat` while a warning about it is in force: the warning message
    /// carries the threat's state (position and velocity now, danger radius), whatever the satellite's
    /// own sensors see. `None` without a warning.
    pub fn warned_threat(&self, threat: usize) -> Option<SensedThreat> {
        if !self.threat_warning(threat) {
            return None;
        }
        let s = &self.swarm;
        let t = s.environment.threats.get(threat)?;
        let position = t.position_hill_m(s.shared.time_s);
        let offset_m = position - self.own_state().position_m;
        Some(SensedThreat {
            id: threat,
            position_hill_m: position,
            velocity_hill_mps: t.velocity_hill_mps(s.shared.time_s),
            offset_m,
            distance_m: offset_m.norm(),
            danger_radius_m: t.danger_radius_m(),
        })
    }

    /// Whether any ground threat warning is in force.
    pub fn any_threat_warning(&self) -> bool {
        self.swarm.environment.threat_warnings.iter().any(|w| *w)
    }
}

/// What a satellite's neighbours broadcast at the previous tick: their law states, readable only through
/// a [`Neighbour`] the satellite's view gave it, plus the satellite's own previous state.
#[derive(Clone, Copy)]
pub struct Broadcast<'a, S> {
    own: &'a S,
    /// Every satellite's previous state by storage index; `None` for a law updated in place (see
    /// [`crate::swarm::GuidanceLaw::reads_neighbour_broadcasts`]).
    previous: Option<&'a [S]>,
}

impl<'a, S> Broadcast<'a, S> {
    /// The broadcasts `previous` (by storage index) as the satellite at storage index `index` reads
    /// them.
    pub(crate) fn new(index: usize, previous: &'a [S]) -> Self {
        Self {
            own: &previous[index],
            previous: Some(previous),
        }
    }

    /// The satellite's own previous state `own` alone, for a law that reads no neighbour's broadcast.
    pub(crate) fn own_only(own: &'a S) -> Self {
        Self {
            own,
            previous: None,
        }
    }

    /// The satellite's own state at the previous tick.
    pub fn own(&self) -> &'a S {
        self.own
    }

    /// What `neighbour` broadcast at the previous tick.
    ///
    /// # Panics
    /// For a law that declared it reads no neighbour's broadcast
    /// ([`crate::swarm::GuidanceLaw::reads_neighbour_broadcasts`] `false`): its states are updated in
    /// place, so the neighbours' previous states are no longer there to read.
    pub fn of(&self, neighbour: &Neighbour) -> &'a S {
        let previous = self
            .previous
            .expect("Broadcast::of called by a law whose reads_neighbour_broadcasts() is false");
        &previous[neighbour.index]
    }
}

#[cfg(test)]
mod tests {
    use super::OwnSample;

    /// A neighbour whose broadcast sits at storage index `index`.
    fn neighbour_at(index: usize) -> super::Neighbour {
        super::Neighbour {
            id: index,
            state: crate::orbit::RelativeStateHill::default(),
            offset_m: nalgebra::Vector3::zeros(),
            distance_m: 0.0,
            index,
        }
    }

    /// Two buffers: a neighbour's broadcast is its previous state, found by its storage index.
    #[test]
    fn broadcast_reads_a_neighbours_previous_state() {
        let previous = [10.0, 11.0, 12.0];
        let broadcast = super::Broadcast::new(1, &previous);
        assert_eq!(*broadcast.own(), 11.0);
        assert_eq!(*broadcast.of(&neighbour_at(2)), 12.0);
    }

    /// In place, only the own previous state is there: reading a neighbour's broadcast panics
    /// instead of returning a state that may already be this tick's.
    #[test]
    #[should_panic(expected = "reads_neighbour_broadcasts() is false")]
    fn own_only_broadcast_refuses_a_neighbours_state() {
        let own = 11.0;
        let broadcast = super::Broadcast::own_only(&own);
        assert_eq!(*broadcast.own(), 11.0);
        let _ = broadcast.of(&neighbour_at(0));
    }
    use crate::swarm::law::test_swarm::{grid_of, random_swarm, view, RANGE_M};

    /// A walk within a reach below the sensing range visits exactly the neighbours of the full walk
    /// within that reach, in the same order, with the same values: through the id, the own-sample and
    /// the replayed-walk paths, on masked and unmasked grids, with removed and link-cut satellites; a
    /// reach above the sensing range is capped at it, and a NaN or negative one reaches nobody.
    #[test]
    fn walk_within_a_reach_is_the_full_walk_filtered_by_distance() {
        let n = 1500;
        let states = random_swarm(n);
        let masses_kg = vec![10.0; n];
        let active: Vec<bool> = (0..n).map(|i| i % 11 != 4).collect();
        let links_up: Vec<bool> = (0..n).map(|i| i % 7 != 2).collect();
        let mut visited = 0;
        for masked in [false, true] {
            let mut grid = grid_of(&states);
            if masked {
                grid.mask(|i| active[i] && links_up[i]);
            }
            let swarm = view(&states, &masses_kg, &active, &links_up, &grid, 0.0);
            for i in 0..n {
                let mut by_id = Vec::new();
                swarm.satellite(i).for_each_neighbour(|nb| by_id.push(*nb));
                let own = OwnSample::of(&swarm, i, grid.slot(i));
                let mut sensed = Vec::new();
                swarm.satellite_with(own).collect_neighbours(&mut sensed);
                for satellite in [
                    swarm.satellite(i),
                    swarm.satellite_with(own),
                    swarm.satellite_sensing(own, &sensed),
                ] {
                    let mut full = Vec::new();
                    satellite.for_each_neighbour(|nb| full.push(*nb));
                    assert_eq!(full, by_id, "satellite {i}");
                    for reach in [
                        f64::NAN,
                        -1.0,
                        0.0,
                        0.1 * RANGE_M,
                        0.45 * RANGE_M,
                        RANGE_M,
                        3.0 * RANGE_M,
                    ] {
                        let mut within = Vec::new();
                        satellite.for_each_neighbour_within(reach, |nb| within.push(*nb));
                        let expected: Vec<_> = full
                            .iter()
                            .filter(|nb| nb.distance_m <= reach)
                            .copied()
                            .collect();
                        assert_eq!(within, expected, "satellite {i}, reach {reach} m");
                        visited += within.len();
                    }
                }
            }
        }
        assert!(visited > 50_000, "too few neighbours to test: {visited}");
    }
}
