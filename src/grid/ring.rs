//! The ring neighbourhood: satellites ordered by their phase along the orbit, each sensing the `k`
//! nearest ahead and the `k` nearest behind in that order, however far away they are (inter-satellite
//! links over an orbit-wide flock, where a range ball would hold everyone or no one).
//!
//! Built once per evaluation in O(N log N) (one sort of the included satellites by phase); a query
//! visits at most 2k satellites in O(k). Phases are any angles in radians (the engine gives
//! `atan2(y, R + x)` of the Hill position, R the reference orbit's radius); the order is cyclic, so
//! the satellite behind the first is the last. Ties of phase are broken by rank (the satellite's id),
//! so the order depends only on the phases and ids, never on the storage order or on threads.

/// The satellites in phase order and each one's place in it. Allocated once and reused across builds.
#[derive(Clone, Debug, Default)]
pub struct RingOrder {
    /// Included satellites (indices into the built slices), by ascending (phase, rank).
    order: Vec<u32>,
    /// Each index's place in `order` (`u32::MAX`: not included).
    place: Vec<u32>,
    /// Neighbours sensed on each side.
    each_side: usize,
}

impl RingOrder {
    /// An empty ring: nobody has neighbours until [`RingOrder::build`].
    pub fn new() -> Self {
        Self::default()
    }

    /// Orders the satellites `i` with `include(i)` by `phases_rad[i]` (ties by `ranks[i]`, or by `i`
    /// without ranks), each to sense `each_side` neighbours ahead and as many behind. A non-finite
    /// phase sorts last (`f64::total_cmp`).
    pub fn build(
        &mut self,
        phases_rad: &[f64],
        ranks: Option<&[u32]>,
        include: impl Fn(usize) -> bool,
        each_side: usize,
    ) {
        let n = phases_rad.len();
        self.each_side = each_side;
        self.order.clear();
        self.order
            .extend((0..n as u32).filter(|&i| include(i as usize)));
        let rank = |i: u32| ranks.map_or(i, |r| r[i as usize]);
        self.order.sort_unstable_by(|&a, &b| {
            phases_rad[a as usize]
                .total_cmp(&phases_rad[b as usize])
                .then(rank(a).cmp(&rank(b)))
        });
        self.place.clear();
        self.place.resize(n, u32::MAX);
        for (k, &i) in self.order.iter().enumerate() {
            self.place[i as usize] = k as u32;
        }
    }

    /// Neighbours sensed on each side.
    pub fn each_side(&self) -> usize {
        self.each_side
    }

    /// Visits satellite `i`'s ring neighbours: the 1st, 2nd, … `k`-th ahead (increasing phase), then
    /// the 1st … `k`-th behind, each other satellite at most once (a ring of fewer than 2k + 1 visits
    /// everyone else once). Nothing for a satellite that was not included, or out of range.
    pub fn for_each_neighbour(&self, i: usize, mut visit: impl FnMut(usize)) {
        let Some(&place) = self.place.get(i) else {
            return;
        };
        if place == u32::MAX {
            return;
        }
        let m = self.order.len();
        let others = m - 1;
        let ahead = self.each_side.min(others);
        let behind = self.each_side.min(others - ahead);
        let place = place as usize;
        for step in 1..=ahead {
            visit(self.order[(place + step) % m] as usize);
        }
        for step in 1..=behind {
            visit(self.order[(place + m - step) % m] as usize);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute force: the included satellites sorted by (phase, rank), then for i the `k` next and the
    /// `k` previous places cyclically, without repeats and without i.
    fn brute(phases: &[f64], ranks: &[u32], include: &[bool], k: usize, i: usize) -> Vec<usize> {
        let mut order: Vec<usize> = (0..phases.len()).filter(|&j| include[j]).collect();
        order.sort_by(|&a, &b| {
            phases[a]
                .total_cmp(&phases[b])
                .then(ranks[a].cmp(&ranks[b]))
        });
        let Some(p) = order.iter().position(|&j| j == i) else {
            return Vec::new();
        };
        let m = order.len() as isize;
        let mut out = Vec::new();
        for s in (1..=k as isize).chain((1..=k as isize).map(|s| -s)) {
            let j = order[((p as isize + s).rem_euclid(m)) as usize];
            if j != i && !out.contains(&j) {
                out.push(j);
            }
        }
        out
    }

    #[test]
    fn val_ring_neighbours_match_a_brute_force_order() {
        // 40 satellites on a ring with repeated phases (ties broken by rank), some excluded.
        let n = 40;
        let phases: Vec<f64> = (0..n)
            .map(|i| ((i * 7919) % 23) as f64 * 0.27 - 3.0)
            .collect();
        let ranks: Vec<u32> = (0..n as u32).map(|i| (i * 13) % n as u32).collect();
        let include: Vec<bool> = (0..n).map(|i| i % 9 != 4).collect();
        for k in [1, 2, 5, 17, 18, 40] {
            let mut ring = RingOrder::new();
            ring.build(&phases, Some(&ranks), |i| include[i], k);
            for i in 0..n {
                let mut seen = Vec::new();
                ring.for_each_neighbour(i, |j| seen.push(j));
                assert_eq!(seen, brute(&phases, &ranks, &include, k, i), "k {k}, i {i}");
            }
        }
    }

    #[test]
    fn val_ring_wraps_and_small_rings_visit_everyone_once() {
        let phases = [3.0, -3.0, 0.0];
        let mut ring = RingOrder::new();
        ring.build(&phases, None, |_| true, 1);
        // Order: 1 (−3), 2 (0), 0 (3): ahead of 0 wraps to 1, behind 1 wraps to 0.
        let mut ahead_of_0 = Vec::new();
        ring.for_each_neighbour(0, |j| ahead_of_0.push(j));
        assert_eq!(ahead_of_0, vec![1, 2]);
        ring.build(&phases, None, |_| true, 5);
        let mut all = Vec::new();
        ring.for_each_neighbour(2, |j| all.push(j));
        assert_eq!(all, vec![0, 1]);
        // Alone, or excluded: nobody.
        ring.build(&phases, None, |i| i == 1, 3);
        let mut none = Vec::new();
        ring.for_each_neighbour(1, |j| none.push(j));
        ring.for_each_neighbour(0, |j| none.push(j));
        assert!(none.is_empty());
    }
}
