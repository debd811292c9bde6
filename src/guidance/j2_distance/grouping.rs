//! Neighbour selection of the `j2-distance` law: the multi-leader grouping of Takahashi & Sakai
//! (Algorithm 1) on a 2-D Delaunay triangulation (DT) of the swarm in the normalised swarm frame {Ŝ}.
//!
//! **This step is centralised**: it needs every satellite's position and the pair parameters of every
//! candidate pair at once (method page `docs/methods/j2-distance.md` §9, §13). The law runs it as the engine's
//! periodic centralised step ([`crate::swarm::Centralised::centralised_update`]); the control itself
//! stays decentralised (each satellite uses only its neighbours' relative states).
//!
//! Steps (method page §9.2–9.3):
//! 1. P_j = rows 2–3 of C^{Ŝ/O} r_j (the swarm-plane layout, §5.6);
//! 2. DT of {P_j} (crate `delaunator`);
//! 3. outer-edge pruning \[reconstruction, §9.3\]: drop DT edges longer than κ·2r_xyd, then re-add the
//!    dropped ones in ascending length whenever they join two components;
//! 4. every satellite is a leader: its group is itself plus up to n̄_f DT neighbours within r_s
//!    (Ŝ-plane distance), most urgent first (ascending T̂_conn of the pair, ties by distance);
//! 5. the edge set is the union over groups of the member pairs that are (pruned) DT edges.
//!
//! Since every satellite leads, the union does not depend on the leader order (the DT degree ordering of
//! Algorithm 1 line 4 is therefore not needed). The bounds n̄_{l←f} and "no shared edge" are not
//! enforced by the printed algorithm, nor here (method page §9.2, §12).
//!
//! [`preserve_connectivity`] is an opt-in extension beyond the paper (method page §9.6): after
//! Algorithm 1 it adds back, shortest first, the links that rejoin pieces of the communication graph the
//! grouping split.

use delaunator::{triangulate, Point};

/// One candidate satellite for grouping, in the swarm plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    /// Satellite index in the swarm.
    pub id: usize,
    /// (y, z) components in the normalised swarm frame {Ŝ} \[m\].
    pub plane_m: [f64; 2],
}

/// Settings of the grouping (method page §9.2–9.3, §10.1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GroupingSettings {
    /// Maximum followers per leader n̄_f \[-\].
    pub followers_max: usize,
    /// Controllable range r_s \[m\], compared with the Ŝ-plane distance.
    pub range_m: f64,
    /// Pruning threshold κ·2r_xyd \[m\] on Ŝ-plane DT edge lengths; `None` disables pruning.
    pub prune_length_m: Option<f64>,
}

/// The result of one grouping.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Grouping {
    /// Undirected edges (j, k) with j < k, sorted, as swarm indices.
    pub edges: Vec<(usize, usize)>,
    /// Number of (pruned) DT edges considered.
    pub dt_edges: usize,
}

/// Union–find over `n` items (path halving), for the connectivity repair and component counts.
pub(crate) struct Components {
    parent: Vec<usize>,
}

impl Components {
    pub(crate) fn new(n: usize) -> Self {
        Self {
            parent: (0..n).collect(),
        }
    }

    pub(crate) fn find(&mut self, mut i: usize) -> usize {
        while self.parent[i] != i {
            self.parent[i] = self.parent[self.parent[i]];
            i = self.parent[i];
        }
        i
    }

    /// Joins the sets of `a` and `b`; `true` if they were different.
    pub(crate) fn union(&mut self, a: usize, b: usize) -> bool {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra == rb {
            return false;
        }
        self.parent[ra.max(rb)] = ra.min(rb);
        true
    }
}

