//! Release-mode reproductions of Gao, Li & Wei 2022 (method page `docs/methods/bifurcating.md` §6) for the
//! shapes outcomes O9–O13, sized for CI: the same code as `satflock validate gao`
//! (`satflock_cli::validate::gao`), on the built-in `gao-*` scenarios, 3 seeds (1–3) where the outcome is
//! seed-dependent, median tested, with our reconstruction's tolerances. The runs of one test go over the cores
//! whole (`run_all`), one single-thread run per core.

use satflock_cli::validate::gao::{
    central_line_spacing_m, filled_shape, line_distance_m, median, ring_assignment, run_all,
    run_seeds, zigzag_critical_spacing_m, Trace, G6_LONG_S,
};

/// Seeds of the CI tests (the full report uses 5).
const SEEDS: [u64; 3] = [1, 2, 3];

fn last(t: &Trace) -> usize {
    t.times_s.len() - 1
}

fn med(traces: &[Trace], f: impl Fn(&Trace) -> f64) -> f64 {
    median(&traces.iter().map(f).collect::<Vec<_>>())
}

/// O9, G6 (concentric double circle 0.5/1.5 km, μ = +0.5 km, from a 2 km cube), run to G6_LONG_S
/// (8000 s), 3 seeds, medians. Our reconstruction's "every satellite within 3 % of a ring" does NOT hold, at
/// 2000 s or at 8000 s: `satflock validate gao` measures 10 % and 56 % of satellites in the band
/// (5 seeds; README, O9). The ring stiffness is k_f·φ''(±μ) = k_f·μ = 1.5 N/m, time constant
/// k_v/(k_f μ) ≈ 1330 s, and satellites near the ridge ρ = 1 km leave it at the same rate. Asserted:
/// * nearest-ring assignment (method page: ≥ 95 % go to the ring nearer their start, ρ < 1 km → inner) at
///   2000 s and at 8000 s: the ridge of the potential is at ρ = r = 1 km, so the sign of ρ − 1 km at
///   the start decides;
/// * the fraction within 3 % of a ring grows from 2000 s to 8000 s (the settling the time constant
///   predicts; the band is not asserted).
#[test]
fn regress_o9_double_circle_nearest_ring_and_radii() {
    let g6 = run_seeds("gao-double-circle", &SEEDS, Some(G6_LONG_S)).unwrap();
    let at = |time: f64, which: usize| {
        med(&g6, |t| {
            let r = ring_assignment(t, 0, t.index_at(time), [500.0, 1500.0], 1000.0, 0.03);
            if which == 0 {
                r.0
            } else {
                r.1
            }
        })
    };
    let rho = |q: &nalgebra::Vector3<f64>| (q.x * q.x + q.z * q.z).sqrt();
    let outer_error = med(&g6, |t| {
        t.positions_gao_m[last(t)]
            .iter()
            .map(rho)
            .filter(|r| *r > 1000.0)
            .map(|r| (r - 1500.0).abs() / 1500.0)
            .fold(0.0, f64::max)
    });
    let inner_count = med(&g6, |t| {
        t.positions_gao_m[last(t)]
            .iter()
            .filter(|q| rho(q) < 1000.0)
            .count() as f64
    });
    let (band_2000, band_long) = (at(2000.0, 0), at(G6_LONG_S, 0));
    let (n2000, nlong) = (at(2000.0, 1), at(G6_LONG_S, 1));
    eprintln!(
        "O9: in the 3 % band {band_2000} (2000 s), {band_long} ({G6_LONG_S} s); nearest {n2000}, \
         {nlong}; outer ring worst error {outer_error}; inner ring {inner_count} satellites"
    );
    assert!(n2000 >= 0.95, "nearest ring at 2000 s: {n2000}");
    assert!(nlong >= 0.95, "nearest ring at {G6_LONG_S} s: {nlong}");
    assert!(band_long > band_2000, "{band_2000} -> {band_long}");
}

