//! Parameters of the `pigeon` law (the `[law]` table of a scenario), with units in every name and
//! [`PigeonParameters::check`]. The paper (H. Qiu, Q. Zhou, C. Sun, X. Wang, Y. Feng, "Distributed
//! Satellite Formation Based on Swarm Intelligence of Pigeon Flocks", IEEE conference paper) states the
//! ranges and limits but not its Algorithm 1 parameter table; the defaults here are ours and
//! `docs/methods/pigeon.md` gives the reason for each.
//!
//! Frames: `target_hill_m` is in the Hill frame (x radial out, y along-track, z orbit normal) relative to
//! the LVLH origin; every range is a 2-D distance in the y–z plane (the law's "pigeon" plane).

use crate::invalid::Invalid;
use serde::{Deserialize, Serialize};

use crate::swarm::LawError;

/// Parameters of the `pigeon` law. Keys carry their units.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PigeonParameters {
    /// Pattern switching on (default). `false`: p_h = 0 always, every satellite egalitarian (the
    /// paper's non-switching baseline).
    #[serde(default = "default_true")]
    pub switching: bool,
    /// Dominant set S_d: 0-based indices of the satellites that know the target (default [0, 1, 2]).
    #[serde(default = "default_dominant")]
    pub dominant: Vec<usize>,
    /// Target x_T, Hill frame relative to the LVLH origin \[m\] (default the origin); the law uses its
    /// (z, y) components.
    #[serde(default)]
    pub target_hill_m: [f64; 3],
    /// R_c^1: egalitarian link range \[m\] (default 130; 120 until 2026-12-01, changed after the results
    /// were seen because at 120 m the initial link graph of the paper's Table I was not connected:
    /// satellite 0's nearest neighbour is 115.3 m away, beyond R_c^1 − R_L^1 = 110 m, so it flew off
    /// alone; see `docs/methods/pigeon.md`); finite, > 0.
    #[serde(default = "default_egalitarian_range")]
    pub egalitarian_range_m: f64,
    /// R_c^2: hierarchical link range \[m\] (default 150); finite, >= R_c^1, and <= the scenario's
    /// sensing range (checked when the law starts).
    #[serde(default = "default_hierarchical_range")]
    pub hierarchical_range_m: f64,
    /// R_L^1: link delay distance \[m\] (default 10); 0 < R_L^1 < R_c^1. A link forms at R_c^1 − R_L^1
    /// and breaks beyond R_c^1.
    #[serde(default = "default_link_delay")]
    pub link_delay_m: f64,
    /// R_L^3: minimum allowed separation \[m\] (default 20), the formation potential's collision barrier;
    /// finite, > 0.
    #[serde(default = "default_min_separation")]
    pub min_separation_m: f64,
    /// R_d: desired separation \[m\] (default 40), the formation potential's minimum;
    /// R_L^3 < R_d < R_c^1.
    #[serde(default = "default_desired_separation")]
    pub desired_separation_m: f64,
    /// R_L^2: target zone radius \[m\] (default 50): no target pull inside it; finite, >= 0.
    #[serde(default = "default_target_zone")]
    pub target_zone_m: f64,
    /// R_L^4: minimum allowed clearance from an obstacle's surface \[m\] (default 10); finite, >= 0.
    #[serde(default = "default_min_clearance")]
    pub min_clearance_m: f64,
    /// R_c^3: obstacle detection distance from the surface \[m\] (default 100); finite, > R_L^4.
    #[serde(default = "default_obstacle_detection")]
    pub obstacle_detection_m: f64,
    /// K^F: formation gain \[1/s²\] (default 0.02); finite, >= 0.
    #[serde(default = "default_k_formation")]
    pub k_formation_per_s2: f64,
    /// K^T: target gain \[1/(m·s²)\] (default 1e-5); finite, >= 0.
    #[serde(default = "default_k_target")]
    pub k_target_per_m_s2: f64,
    /// K^V: velocity alignment gain \[1/s\] (default 0.3); finite, >= 0.
    #[serde(default = "default_k_alignment")]
    pub k_alignment_per_s: f64,
    /// K^O: obstacle gain \[1/s²\] (default 0.05); finite, >= 0.
    #[serde(default = "default_k_obstacle")]
    pub k_obstacle_per_s2: f64,
    /// K^P: radial PD stiffness \[1/s²\] (default 0.04); finite, >= 0.
    #[serde(default = "default_k_radial_p")]
    pub k_radial_p_per_s2: f64,
    /// K^D: radial PD damping \[1/s\] (default 0.4); finite, >= 0.
    #[serde(default = "default_k_radial_d")]
    pub k_radial_d_per_s: f64,
    /// α of the switching probability p_h = 1/(1 + α e^(−β(1 − V_a))) (default 9); finite, > 1.
    #[serde(default = "default_alpha")]
    pub alpha: f64,
    /// β of the switching probability (default 10); finite, > 0.
    #[serde(default = "default_beta")]
    pub beta: f64,
    /// w': alignment weight on leaders in the hierarchical pattern (default 3); finite, >= 1.
    #[serde(default = "default_leader_weight")]
    pub leader_weight: f64,
    /// K^{T,v}: absolute velocity damping −K^{T,v} v_i of the dominant satellites \[1/s\] (default 0,
    /// off). **Not in the paper**: our optional extension (see `docs/methods/pigeon.md`); finite, >= 0.
    #[serde(default)]
    pub target_velocity_damping_per_s: f64,
}