fn distance(a: &[f64; 2], b: &[f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Edges (local indices, i < j, sorted) of the DT of `points`. Degenerate sets (fewer than three points,
/// or all collinear) get the chain of consecutive points in lexicographic order, the DT's limit.
fn delaunay_edges(points: &[[f64; 2]]) -> Vec<(usize, usize)> {
    let pts: Vec<Point> = points.iter().map(|p| Point { x: p[0], y: p[1] }).collect();
    let t = triangulate(&pts);
    let mut edges: Vec<(usize, usize)> = if t.triangles.is_empty() {
        let mut order: Vec<usize> = (0..points.len()).collect();
        order.sort_by(|&a, &b| {
            points[a][0]
                .total_cmp(&points[b][0])
                .then(points[a][1].total_cmp(&points[b][1]))
        });
        order
            .windows(2)
            .map(|w| (w[0].min(w[1]), w[0].max(w[1])))
            .collect()
    } else {
        t.triangles
            .chunks_exact(3)
            .flat_map(|tri| [(tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])])
            .map(|(a, b)| (a.min(b), a.max(b)))
            .collect()
    };
    edges.sort_unstable();
    edges.dedup();
    edges
}

/// Outer-edge pruning with connectivity repair (method page §9.3): keeps edges no longer than `limit_m`, then
/// re-adds the others in ascending length when they join two components. `edges` are local indices.
fn prune(points: &[[f64; 2]], edges: Vec<(usize, usize)>, limit_m: f64) -> Vec<(usize, usize)> {
    let mut components = Components::new(points.len());
    let (mut kept, mut dropped): (Vec<_>, Vec<_>) = edges
        .into_iter()
        .partition(|&(a, b)| distance(&points[a], &points[b]) <= limit_m);
    for &(a, b) in &kept {
        components.union(a, b);
    }
    dropped.sort_by(|&(a, b), &(c, d)| {
        distance(&points[a], &points[b])
            .total_cmp(&distance(&points[c], &points[d]))
            .then((a, b).cmp(&(c, d)))
    });
    for (a, b) in dropped {
        if components.union(a, b) {
            kept.push((a, b));
        }
    }
    kept.sort_unstable();
    kept
}

/// Algorithm 1 (method page §9.2) with the pruning of §9.3. `connectable_time_s(a, b)` is T̂_conn \[s\] of the pair
/// of nodes `a`, `b` (local indices into `nodes`). Deterministic: ties are broken by distance, then index.
pub fn group(
    nodes: &[Node],
    settings: &GroupingSettings,
    connectable_time_s: impl Fn(usize, usize) -> f64,
) -> Grouping {
    let points: Vec<[f64; 2]> = nodes.iter().map(|n| n.plane_m).collect();
    let mut dt = delaunay_edges(&points);
    if let Some(limit) = settings.prune_length_m {
        dt = prune(&points, dt, limit);
    }
    let n = nodes.len();
    let mut adjacency: Vec<Vec<usize>> = vec![Vec::new(); n];
    for &(a, b) in &dt {
        adjacency[a].push(b);
        adjacency[b].push(a);
    }
    for list in &mut adjacency {
        list.sort_unstable();
    }
    let is_dt = |a: usize, b: usize| adjacency[a].binary_search(&b).is_ok();
    let mut edges = Vec::new();
    let mut group = Vec::with_capacity(settings.followers_max + 1);
    for leader in 0..n {
        // Candidates: only DT neighbours can pass the A_DT test, so sorting them is Algorithm 1's sort
        // restricted to the satellites it can accept.
        let mut candidates: Vec<(f64, f64, usize)> = adjacency[leader]
            .iter()
            .map(|&f| {
                (
                    connectable_time_s(leader, f),
                    distance(&points[leader], &points[f]),
                    f,
                )
            })
            .filter(|c| c.1 <= settings.range_m)
            .collect();
        candidates.sort_by(|a, b| {
            a.0.total_cmp(&b.0)
                .then(a.1.total_cmp(&b.1))
                .then(a.2.cmp(&b.2))
        });
        group.clear();
        group.push(leader);
        group.extend(candidates.iter().take(settings.followers_max).map(|c| c.2));
        for (i, &a) in group.iter().enumerate() {
            for &b in &group[i + 1..] {
                if is_dt(a, b) {
                    let (p, q) = (nodes[a].id, nodes[b].id);
                    edges.push((p.min(q), p.max(q)));
                }
            }
        }
    }
    edges.sort_unstable();
    edges.dedup();
    Grouping {
        edges,
        dt_edges: dt.len(),
    }
}

/// Connectivity-preserving grouping (method page §9.6; an extension beyond the paper, off by default in
/// the law). `links` are the pairs that can communicate (local indices into `nodes`, any order). Every
/// link whose two ends lie in different components of `grouping.edges` is a candidate; candidates are
/// taken in ascending Ŝ-plane distance (ties by the pair's satellite indices) and each one that still
/// joins two components is added (Kruskal), so that afterwards no component of the link graph is split
/// by the grouping: the grouping graph has at most as many components as the link graph. Returns the
/// edges added (swarm indices, j < k, in the order added; empty if the grouping split nothing) and
/// keeps `grouping.edges` sorted. Links outside `nodes` and edges between satellites not in `nodes`
/// are ignored.
///
/// When every pair of nodes is a link, each added edge is the shortest pair between two components, an
/// edge of the Ŝ-plane Euclidean minimum spanning tree and therefore of the Delaunay triangulation: it
/// crosses no edge of the grouping.
pub fn preserve_connectivity(
    nodes: &[Node],
    links: &[(usize, usize)],
    grouping: &mut Grouping,
) -> Vec<(usize, usize)> {
    let local: std::collections::HashMap<usize, usize> =
        nodes.iter().enumerate().map(|(k, n)| (n.id, k)).collect();
    let mut components = Components::new(nodes.len());
    for (a, b) in &grouping.edges {
        if let (Some(&i), Some(&j)) = (local.get(a), local.get(b)) {
            components.union(i, j);
        }
    }
    let mut candidates: Vec<_> = links
        .iter()
        .filter(|&&(a, b)| a < nodes.len() && b < nodes.len())
        .filter(|&&(a, b)| components.find(a) != components.find(b))
        .map(|&(a, b)| {
            let (p, q) = (nodes[a].id, nodes[b].id);
            (
                distance(&nodes[a].plane_m, &nodes[b].plane_m),
                (p.min(q), p.max(q)),
                (a, b),
            )
        })
        .collect();
    candidates.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    let added: Vec<(usize, usize)> = candidates
        .into_iter()
        .filter(|&(_, _, (a, b))| components.union(a, b))
        .map(|(_, edge, _)| edge)
        .collect();
    if !added.is_empty() {
        grouping.edges.extend(&added);
        grouping.edges.sort_unstable();
    }
    added
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lattice(rows: usize, cols: usize, spacing: f64) -> Vec<Node> {
        // A triangular lattice: every DT edge has length `spacing`.
        let mut nodes = Vec::new();
        for r in 0..rows {
            for c in 0..cols {
                let shift = if r % 2 == 1 { 0.5 } else { 0.0 };
                nodes.push(Node {
                    id: nodes.len(),
                    plane_m: [
                        spacing * (c as f64 + shift),
                        spacing * r as f64 * 3f64.sqrt() / 2.0,
                    ],
                });
            }
        }
        nodes
    }

    #[test]
    fn val_triangular_lattice_keeps_every_lattice_edge() {
        // On a triangular lattice the DT is the lattice (interior degree 6); with n̄_f = 6 every leader
        // takes all its DT neighbours, so the edges are exactly the lattice's unit-length pairs.
        let nodes = lattice(4, 5, 0.5);
        let settings = GroupingSettings {
            followers_max: 6,
            range_m: 1.0,
            prune_length_m: Some(0.75),
        };
        let g = group(&nodes, &settings, |_, _| f64::INFINITY);
        let mut expected = Vec::new();
        for a in 0..nodes.len() {
            for b in a + 1..nodes.len() {
                if (distance(&nodes[a].plane_m, &nodes[b].plane_m) - 0.5).abs() < 1e-9 {
                    expected.push((a, b));
                }
            }
        }
        assert_eq!(g.edges, expected);
    }

    #[test]
    fn val_pruning_repairs_connectivity() {
        // Two clusters 3 m apart: the long DT edges are pruned except the shortest bridge.
        let mut nodes = lattice(2, 3, 0.5);
        let far: Vec<Node> = lattice(2, 3, 0.5)
            .into_iter()
            .map(|n| Node {
                id: n.id + 6,
                plane_m: [n.plane_m[0] + 3.0, n.plane_m[1]],
            })
            .collect();
        nodes.extend(far);
        let settings = GroupingSettings {
            followers_max: 5,
            range_m: 10.0,
            prune_length_m: Some(0.75),
        };
        let g = group(&nodes, &settings, |_, _| f64::INFINITY);
        let mut c = Components::new(nodes.len());
        for &(a, b) in &g.edges {
            c.union(a, b);
        }
        let roots: std::collections::BTreeSet<usize> =
            (0..nodes.len()).map(|i| c.find(i)).collect();
        assert_eq!(roots.len(), 1);
        let long = g
            .edges
            .iter()
            .filter(|&&(a, b)| distance(&nodes[a].plane_m, &nodes[b].plane_m) > 0.75)
            .count();
        assert_eq!(long, 1, "exactly one bridge: {:?}", g.edges);
    }

    fn count_components(n: usize, edges: &[(usize, usize)]) -> usize {
        let mut c = Components::new(n);
        for &(a, b) in edges {
            c.union(a, b);
        }
        (0..n)
            .map(|i| c.find(i))
            .collect::<std::collections::BTreeSet<_>>()
            .len()
    }

    fn all_pairs(n: usize) -> Vec<(usize, usize)> {
        (0..n)
            .flat_map(|a| (a + 1..n).map(move |b| (a, b)))
            .collect()
    }

    #[test]
    fn val_preserving_grouping_keeps_the_only_bridge() {
        // Two 2×3 lattices (spacing 0.5 m) 3 m apart; the far one's ids skip 6, as if satellite 6 had
        // been removed. By hand: the nearest cross pair is local 5 (1.25, 0.433) – local 6 (3, 0), at
        // √(1.75² + 0.433²) = 1.803 m; the next ones (2–6, 5–9) are 2 m. Pruning keeps that bridge in
        // the DT (repair), but it is longer than r_s = 1 m, so Algorithm 1 drops it.
        let mut nodes = lattice(2, 3, 0.5);
        nodes.extend(lattice(2, 3, 0.5).into_iter().map(|n| Node {
            id: n.id + 7,
            plane_m: [n.plane_m[0] + 3.0, n.plane_m[1]],
        }));
        let settings = GroupingSettings {
            followers_max: 5,
            range_m: 1.0,
            prune_length_m: Some(0.75),
        };
        let paper = group(&nodes, &settings, |_, _| f64::INFINITY);
        let local = |id: usize| if id < 6 { id } else { id - 1 };
        let local_edges = |g: &Grouping| -> Vec<(usize, usize)> {
            g.edges.iter().map(|&(a, b)| (local(a), local(b))).collect()
        };
        assert_eq!(count_components(12, &local_edges(&paper)), 2);
        // Every pair can communicate: the repair adds exactly the bridge (ids 5 and 7) and reconnects.
        let mut kept = paper.clone();
        let added = preserve_connectivity(&nodes, &all_pairs(12), &mut kept);
        assert_eq!(added, vec![(5, 7)]);
        assert_eq!(count_components(12, &local_edges(&kept)), 1);
        let mut expected = paper.edges.clone();
        expected.push((5, 7));
        expected.sort_unstable();
        assert_eq!(kept.edges, expected);
        // Deterministic: the order of the links does not matter.
        let mut reversed = paper.clone();
        let mut links = all_pairs(12);
        links.reverse();
        assert_eq!(preserve_connectivity(&nodes, &links, &mut reversed), added);
        assert_eq!(reversed, kept);
        // No link between the clusters: the link graph has two components too, nothing is added.
        let within: Vec<(usize, usize)> = all_pairs(12)
            .into_iter()
            .filter(|&(a, b)| (a < 6) == (b < 6))
            .collect();
        let mut unchanged = paper.clone();
        assert!(preserve_connectivity(&nodes, &within, &mut unchanged).is_empty());
        assert_eq!(unchanged, paper);
    }

    #[test]
    fn val_preserving_grouping_breaks_ties_by_index() {
        // A 1 m × 3 m rectangle: Algorithm 1 keeps the two 1 m sides (r_s = 1 m); the two 3 m sides tie
        // exactly, and the one with the smaller indices (0–2) rejoins the halves; 1–3 then joins nothing.
        let nodes: Vec<Node> = [[0.0, 0.0], [0.0, 1.0], [3.0, 0.0], [3.0, 1.0]]
            .into_iter()
            .enumerate()
            .map(|(id, plane_m)| Node { id, plane_m })
            .collect();
        let settings = GroupingSettings {
            followers_max: 5,
            range_m: 1.0,
            prune_length_m: None,
        };
        let mut g = group(&nodes, &settings, |_, _| f64::INFINITY);
        assert_eq!(g.edges, vec![(0, 1), (2, 3)]);
        let mut links = all_pairs(4);
        links.reverse();
        // A link outside the nodes is ignored.
        links.push((1, 4));
        assert_eq!(preserve_connectivity(&nodes, &links, &mut g), vec![(0, 2)]);
        assert_eq!(g.edges, vec![(0, 1), (0, 2), (2, 3)]);
    }

    #[test]
    fn regress_urgent_followers_first() {
        // A hub with 6 DT neighbours and n̄_f = 1 keeps, among the hub's own group, the most urgent
        // neighbour (smallest T̂_conn); other edges come from the other leaders' groups.
        let nodes = lattice(3, 3, 0.5);
        let hub = 4;
        let urgent = 5;
        let settings = GroupingSettings {
            followers_max: 1,
            range_m: 1.0,
            prune_length_m: None,
        };
        let t = |a: usize, b: usize| {
            if (a == hub && b == urgent) || (a == urgent && b == hub) {
                10.0
            } else {
                1e6
            }
        };
        let g = group(&nodes, &settings, t);
        assert!(g.edges.contains(&(hub, urgent)));
    }
}
