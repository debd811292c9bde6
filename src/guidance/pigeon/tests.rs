//! Unit tests of the `pigeon` law's state update, driven through `update_state` with the crate-private
//! `Broadcast` (P9: the egalitarian hysteresis on a scripted pair of distances; P10: the empirical
//! frequency of the hierarchical draw against p_h).

use nalgebra::Vector3;

use super::{Pigeon, PigeonParameters, PigeonState};
use crate::grid::NeighbourGrid;
use crate::orbit::{EarthModel, RelativeStateHill};
use crate::relative::SchweighartSedwick;
use crate::swarm::{
    Actuator, Broadcast, EnvironmentView, GuidanceLaw, LawContext, LimitKind, SharedInfo, SwarmView,
};

/// Satellites, their grid and a 200 m sensing range (≥ R_c^2 = 150 m of the defaults).
struct Scene {
    states: Vec<RelativeStateHill>,
    masses_kg: Vec<f64>,
    flags: Vec<bool>,
    grid: NeighbourGrid,
}

const RANGE_M: f64 = 200.0;

impl Scene {
    fn new(states: Vec<RelativeStateHill>) -> Self {
        let mut grid = NeighbourGrid::new();
        let x: Vec<f64> = states.iter().map(|s| s.position_m.x).collect();
        let y: Vec<f64> = states.iter().map(|s| s.position_m.y).collect();
        let z: Vec<f64> = states.iter().map(|s| s.position_m.z).collect();
        grid.build(&x, &y, &z, RANGE_M).unwrap();
        let count = states.len();
        Self {
            states,
            masses_kg: vec![10.0; count],
            flags: vec![true; count],
            grid,
        }
    }

    fn view(&self) -> SwarmView<'_> {
        let earth = EarthModel::WGS84_EGM96;
        SwarmView::new(
            &self.states,
            &self.masses_kg,
            &self.flags,
            &self.flags,
            &self.grid,
            SharedInfo {
                time_s: 0.0,
                mean_motion_rad_s: earth.mean_motion_rad_s(7.4e6),
                sensing_range_m: RANGE_M,
                reference_model: SchweighartSedwick::new(
                    7.4e6,
                    0.0,
                    earth.mu_m3_s2,
                    earth.equatorial_radius_m,
                    0.0,
                ),
            },
            EnvironmentView::default(),
        )
    }
}

fn state(position_m: Vector3<f64>, velocity_mps: Vector3<f64>) -> RelativeStateHill {
    RelativeStateHill {
        position_m,
        velocity_mps,
    }
}

fn context(tick: u64) -> LawContext {
    LawContext::new(
        0.1 * tick as f64,
        tick,
        0.1,
        Actuator::new(5.0, LimitKind::PerAxis),
        0,
        7,
    )
}

/// Advances every satellite's state by one update on `scene`.
fn step(law: &Pigeon, scene: &Scene, previous: &[PigeonState], tick: u64) -> Vec<PigeonState> {
    let view = scene.view();
    (0..previous.len())
        .map(|i| {
            law.update_state(
                &view.satellite(i),
                &Broadcast::new(i, previous),
                &context(tick),
            )
        })
        .collect()
}