fn default_true() -> bool {
    true
}
fn default_dominant() -> Vec<usize> {
    vec![0, 1, 2]
}
fn default_egalitarian_range() -> f64 {
    130.0
}
fn default_hierarchical_range() -> f64 {
    150.0
}
fn default_link_delay() -> f64 {
    10.0
}
fn default_min_separation() -> f64 {
    20.0
}
fn default_desired_separation() -> f64 {
    40.0
}
fn default_target_zone() -> f64 {
    50.0
}
fn default_min_clearance() -> f64 {
    10.0
}
fn default_obstacle_detection() -> f64 {
    100.0
}
fn default_k_formation() -> f64 {
    0.02
}
fn default_k_target() -> f64 {
    1e-5
}
fn default_k_alignment() -> f64 {
    0.3
}
fn default_k_obstacle() -> f64 {
    0.05
}
fn default_k_radial_p() -> f64 {
    0.04
}
fn default_k_radial_d() -> f64 {
    0.4
}
fn default_alpha() -> f64 {
    9.0
}
fn default_beta() -> f64 {
    10.0
}
fn default_leader_weight() -> f64 {
    3.0
}

impl Default for PigeonParameters {
    fn default() -> Self {
        Self {
            switching: true,
            dominant: default_dominant(),
            target_hill_m: [0.0; 3],
            egalitarian_range_m: default_egalitarian_range(),
            hierarchical_range_m: default_hierarchical_range(),
            link_delay_m: default_link_delay(),
            min_separation_m: default_min_separation(),
            desired_separation_m: default_desired_separation(),
            target_zone_m: default_target_zone(),
            min_clearance_m: default_min_clearance(),
            obstacle_detection_m: default_obstacle_detection(),
            k_formation_per_s2: default_k_formation(),
            k_target_per_m_s2: default_k_target(),
            k_alignment_per_s: default_k_alignment(),
            k_obstacle_per_s2: default_k_obstacle(),
            k_radial_p_per_s2: default_k_radial_p(),
            k_radial_d_per_s: default_k_radial_d(),
            alpha: default_alpha(),
            beta: default_beta(),
            leader_weight: default_leader_weight(),
            target_velocity_damping_per_s: 0.0,
        }
    }
}

impl PigeonParameters {
    /// Checks every range and combination; messages name the key and what is allowed.
    pub fn check(&self) -> Result<(), LawError> {
        let range = |key: &str, v: f64, min: f64, strict: bool| {
            let ok = v.is_finite() && if strict { v > min } else { v >= min };
            if ok {
                Ok(())
            } else {
                Err(invalid(Invalid::range(
                    key,
                    v,
                    format!("finite, {} {min}", if strict { ">" } else { ">=" }),
                )))
            }
        };
        range("egalitarian_range_m", self.egalitarian_range_m, 0.0, true)?;
        range(
            "hierarchical_range_m",
            self.hierarchical_range_m,
            self.egalitarian_range_m,
            false,
        )?;
        range("link_delay_m", self.link_delay_m, 0.0, true)?;
        if self.link_delay_m >= self.egalitarian_range_m {
            return Err(invalid(Invalid::range(
                "link_delay_m",
                self.link_delay_m,
                format!(
                    "0 < link_delay_m < egalitarian_range_m = {}",
                    self.egalitarian_range_m
                ),
            )));
        }
        range("min_separation_m", self.min_separation_m, 0.0, true)?;
        range(
            "desired_separation_m",
            self.desired_separation_m,
            self.min_separation_m,
            true,
        )?;
        if self.desired_separation_m >= self.egalitarian_range_m {
            return Err(invalid(Invalid::range(
                "desired_separation_m",
                self.desired_separation_m,
                format!(
                    "min_separation_m < desired_separation_m < egalitarian_range_m = {}",
                    self.egalitarian_range_m
                ),
            )));
        }
        range("target_zone_m", self.target_zone_m, 0.0, false)?;
        range("min_clearance_m", self.min_clearance_m, 0.0, false)?;
        range(
            "obstacle_detection_m",
            self.obstacle_detection_m,
            self.min_clearance_m,
            true,
        )?;
        range("k_formation_per_s2", self.k_formation_per_s2, 0.0, false)?;
        range("k_target_per_m_s2", self.k_target_per_m_s2, 0.0, false)?;
        range("k_alignment_per_s", self.k_alignment_per_s, 0.0, false)?;
        range("k_obstacle_per_s2", self.k_obstacle_per_s2, 0.0, false)?;
        range("k_radial_p_per_s2", self.k_radial_p_per_s2, 0.0, false)?;
        range("k_radial_d_per_s", self.k_radial_d_per_s, 0.0, false)?;
        range("alpha", self.alpha, 1.0, true)?;
        range("beta", self.beta, 0.0, true)?;
        range("leader_weight", self.leader_weight, 1.0, false)?;
        range(
            "target_velocity_damping_per_s",
            self.target_velocity_damping_per_s,
            0.0,
            false,
        )?;
        if self.target_hill_m.iter().any(|v| !v.is_finite()) {
            return Err(invalid(Invalid::keys(
                "target_hill_m",
                format!(
                    "target_hill_m = {:?} is out of range (allowed: finite)",
                    self.target_hill_m
                ),
                "",
            )));
        }
        let mut sorted = self.dominant.clone();
        sorted.sort_unstable();
        sorted.dedup();
        if sorted.len() != self.dominant.len() {
            return Err(invalid(Invalid::keys(
                "dominant",
                format!(
                    "dominant = {:?} lists a satellite twice (allowed: distinct 0-based indices)",
                    self.dominant
                ),
                "",
            )));
        }
        Ok(())
    }
}

pub(super) fn invalid(invalid: Invalid) -> LawError {
    LawError::invalid("pigeon", invalid)
}