/// O10, G1 (line z = 0, k_f = 10 kg/(km s²), μ = −1 km, s = 0.2 km) and G2 (lines z = ±0.5 km) at
/// 2000 s, 3 seeds. The method page expects ≤ 5 m from the target lines; our G1 line is ~30 m thick.
/// Analysis (README, O10): the line is force-free along-track and spreads only by repulsion, so at
/// 2000 s its middle is still compressed (spacing ~13 m, s = 200 m); a straight line is linearly
/// unstable to the alternating zigzag mode when 2 Σ_(odd j) k_c (s/(jδ) − 1) > k_f a²|μ| = 10 N/m,
/// i.e. for spacings δ below ≈ 24 m. The thickness is this buckling, not a bug. Asserted:
/// * out of plane |y| ≤ 5 m on both (the σ well, 2 k_f σ = 200 N/m, is 20× stiffer than the line);
/// * G1's central spacing at 2000 s is below the critical spacing computed from the gains, so the
///   buckling is expected, and the line is then thicker than 5 m (our reconstruction's 5 m is NOT reproduced;
///   if this starts failing because the line became straight, update the README's O10 row);
/// * G1's thickness shrinks from 1000 s to 2000 s as the line lengthens.
#[test]
fn regress_o10_lines_zigzag() {
    let jobs: Vec<_> = SEEDS
        .iter()
        .map(|&s| ("gao-line", s, None))
        .chain(SEEDS.iter().map(|&s| ("gao-double-line", s, None)))
        .collect();
    let all = run_all(&jobs).unwrap();
    let (g1, g2) = all.split_at(SEEDS.len());
    let y_max = |t: &Trace| t.shape_error(last(t)).max_out_of_plane_m;
    assert!(med(g1, y_max) <= 5.0 && med(g2, y_max) <= 5.0);
    let thick_2000 = med(g1, |t| line_distance_m(t, last(t)));
    let thick_1000 = med(g1, |t| line_distance_m(t, t.index_at(1000.0)));
    let gap = med(g1, |t| central_line_spacing_m(t, last(t)));
    let p = &g1[0].parameters[0];
    let critical = zigzag_critical_spacing_m(
        p.k_c_kg_per_s2,
        p.avoidance_radius_m,
        p.k_f_kg_per_m_s2 * p.a * p.a * p.mu_m.abs(),
    );
    let g2_dist = med(g2, |t| line_distance_m(t, last(t)));
    eprintln!(
        "O10: G1 {thick_1000} m (1000 s) -> {thick_2000} m (2000 s), central gap {gap} m, critical \
         {critical} m; G2 {g2_dist} m"
    );
    // 23.9 m from the bisection of the closed-form sum; ±0.5 m guards the formula, not a fit.
    assert!(
        (critical - 24.0).abs() <= 0.5,
        "critical spacing {critical} m"
    );
    assert!(
        gap < critical,
        "central spacing {gap} m vs critical {critical} m"
    );
    assert!(
        thick_2000 > 5.0,
        "G1 thickness {thick_2000} m: the line is straight now"
    );
    assert!(thick_2000 < thick_1000, "{thick_1000} m -> {thick_2000} m");
}

/// O11: G5 circle r = 5 km (s = r = 5 km): largest radial error and |y| at 2000 s ≤ 3 % of r
/// (method page O11), median of 3 seeds.
#[test]
fn regress_o11_large_circle() {
    let g5 = run_seeds("gao-circle-large", &SEEDS, None).unwrap();
    let rel = med(&g5, |t| {
        let e = t.shape_error(last(t));
        e.max_residual_m.unwrap().max(e.max_out_of_plane_m) / e.size_m.unwrap()
    });
    eprintln!("O11: {rel}");
    assert!(rel <= 0.03, "G5 radial error {rel}");
}

/// O12 (Fig. 19): the sphere surface and the 1/0.6 ellipse within 3 % of their size at 2000 s (largest
/// first-order distance to the level set, and |y| for the 2-D ellipse), and the filled disk formed: the
/// level set enclosing all satellites has the commanded aspect (RMS extents within 10 %, finite-N
/// sampling of 50 points), is filled (no empty annulus wider than 0.4 ρ_max: our 1+8+16+25
/// disk lattice has 1/3, one ring ≈ 1, two rings at ρ_max/3 and ρ_max 0.67) and in the orbital plane
/// (|y| ≤ 3 %). Median of 3 seeds. (Not "median ρ/ρ_max ≤ 0.85": this law piles satellites on the
/// boundary, our filled disk gives 0.87–0.91; README, O12.)
#[test]
fn regress_o12_fig19_shapes() {
    let names = ["gao-sphere-surface", "gao-ellipse", "gao-disk"];
    let jobs: Vec<_> = names
        .iter()
        .flat_map(|&n| SEEDS.iter().map(move |&s| (n, s, None)))
        .collect();
    let all = run_all(&jobs).unwrap();
    for (i, name) in names.iter().enumerate() {
        let runs = &all[i * SEEDS.len()..(i + 1) * SEEDS.len()];
        if *name == "gao-disk" {
            let f: Vec<_> = runs.iter().map(|t| filled_shape(t, last(t))).collect();
            eprintln!("O12 {name}: {f:?}");
            let fill = median(&f.iter().map(|x| x.largest_radial_gap).collect::<Vec<_>>());
            let aspect = median(&f.iter().map(|x| x.aspect_error).collect::<Vec<_>>());
            let plane = median(&f.iter().map(|x| x.out_of_plane).collect::<Vec<_>>());
            assert!(
                fill <= 0.4 && aspect <= 0.10 && plane <= 0.03,
                "{name}: {f:?}"
            );
        } else {
            let rel = med(runs, |t| {
                let e = t.shape_error(last(t));
                e.max_residual_m.unwrap().max(e.max_out_of_plane_m) / e.size_m.unwrap()
            });
            eprintln!("O12 {name}: {rel}");
            assert!(rel <= 0.03, "{name}: {rel}");
        }
    }
}
