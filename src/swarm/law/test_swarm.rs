//! Test support: a small random swarm and a [`SwarmView`] over it, for the tests of the views and of
//! the law handle.

use nalgebra::Vector3;

use crate::grid::NeighbourGrid;
use crate::orbit::{EarthModel, RelativeStateHill};
use crate::random::{Purpose, RandomStream};
use crate::relative::SchweighartSedwick;
use crate::swarm::{EnvironmentView, SharedInfo, SwarmView};

/// Sensing range of the views \[m\].
pub const RANGE_M: f64 = 60.0;

/// A random ball of `n` satellites, 250 m radius, moving at up to 1 m/s per axis.
pub fn random_swarm(n: usize) -> Vec<RelativeStateHill> {
    (0..n)
        .map(|i| {
            let mut draw = RandomStream::new(11, Purpose::InitialStates, i as u64, 0);
            let mut point = || Vector3::from_fn(|_, _| draw.uniform_range(-1.0, 1.0));
            let direction = point();
            RelativeStateHill {
                position_m: 250.0 * direction / direction.norm().max(1.0),
                velocity_mps: point(),
            }
        })
        .collect()
}

/// The grid over the positions of `states` with radius [`RANGE_M`].
pub fn grid_of(states: &[RelativeStateHill]) -> NeighbourGrid {
    let coordinates = |k: usize| -> Vec<f64> { states.iter().map(|s| s.position_m[k]).collect() };
    let mut grid = NeighbourGrid::new();
    grid.build(&coordinates(0), &coordinates(1), &coordinates(2), RANGE_M)
        .unwrap();
    grid
}

/// A view of `states` at time `time_s` \[s\] with sensing range [`RANGE_M`], no environment.
pub fn view<'a>(
    states: &'a [RelativeStateHill],
    masses_kg: &'a [f64],
    active: &'a [bool],
    links_up: &'a [bool],
    grid: &'a NeighbourGrid,
    time_s: f64,
) -> SwarmView<'a> {
    let earth = EarthModel::WGS84_EGM96;
    SwarmView::new(
        states,
        masses_kg,
        active,
        links_up,
        grid,
        SharedInfo {
            time_s,
            mean_motion_rad_s: earth.mean_motion_rad_s(7.0e6),
            sensing_range_m: RANGE_M,
            reference_model: SchweighartSedwick::new(
                7.0e6,
                0.0,
                earth.mu_m3_s2,
                earth.equatorial_radius_m,
                0.0,
            ),
        },
        EnvironmentView::default(),
    )
}
