//! The initial egalitarian link graph of the `pigeon` law and the load-time warning when it is not
//! connected.
//!
//! At the first tick no pair is linked, so (paper Eq. 3 at t_0) a pair links when its distance in the
//! law's pigeon plane — the 2-D distance in (z, y), the distance every rule of the law uses — is
//! ≤ R_c^1 − R_L^1. A satellite left without a link feels no formation force: a dominant one is pulled
//! by the target alone, an ordinary one by nothing (velocity alignment with hierarchical neighbours
//! within R_c^2 aside) until it comes within the link radius of another. With the paper's Table I at
//! R_c^1 = 120 m, R_L^1 = 10 m, satellite 0 (115.3 m from its nearest neighbour) started alone, flew off
//! at the 5 m/s² cap and crashed back through the flock after about 90 s (`docs/methods/pigeon.md`).
//!
//! The engine reports a neighbour only within the 3-D sensing range (≥ R_c^2 > R_c^1 − R_L^1); a pair
//! within the link radius in the plane but beyond the sensing range in 3-D (a radial offset of tens of
//! metres) links only once the radial PD has brought x towards zero, within seconds, so the check uses
//! the law's 2-D rule alone. Navigation noise is not included (the check uses the true initial states).

use std::collections::HashMap;

use nalgebra::{Vector2, Vector3};

use super::{pigeon_plane, PigeonParameters};

/// The connected components of the initial egalitarian link graph.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct InitialLinks {
    /// The link radius R_c^1 − R_L^1 \[m\].
    pub radius_m: f64,
    /// The components, each a sorted list of satellite indices; largest first, ties by lowest index.
    pub components: Vec<Vec<usize>>,
}

/// Union–find over satellite indices (path halving, union by size).
struct Sets {
    parent: Vec<usize>,
    size: Vec<usize>,
}

impl Sets {
    fn new(n: usize) -> Self {
        Self {
            parent: (0..n).collect(),
            size: vec![1; n],
        }
    }

    fn find(&mut self, mut i: usize) -> usize {
        while self.parent[i] != i {
            self.parent[i] = self.parent[self.parent[i]];
            i = self.parent[i];
        }
        i
    }

    fn union(&mut self, a: usize, b: usize) {
        let (mut a, mut b) = (self.find(a), self.find(b));
        if a == b {
            return;
        }
        if self.size[a] < self.size[b] {
            std::mem::swap(&mut a, &mut b);
        }
        self.parent[b] = a;
        self.size[a] += self.size[b];
    }
}

/// The components of the initial egalitarian link graph of satellites at `positions_hill_m` (Hill
/// frame \[m\], index = satellite) under `parameters`: pairs at pigeon-plane distance
/// ≤ R_c^1 − R_L^1 are linked.
///
/// Linear in the satellite count for a spread swarm: the plane is cut into square cells of side
/// (R_c^1 − R_L^1)/√2 (shrunk by 1e-9 relative, so rounding never links a pair the law would not), in
/// which every pair is linked; only cells up to two apart are compared, and a pair of cells only until
/// one link joins them.
pub(crate) fn initial_link_components(
    positions_hill_m: &[Vector3<f64>],
    parameters: &PigeonParameters,
) -> InitialLinks {
    let radius_m = parameters.egalitarian_range_m - parameters.link_delay_m;
    let plane: Vec<Vector2<f64>> = positions_hill_m.iter().map(pigeon_plane).collect();
    let n = plane.len();
    let mut sets = Sets::new(n);
    let cell_m = radius_m / std::f64::consts::SQRT_2 * (1.0 - 1e-9);
    let mut cells: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for (i, p) in plane.iter().enumerate() {
        // Positions are finite (checked when the scenario is prepared); `as` saturates anyway.
        let key = ((p.x / cell_m).floor() as i64, (p.y / cell_m).floor() as i64);
        cells.entry(key).or_default().push(i);
    }
    // Within a cell |dz|, |dy| < cell: the distance is below the radius.
    for members in cells.values() {
        for &j in &members[1..] {
            sets.union(members[0], j);
        }
    }
    // Cells three apart on an axis are more than 2 cell = 1.41 radius apart: never linked.
    let mut keys: Vec<(i64, i64)> = cells.keys().copied().collect();
    keys.sort_unstable();
    for &(a, b) in &keys {
        let here = &cells[&(a, b)];
        for da in 0..=2i64 {
            for db in -2..=2i64 {
                if da == 0 && db <= 0 {
                    continue;
                }
                let Some(there) = cells.get(&(a.saturating_add(da), b.saturating_add(db))) else {
                    continue;
                };
                if sets.find(here[0]) == sets.find(there[0]) {
                    continue;
                }
                'pairs: for &i in here {
                    for &j in there {
                        if (plane[i] - plane[j]).norm() <= radius_m {
                            sets.union(i, j);
                            break 'pairs;
                        }
                    }
                }
            }
        }
    }
    let mut by_root: HashMap<usize, Vec<usize>> = HashMap::new();
    for i in 0..n {
        by_root.entry(sets.find(i)).or_default().push(i);
    }
    // Indices were pushed in increasing order, so each component is sorted.
    let mut components: Vec<Vec<usize>> = by_root.into_values().collect();
    components.sort_unstable_by(|x, y| y.len().cmp(&x.len()).then(x[0].cmp(&y[0])));
    InitialLinks {
        radius_m,
        components,
    }
}