#[test]
fn p9_egalitarian_link_appears_at_rc1_minus_rl1_persists_to_rc1_and_drops_beyond() {
    // Pair separated along z (the pigeon plane's first axis) with an along-track offset too, so the
    // 2-D distance is √(dz² + dy²); x offsets are added to check that the radial axis does not count.
    // R_c^1 = 120 m, R_L^1 = 10 m: link appears at ≤ 110 m, persists while ≤ 120 m. Exact comparisons:
    // the distances are built from a 3-4-5 triangle, so ‖(0.6 d, 0.8 d)‖ = d to the last bit for the
    // values used (checked below).
    let law = Pigeon::new(PigeonParameters {
        egalitarian_range_m: 120.0,
        ..PigeonParameters::default()
    })
    .unwrap();
    let script: [(f64, bool); 9] = [
        (110.5, false), // initial set: only within 110 m
        (110.0, true),  // appears exactly at R_c^1 − R_L^1
        (115.0, true),  // persists
        (120.0, true),  // persists exactly at R_c^1
        (120.5, false), // drops beyond R_c^1
        (115.0, false), // does not reappear above 110 m
        (110.0, true),  // reappears at 110 m
        (119.0, true),
        (60.0, true),
    ];
    let mut states = vec![PigeonState::default(); 2];
    for (tick, (d, linked)) in script.into_iter().enumerate() {
        let a = state(Vector3::new(3.0, 5.0, -7.0), Vector3::zeros());
        let b = state(
            Vector3::new(-2.0, 5.0 + 0.8 * d, -7.0 + 0.6 * d),
            Vector3::zeros(),
        );
        let offset = b.position_m - a.position_m;
        assert_eq!(
            offset.y.hypot(offset.z),
            d,
            "scripted distance must be exact"
        );
        let scene = Scene::new(vec![a, b]);
        states = step(&law, &scene, &states, tick as u64);
        let expected: &[u32] = if linked { &[1] } else { &[] };
        assert_eq!(
            states[0].egalitarian(),
            expected,
            "tick {tick}, d = {d} m (0 -> 1)"
        );
        let expected: &[u32] = if linked { &[0] } else { &[] };
        assert_eq!(
            states[1].egalitarian(),
            expected,
            "tick {tick}, d = {d} m (1 -> 0)"
        );
    }
}

#[test]
fn p10_hierarchical_draw_frequency_matches_ph_within_three_sigma() {
    // Two satellites 50 m apart (linked), moving at right angles in the pigeon plane: V_a,i = ‖ẑ + ŷ‖/2
    // = 1/√2 for both, every tick (the states are not propagated). 1e5 independent draws (one per
    // tick, each from its own stream): the count of hierarchical ticks is binomial(1e5, p_h), so it
    // lies within 3σ = 3 √(n p (1 − p)) of n p except with probability 0.27 %; the seed is fixed.
    let law = Pigeon::new(PigeonParameters::default()).unwrap();
    let scene = Scene::new(vec![
        state(Vector3::zeros(), Vector3::new(0.0, 0.0, 1.0)),
        state(Vector3::new(0.0, 50.0, 0.0), Vector3::new(0.0, 2.0, 0.0)),
    ]);
    let va = std::f64::consts::FRAC_1_SQRT_2;
    let p = 1.0 / (1.0 + 9.0 * (-10.0 * (1.0 - va)).exp());
    let draws = 100_000u64;
    let mut states = vec![PigeonState::default(); 2];
    let mut hierarchical = 0u64;
    let mut switches = 0u64;
    let mut previous_pattern = None;
    for tick in 0..draws {
        states = step(&law, &scene, &states, tick);
        let s = &states[0];
        assert!(
            (s.local_order_parameter - va).abs() <= 1e-15,
            "V_a,i {}",
            s.local_order_parameter
        );
        assert!((s.hierarchical_probability - p).abs() <= 1e-15);
        if let Some(previous) = previous_pattern {
            switches += u64::from(previous != s.hierarchical);
        }
        previous_pattern = Some(s.hierarchical);
        hierarchical += u64::from(s.hierarchical);
    }
    let n = draws as f64;
    let sigma = (n * p * (1.0 - p)).sqrt();
    assert!(
        (hierarchical as f64 - n * p).abs() <= 3.0 * sigma,
        "{hierarchical} hierarchical of {draws}, expected {} ± {}",
        n * p,
        3.0 * sigma
    );
    // The state's switch counter is the number of pattern changes between consecutive ticks.
    assert_eq!(states[0].switches, switches);
    // Non-switching: p_h = 0 and never hierarchical.
    let fixed = Pigeon::new(PigeonParameters {
        switching: false,
        ..PigeonParameters::default()
    })
    .unwrap();
    let mut states = vec![PigeonState::default(); 2];
    for tick in 0..1000 {
        states = step(&fixed, &scene, &states, tick);
        assert!(!states[0].hierarchical && states[0].hierarchical_probability == 0.0);
    }
}

