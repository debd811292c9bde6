//! The laws' target formations (`TargetFormation::target_formation_hill_m`, written to `scene.json`),
//! checked against the geometry each built-in scenario states in words: gao-circle's ring of radius
//! 0.5 km in the orbital plane, gao-double-circle's concentric rings of 1 ± 0.5 km, gao-sphere-surface's
//! sphere of 1 km, es-e0's rhombus of side 6 m whose nodes the satellites start on, hold's slots (the
//! start positions); and laws without fixed target points give none.

use satflock::run::build_simulation;
use satflock::scenario::Scenario;
use satflock::swarm::Simulation;

fn simulation(name: &str) -> Simulation {
    build_simulation(&Scenario::load(name).unwrap()).unwrap()
}

fn targets(name: &str) -> Option<Vec<[f64; 3]>> {
    simulation(name)
        .law()
        .target_formation_hill_m()
        .map(|points| points.iter().map(|p| [p.x, p.y, p.z]).collect())
}

/// In-plane radius (Hill x radial, y along-track) and out-of-plane offset of a point [m].
fn in_plane(p: &[f64; 3]) -> (f64, f64) {
    (p[0].hypot(p[1]), p[2])
}

#[test]
fn val_gao_circle_target_is_a_ring_of_0_5_km_in_the_orbital_plane() {
    let points = targets("gao-circle").expect("the bifurcating ring has target points");
    assert_eq!(points.len(), 72);
    for p in &points {
        let (r, z) = in_plane(p);
        assert!((r - 500.0).abs() < 1e-9, "radius {r} m");
        assert!(z.abs() < 1e-12, "out of plane {z} m");
    }
    // Evenly spread around the ring: consecutive points 5° apart.
    let chord = 2.0 * 500.0 * (2.5f64).to_radians().sin();
    for w in points.windows(2) {
        let d = ((w[0][0] - w[1][0]).powi(2) + (w[0][1] - w[1][1]).powi(2)).sqrt();
        assert!(
            (d - chord).abs() < 1e-9,
            "spacing {d} m, expected {chord} m"
        );
    }
}

#[test]
fn val_gao_double_circle_target_is_two_rings_of_0_5_and_1_5_km() {
    let points = targets("gao-double-circle").unwrap();
    let (inner, outer): (Vec<_>, Vec<_>) = points.iter().partition(|p| in_plane(p).0 < 1000.0);
    assert_eq!((inner.len(), outer.len()), (72, 72));
    assert!(inner.iter().all(|p| (in_plane(p).0 - 500.0).abs() < 1e-9));
    assert!(outer.iter().all(|p| (in_plane(p).0 - 1500.0).abs() < 1e-9));
}

#[test]
fn val_gao_sphere_surface_target_lies_on_a_sphere_of_1_km() {
    let points = targets("gao-sphere-surface").unwrap();
    assert_eq!(points.len(), 400);
    let mut octants = [0usize; 8];
    for p in &points {
        let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        assert!((r - 1000.0).abs() < 1e-9, "radius {r} m");
        let o = (p[0] > 0.0) as usize + 2 * (p[1] > 0.0) as usize + 4 * (p[2] > 0.0) as usize;
        octants[o] += 1;
    }
    // Spread over the whole surface: every octant holds about an eighth.
    assert!(
        octants.iter().all(|&k| (40..=60).contains(&k)),
        "{octants:?}"
    );
}

#[test]
fn val_es_e0_target_is_the_rhombus_the_satellites_start_on() {
    let sim = simulation("es-e0");
    let nodes = sim.law().target_formation_hill_m().unwrap();
    // "satellites at rest on their nodes": the scenario lists the start states.
    assert_eq!(nodes.len(), sim.states_hill().len());
    for (node, state) in nodes.iter().zip(sim.states_hill()) {
        assert!(
            (node - state.position_m).norm() < 1e-12,
            "{node} vs {state:?}"
        );
    }
    // Rhombus of side 6 m: nodes 0 and 1 on the x axis, 2 and 3 on the y axis, every side 6 m.
    for (i, j) in [(0, 2), (2, 1), (1, 3), (3, 0)] {
        let side = (nodes[i] - nodes[j]).norm();
        assert!((side - 6.0).abs() < 1e-9, "side {i}-{j}: {side} m");
    }
}

#[test]
fn val_hold_targets_are_the_start_slots_and_other_laws_have_none() {
    let sim = simulation("hold");
    let slots = sim.law().target_formation_hill_m().unwrap();
    assert_eq!(slots.len(), sim.states_hill().len());
    for (slot, state) in slots.iter().zip(sim.states_hill()) {
        assert_eq!(*slot, state.position_m);
    }
    for name in [
        "free-drift",
        "pigeon-baseline",
        "ts-plane-1",
        "gao-disk",
        "gao-line",
    ] {
        assert!(targets(name).is_none(), "{name}");
    }
}