/// The nearest other satellite to satellite `i` in the pigeon plane and its distance \[m\] (`None`
/// for a swarm of one). O(N).
pub(crate) fn nearest_in_plane(
    positions_hill_m: &[Vector3<f64>],
    i: usize,
) -> Option<(usize, f64)> {
    let own = pigeon_plane(&positions_hill_m[i]);
    positions_hill_m
        .iter()
        .enumerate()
        .filter(|(j, _)| *j != i)
        .map(|(j, p)| (j, (pigeon_plane(p) - own).norm()))
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// A length \[m\] for a message: one decimal, without a trailing `.0`.
fn metres(v: f64) -> String {
    let text = format!("{v:.1}");
    match text.strip_suffix(".0") {
        Some(whole) => whole.to_string(),
        None => text,
    }
}

/// "a, b and c" of a list.
fn and_list(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

/// The load-time warning when the initial egalitarian link graph of satellites at `positions_hill_m`
/// (Hill frame \[m\]) is not connected under `parameters`; `None` when it is (or for fewer than two
/// satellites). It names the scenario keys (`law.egalitarian_range_m`, `law.link_delay_m`), the link
/// radius, the number of components and their sizes, and the satellites left alone (up to three) with
/// their nearest neighbour's distance, e.g. for the paper's Table I at R_c^1 = 120 m:
///
/// `law.egalitarian_range_m − law.link_delay_m = 110 m: the initial egalitarian link graph is not
/// connected (2 components of 9 and 1 satellites; satellite 0 has no neighbour within 110 m, nearest
/// 115.3 m): unlinked satellites are pulled only by the target (if dominant), and separate groups feel
/// no formation force from each other`
pub(crate) fn initial_link_warning(
    positions_hill_m: &[Vector3<f64>],
    parameters: &PigeonParameters,
) -> Option<String> {
    let links = initial_link_components(positions_hill_m, parameters);
    let count = links.components.len();
    if count <= 1 {
        return None;
    }
    let radius = metres(links.radius_m);
    const LISTED: usize = 5;
    let sizes = if count <= LISTED {
        let sizes: Vec<String> = links
            .components
            .iter()
            .map(|c| c.len().to_string())
            .collect();
        format!("{count} components of {} satellites", and_list(&sizes))
    } else {
        format!(
            "{count} components, the largest of {} satellites",
            links.components[0].len()
        )
    };
    let alone: Vec<usize> = links
        .components
        .iter()
        .filter(|c| c.len() == 1)
        .map(|c| c[0])
        .collect();
    let nearest =
        |i: usize| nearest_in_plane(positions_hill_m, i).map_or(String::new(), |(_, d)| metres(d));
    let detail = match alone.as_slice() {
        [] => {
            let smallest = links.components.last().expect("two or more components");
            let ids: Vec<String> = smallest
                .iter()
                .take(LISTED)
                .map(|i| i.to_string())
                .collect();
            let more = smallest.len().saturating_sub(LISTED);
            format!(
                "the smallest holds satellites {}{}",
                ids.join(", "),
                if more > 0 {
                    format!(" and {more} more")
                } else {
                    String::new()
                }
            )
        }
        [one] => format!(
            "satellite {one} has no neighbour within {radius} m, nearest {} m",
            nearest(*one)
        ),
        many => {
            const NAMED: usize = 3;
            let mut named: Vec<String> = many
                .iter()
                .take(NAMED)
                .map(|&i| format!("{i} (nearest {} m)", nearest(i)))
                .collect();
            if many.len() > NAMED {
                named.push(format!("{} more", many.len() - NAMED));
            }
            format!(
                "satellites {} have no neighbour within {radius} m",
                and_list(&named)
            )
        }
    };
    Some(format!(
        "law.egalitarian_range_m − law.link_delay_m = {radius} m: the initial egalitarian link graph \
         is not connected ({sizes}; {detail}): unlinked satellites are pulled only by the target (if \
         dominant), and separate groups feel no formation force from each other"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params(range_m: f64, delay_m: f64) -> PigeonParameters {
        PigeonParameters {
            egalitarian_range_m: range_m,
            link_delay_m: delay_m,
            ..PigeonParameters::default()
        }
    }

    /// Brute-force components (every pair), the reference of the grid version.
    fn brute(positions: &[Vector3<f64>], radius_m: f64) -> Vec<Vec<usize>> {
        let n = positions.len();
        let mut sets = Sets::new(n);
        for i in 0..n {
            for j in i + 1..n {
                let d = (pigeon_plane(&positions[i]) - pigeon_plane(&positions[j])).norm();
                if d <= radius_m {
                    sets.union(i, j);
                }
            }
        }
        let mut by_root: HashMap<usize, Vec<usize>> = HashMap::new();
        for i in 0..n {
            by_root.entry(sets.find(i)).or_default().push(i);
        }
        let mut c: Vec<Vec<usize>> = by_root.into_values().collect();
        c.sort_unstable_by(|x, y| y.len().cmp(&x.len()).then(x[0].cmp(&y[0])));
        c
    }

    #[test]
    fn grid_components_equal_brute_force_on_random_swarms() {
        use crate::random::{Purpose, RandomStream};
        for seed in 0..20u64 {
            let mut rng = RandomStream::new(seed, Purpose::InitialStates, 0, 0);
            let n = 10 + (seed as usize) * 15;
            let positions: Vec<Vector3<f64>> = (0..n)
                .map(|_| {
                    Vector3::new(
                        300.0 * (rng.uniform() - 0.5),
                        800.0 * (rng.uniform() - 0.5),
                        800.0 * (rng.uniform() - 0.5),
                    )
                })
                .collect();
            for radius in [10.0, 40.0, 90.0, 250.0] {
                let got = initial_link_components(&positions, &params(radius + 10.0, 10.0));
                assert_eq!(
                    got.components,
                    brute(&positions, radius),
                    "seed {seed}, {radius} m"
                );
            }
        }
    }

    #[test]
    fn a_pair_links_exactly_at_the_radius_and_x_does_not_count() {
        // 3-4-5 triangle in (z, y): distance exactly 110 m; a 500 m radial offset is ignored.
        let a = Vector3::new(0.0, 0.0, 0.0);
        let b = Vector3::new(500.0, 88.0, 66.0);
        let p = params(120.0, 10.0);
        assert_eq!(
            initial_link_components(&[a, b], &p).components,
            vec![vec![0, 1]]
        );
        assert!(initial_link_warning(&[a, b], &p).is_none());
        let c = Vector3::new(0.0, 88.0 * 1.001, 66.0 * 1.001);
        let w = initial_link_warning(&[a, c], &p).unwrap();
        assert!(w.contains("2 components of 1 and 1 satellites"), "{w}");
        assert!(
            w.contains("satellites 0 (nearest 110.1 m) and 1 (nearest 110.1 m)"),
            "{w}"
        );
        assert!(initial_link_warning(&[a], &p).is_none());
        assert!(initial_link_warning(&[], &p).is_none());
    }

    #[test]
    fn groups_without_a_lone_satellite_name_the_smallest() {
        let p = params(60.0, 10.0);
        let positions: Vec<Vector3<f64>> = [0.0, 40.0, 80.0, 300.0, 340.0]
            .iter()
            .map(|y| Vector3::new(0.0, *y, 0.0))
            .collect();
        let w = initial_link_warning(&positions, &p).unwrap();
        assert!(
            w.starts_with("law.egalitarian_range_m − law.link_delay_m = 50 m:"),
            "{w}"
        );
        assert!(
            w.contains("(2 components of 3 and 2 satellites; the smallest holds satellites 3, 4)"),
            "{w}"
        );
    }
}
