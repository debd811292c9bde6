//! The artificial potentials of the `pigeon` law as functions of a 2-D distance r \[m\] in the y–z plane:
//! formation V^F (Qiu et al. Eq. 6, reconstructed), target V^T (Eq. 7) and obstacle V^O (Eq. 15,
//! reconstructed), each with its radial slope dV/dr. The law uses the slopes; the potentials exist so
//! the slopes can be checked against them (the additive constants are irrelevant).
//!
//! Both barrier potentials are built from g(s) = s²/2 − c² ln s, whose only minimum is at s = c; the
//! slopes are evaluated with s clamped to s ≥ [`CLAMP_FRACTION`]·c so the force stays finite when a
//! discrete-time, saturated run crosses a barrier (the law counts such samples).

/// The clamp of the barrier arguments, as a fraction of the potential's scale (R_d or ρ_j): s ≥ 1e-3 c.
pub const CLAMP_FRACTION: f64 = 1e-3;

/// g(s) = s²/2 − c² ln s \[m²\] (s, c in m; the logarithm of a length only shifts the constant).
fn barrier_g(s: f64, c: f64) -> f64 {
    0.5 * s * s - c * c * s.ln()
}

/// g'(s) = s − c²/s \[m\].
fn barrier_dg(s: f64, c: f64) -> f64 {
    s - c * c / s
}

/// The formation potential's geometry: R_L^3 (collision barrier), R_d (minimum) and R_c^1 (connectivity
/// barrier) \[m\], with R_L^3 < R_d < R_c^1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FormationPotential {
    /// R_L^3: minimum allowed separation \[m\].
    pub min_separation_m: f64,
    /// R_d: desired separation \[m\].
    pub desired_separation_m: f64,
    /// R_c^1: egalitarian link range \[m\].
    pub link_range_m: f64,
}

impl FormationPotential {
    /// Repulsive-branch argument s_A = R_d (r − R_L^3)/(R_d − R_L^3) and its dr-derivative (unclamped).
    fn branch_a(&self, r_m: f64) -> (f64, f64) {
        let (lo, d) = (self.min_separation_m, self.desired_separation_m);
        let c = d / (d - lo);
        (c * (r_m - lo), c)
    }

    /// Attractive-branch argument s_B = R_d (R_c^1 − r)/(R_c^1 − R_d) and its dr-derivative (unclamped).
    fn branch_b(&self, r_m: f64) -> (f64, f64) {
        let (d, hi) = (self.desired_separation_m, self.link_range_m);
        let c = d / (hi - d);
        (c * (hi - r_m), -c)
    }

    /// V^F(r) \[m²\] for R_L^3 < r < R_c^1 (+∞ outside: the barriers).
    pub fn potential_m2(&self, r_m: f64) -> f64 {
        let d = self.desired_separation_m;
        if r_m <= self.min_separation_m || r_m >= self.link_range_m {
            return f64::INFINITY;
        }
        let (s, _) = if r_m <= d {
            self.branch_a(r_m)
        } else {
            self.branch_b(r_m)
        };
        barrier_g(s, d)
    }

    /// dV^F/dr \[m\] with the argument clamped at s ≥ 1e-3 R_d: ≤ 0 (repulsive) for r ≤ R_d, ≥ 0
    /// (attractive) beyond. Finite for every r (at or past a barrier it is the clamped barrier slope).
    pub fn slope_m(&self, r_m: f64) -> f64 {
        let d = self.desired_separation_m;
        let s_min = CLAMP_FRACTION * d;
        let (s, ds_dr) = if r_m <= d {
            self.branch_a(r_m)
        } else {
            self.branch_b(r_m)
        };
        barrier_dg(s.max(s_min), d) * ds_dr
    }
}

/// V^T(r_T) = (r_T − R_L^2)³/3 beyond the target zone, 0 inside \[m³\].
pub fn target_potential_m3(distance_m: f64, zone_m: f64) -> f64 {
    if distance_m >= zone_m {
        (distance_m - zone_m).powi(3) / 3.0
    } else {
        0.0
    }
}

/// dV^T/dr_T = (r_T − R_L^2)² beyond the target zone, 0 inside \[m²\].
pub fn target_slope_m2(distance_m: f64, zone_m: f64) -> f64 {
    if distance_m >= zone_m {
        (distance_m - zone_m).powi(2)
    } else {
        0.0
    }
}

/// The obstacle potential of one circle of radius r^O in the y–z plane: R_L^4 (clearance limit) and
/// R_c^3 (detection distance), both from the surface \[m\], R_c^3 > R_L^4.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObstaclePotential {
    /// r^O: the obstacle's radius \[m\].
    pub radius_m: f64,
    /// R_L^4: minimum allowed clearance from the surface \[m\].
    pub min_clearance_m: f64,
    /// R_c^3: detection distance from the surface \[m\].
    pub detection_m: f64,
}

impl ObstaclePotential {
    /// ρ = r^O + R_c^3: the centre distance beyond which the potential is flat \[m\].
    pub fn outer_m(&self) -> f64 {
        self.radius_m + self.detection_m
    }

    /// r_in = r^O + R_L^4: the centre distance of the barrier \[m\].
    pub fn inner_m(&self) -> f64 {
        self.radius_m + self.min_clearance_m
    }

    /// s = ρ (r − r_in)/(R_c^3 − R_L^4) and ds/dr (unclamped).
    fn argument(&self, r_m: f64) -> (f64, f64) {
        let c = self.outer_m() / (self.detection_m - self.min_clearance_m);
        (c * (r_m - self.inner_m()), c)
    }

    /// V^O(r) \[m²\] of the distance r from the centre (+∞ at or inside r_in, the constant g(ρ) beyond ρ).
    pub fn potential_m2(&self, r_m: f64) -> f64 {
        let rho = self.outer_m();
        if r_m <= self.inner_m() {
            f64::INFINITY
        } else if r_m <= rho {
            barrier_g(self.argument(r_m).0, rho)
        } else {
            barrier_g(rho, rho)
        }
    }

    /// dV^O/dr \[m\] with s clamped at s ≥ 1e-3 ρ: ≤ 0 (repulsive) inside ρ, 0 beyond.
    pub fn slope_m(&self, r_m: f64) -> f64 {
        let rho = self.outer_m();
        if r_m > rho {
            return 0.0;
        }
        let (s, ds_dr) = self.argument(r_m);
        barrier_dg(s.max(CLAMP_FRACTION * rho), rho) * ds_dr
    }
}