#[test]
fn order_parameter_uses_the_previous_ticks_pattern_set() {
    // Three satellites in a row along y, 100 m apart: 0–1 and 1–2 within R_c^1 − R_L^1, 0–2 (200 m)
    // beyond every range. Satellite 0's V_a,0 at the first tick is over N_0^1(t_0) = {1}; its headings
    // are +z and +y, so V_a,0 = 1/√2 whatever the pattern drawn.
    let law = Pigeon::new(PigeonParameters::default()).unwrap();
    let scene = Scene::new(vec![
        state(Vector3::zeros(), Vector3::new(0.0, 0.0, 1.0)),
        state(Vector3::new(0.0, 100.0, 0.0), Vector3::new(0.0, 1.0, 0.0)),
        state(Vector3::new(0.0, 200.0, 0.0), Vector3::new(0.0, 1.0, 0.0)),
    ]);
    let states = step(&law, &scene, &vec![PigeonState::default(); 3], 0);
    let va = std::f64::consts::FRAC_1_SQRT_2;
    assert!((states[0].local_order_parameter - va).abs() <= 1e-15);
    // Satellite 1 sees 0 and 2: (ẑ + ŷ + ŷ)/3 = √5/3.
    assert!((states[1].local_order_parameter - 5f64.sqrt() / 3.0).abs() <= 1e-15);
    // Next tick: satellite 1's set is the one its pattern chose (both sets are {0, 2} here).
    assert_eq!(states[1].neighbours(), vec![0, 2]);
}

#[test]
fn stabilisation_time_is_the_first_recording_inside_the_final_band_for_good() {
    // Final value 40 m, band ±0.8 m: 41 m (t = 2 s) and 42 m (t = 4 s) are outside, 40.5 m (t = 3 s)
    // inside but not for good, so the spacing is stable from t = 5 s (our reading of "last time it leaves
    // the ±2 % band"); a history always inside the band is stable from its first recording.
    let mut law = Pigeon::new(PigeonParameters::default()).unwrap();
    assert_eq!(law.stabilisation_time_s(), None);
    law.mean_distance_history = [100.0, 50.0, 41.0, 40.5, 42.0, 40.0]
        .iter()
        .enumerate()
        .map(|(k, d)| (k as f64, *d))
        .collect();
    assert_eq!(law.stabilisation_time_s(), Some(5.0));
    law.mean_distance_history = vec![(10.0, 40.3), (11.0, 39.9), (12.0, 40.0)];
    assert_eq!(law.stabilisation_time_s(), Some(10.0));
}

/// A satellite linked to 18 others (more ids than a state holds inline, so the list is on the heap)
/// keeps the links through the hysteresis band R_c^1 − R_L^1 < d ≤ R_c^1, which a satellite never
/// linked does not get; the members' lists (18 ids each, on the heap too) hold it as well.
#[test]
fn hysteresis_holds_for_a_link_list_longer_than_the_inline_ids() {
    let law = Pigeon::new(PigeonParameters {
        egalitarian_range_m: 120.0,
        hierarchical_range_m: 150.0,
        ..PigeonParameters::default()
    })
    .unwrap();
    // Members 0..18 on the y axis 1 m apart; satellite 18 at z = d, y = 8.5: its distances to the
    // members lie in [d, √(d² + 8.5²)].
    let scene = |d: f64| {
        let mut states: Vec<RelativeStateHill> = (0..18)
            .map(|k| state(Vector3::new(0.0, f64::from(k), 0.0), Vector3::zeros()))
            .collect();
        states.push(state(Vector3::new(0.0, 8.5, d), Vector3::zeros()));
        Scene::new(states)
    };
    let members: Vec<u32> = (0..18).collect();
    let linked = step(&law, &scene(100.0), &vec![PigeonState::default(); 19], 0);
    assert_eq!(linked[18].egalitarian(), members.as_slice());
    let kept = step(&law, &scene(115.0), &linked, 1);
    assert_eq!(kept[18].egalitarian(), members.as_slice());
    assert!(kept[..18].iter().all(|s| s.is_egalitarian(18)));
    assert_eq!(kept[5].egalitarian().len(), 18);
    let fresh = step(&law, &scene(115.0), &vec![PigeonState::default(); 19], 0);
    assert!(fresh[18].egalitarian().is_empty());
    assert!(fresh[..18].iter().all(|s| !s.is_egalitarian(18)));
}
