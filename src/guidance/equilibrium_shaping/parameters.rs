//! Parameters of the `equilibrium-shaping` law (the `[law]` table of a scenario), with units in every
//! name, the paper's values as defaults where the paper gives them and documented defaults where it does
//! not, and [`EquilibriumShapingParameters::check`].
//!
//! Frames: every position and direction is in the Hill frame (x radial out, y along-track, z orbit
//! normal) relative to the LVLH origin.

use crate::invalid::Invalid;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::shaping::{check_nodes, GatherAvoidDock};
use crate::swarm::LawError;

/// The paper's four scatter strategies (paper §4), each a NOMINAL, a WARNED and a RETURNING field.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Strategy {
    /// S1: scatter out of a danger sphere when warned (Lennard-Jones + scatter + viscosity), gather back
    /// to the nodes after the all-clear (gather/avoid/dock).
    ScatterGather,
    /// S2: keep the relative geometry (Eq. 1) and dodge with the threat term; the centroid may move.
    MovingCentroid,
    /// S3: dodge with the threat term on top of gather/avoid/dock; return to the same nodes.
    FixedCentroid,
    /// S4: dodge as S2 (Eq. 1 + threat), return as S1/S3 (gather/avoid/dock).
    Mix,
}

impl Strategy {
    /// Name as written in scenario files.
    pub fn name(self) -> &'static str {
        match self {
            Strategy::ScatterGather => "scatter-gather",
            Strategy::MovingCentroid => "moving-centroid",
            Strategy::FixedCentroid => "fixed-centroid",
            Strategy::Mix => "mix",
        }
    }
}

/// The desired geometry.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Formation {
    /// Four nodes, 60°/120° rhombus of side l in the orbital plane (the paper's geometry; the in-plane
    /// orientation is our choice): (∓l√3/2, 0, 0), (0, ±l/2, 0).
    Rhombus,
    /// Six nodes on a regular hexagon of side l in the orbital plane: l (cos kπ/3, sin kπ/3, 0).
    Hexagon,
    /// The nodes of `nodes_hill_m`.
    Custom,
}

/// How the threat term's escape direction â is chosen (paper Eq. 3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Escape {
    /// Flee along the threat's own direction of motion, â = v̂_T.
    #[default]
    Parallel,
    /// One direction perpendicular to v_T, the same for every satellite.
    PerpCommon,
    /// Away from the threat's line, perpendicular to v_T (each satellite its own direction).
    PerpRadial,
    /// Directly away from the threat's current position, â = unit(x − p_T) (each satellite its own
    /// direction, re-evaluated with the threat's motion; the common perpendicular on the threat).
    Away,
}

/// The kinematic-acceleration feed-forward of the tracking controller (paper Eq. 7; how the paper
/// obtains it is not stated).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Feedforward {
    /// The analytic material derivative of the desired-velocity field along the motion.
    #[default]
    Analytic,
    /// No feed-forward: u = k (v_des − v) − a_in.
    None,
}

/// Parameters of the `equilibrium-shaping` law. Keys carry their units; the defaults are the paper's
/// values (S. Nag and L. Summerer, Acta Astronautica 82 (2013) 95–109) except where noted.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EquilibriumShapingParameters {
    /// Which strategy (required).
    pub strategy: Strategy,
    /// Which geometry (required).
    pub formation: Formation,
    /// Side l of the preset formations \[m\] (default 6, the paper's); finite, > 0.
    #[serde(default = "default_side_m")]
    pub side_m: f64,
    /// Nodes of `formation = "custom"`, Hill frame relative to the LVLH origin \[m\]; satellite i takes
    /// node i. Only with `custom`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub nodes_hill_m: Option<Vec<[f64; 3]>>,
    /// Index of the scenario threat the law reacts to (warnings about it and its physical sensing).
    #[serde(default)]
    pub threat: usize,
    /// Escape direction rule of the threat term (default `parallel`).
    #[serde(default)]
    pub escape: Escape,
    /// With `escape = "perp-common"`: the common direction, Hill frame (any length; projected
    /// perpendicular to the threat's velocity and normalised). Absent: a seeded choice
    /// (`escape_seed`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub escape_direction_hill: Option<[f64; 3]>,
    /// Seed of the `perp-common` direction when `escape_direction_hill` is absent (default 0): the angle
    /// about v_T is drawn from it, so every satellite makes the same choice.
    #[serde(default)]
    pub escape_seed: u64,
    /// Command the field velocity itself (the kinematic model, paper Fig. 2) instead of an acceleration.
    #[serde(default)]
    pub kinematic: bool,
    /// Eq. 1 repulsion strength b \[1/s\] (default 20); finite, >= 0.
    #[serde(default = "default_pair_b")]
    pub pair_b_per_s: f64,
    /// Eq. 1 repulsion range c \[m²\] (default 10); finite, > 0.
    #[serde(default = "default_pair_c")]
    pub pair_c_m2: f64,
    /// Eq. 3 threat scale A \[m/s\] (default 40); finite, >= 0.
    #[serde(default = "default_threat_scale")]
    pub threat_scale_mps: f64,
    /// Physical sensing radius R_s \[m\] (default 10): the threat term acts in NOMINAL and RETURNING when
    /// the threat is this close, with K = 2 (R_s/3)²; finite, > 0.
    #[serde(default = "default_physical_sensing_radius")]
    pub physical_sensing_radius_m: f64,
    /// Lennard-Jones depth ε \[m²/s\] (default 0.1); finite, >= 0.
    #[serde(default = "default_lj_epsilon")]
    pub lj_epsilon_m2_per_s: f64,
    /// Danger sphere centre c_D, Hill frame \[m\] (default the origin).
    #[serde(default)]
    pub danger_center_hill_m: [f64; 3],
    /// Danger sphere radius R \[m\] (default 20); finite, > 0.
    #[serde(default = "default_danger_radius")]
    pub danger_radius_m: f64,
    /// Scatter gain κ \[1/(m·s)\] (not given by the paper; default 5e-4, 0.2 m/s at the centre of a 20 m
    /// sphere); finite, >= 0.
    #[serde(default = "default_scatter_gain")]
    pub scatter_gain_per_m_s: f64,
    /// Viscosity gain K_ν (dimensionless; not given by the paper, default 1); finite, >= 0.
    #[serde(default = "default_viscosity_gain")]
    pub viscosity_gain: f64,
    /// Viscosity band D \[m\] (default 0.5); finite, >= 0.
    #[serde(default = "default_viscosity_band")]
    pub viscosity_band_m: f64,
    /// Gather coefficient c \[1/s\] (default 3.214e-3); finite, >= 0.
    #[serde(default = "default_gather")]
    pub gather_per_s: f64,
    /// Dock coefficient d \[1/s\] (default 40); finite, >= 0.
    #[serde(default = "default_dock")]
    pub dock_per_s: f64,
    /// Avoid range k₂ \[m²\] (default 6); finite, > 0.
    #[serde(default = "default_range")]
    pub avoid_range_m2: f64,
    /// Dock range k₃ \[m²\] (default 6); finite, > 0.
    #[serde(default = "default_range")]
    pub dock_range_m2: f64,
    /// Velocity-tracking gain k \[1/s\] (not given by the paper; default 0.05); finite, > 0.
    #[serde(default = "default_tracking_gain")]
    pub tracking_gain_per_s: f64,
    /// Kinematic-acceleration feed-forward (default `analytic`).
    #[serde(default)]
    pub feedforward: Feedforward,
    /// RETURNING → NOMINAL: RMS pair-distance error below this \[m\] (default 0.1); finite, > 0.
    #[serde(default = "default_settle_error")]
    pub settle_error_m: f64,
    /// RETURNING → NOMINAL: own and sensed neighbours' speeds below this \[m/s\] (default 1e-3); finite,
    /// > 0.
    #[serde(default = "default_settle_speed")]
    pub settle_speed_mps: f64,
    /// RETURNING → NOMINAL: both conditions held this long \[s\] (default 10); finite, >= 0.
    #[serde(default = "default_settle_hold")]
    pub settle_hold_s: f64,
}

fn default_side_m() -> f64 {
    6.0
}
fn default_pair_b() -> f64 {
    20.0
}
fn default_pair_c() -> f64 {
    10.0
}
fn default_threat_scale() -> f64 {
    40.0
}
fn default_physical_sensing_radius() -> f64 {
    10.0
}
fn default_lj_epsilon() -> f64 {
    0.1
}
fn default_danger_radius() -> f64 {
    20.0
}
fn default_scatter_gain() -> f64 {
    5e-4
}
fn default_viscosity_gain() -> f64 {
    1.0
}
fn default_viscosity_band() -> f64 {
    0.5
}
fn default_gather() -> f64 {
    3.214e-3
}
fn default_dock() -> f64 {
    40.0
}
fn default_range() -> f64 {
    6.0
}
fn default_tracking_gain() -> f64 {
    0.05
}
fn default_settle_error() -> f64 {
    0.1
}
fn default_settle_speed() -> f64 {
    1e-3
}
fn default_settle_hold() -> f64 {
    10.0
}

impl EquilibriumShapingParameters {
    /// The parameters with every default and the given strategy and formation.
    pub fn new(strategy: Strategy, formation: Formation) -> Self {
        Self {
            strategy,
            formation,
            side_m: default_side_m(),
            nodes_hill_m: None,
            threat: 0,
            escape: Escape::default(),
            escape_direction_hill: None,
            escape_seed: 0,
            kinematic: false,
            pair_b_per_s: default_pair_b(),
            pair_c_m2: default_pair_c(),
            threat_scale_mps: default_threat_scale(),
            physical_sensing_radius_m: default_physical_sensing_radius(),
            lj_epsilon_m2_per_s: default_lj_epsilon(),
            danger_center_hill_m: [0.0; 3],
            danger_radius_m: default_danger_radius(),
            scatter_gain_per_m_s: default_scatter_gain(),
            viscosity_gain: default_viscosity_gain(),
            viscosity_band_m: default_viscosity_band(),
            gather_per_s: default_gather(),
            dock_per_s: default_dock(),
            avoid_range_m2: default_range(),
            dock_range_m2: default_range(),
            tracking_gain_per_s: default_tracking_gain(),
            feedforward: Feedforward::default(),
            settle_error_m: default_settle_error(),
            settle_speed_mps: default_settle_speed(),
            settle_hold_s: default_settle_hold(),
        }
    }

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
        range("side_m", self.side_m, 0.0, true)?;
        range("pair_b_per_s", self.pair_b_per_s, 0.0, false)?;
        range("pair_c_m2", self.pair_c_m2, 0.0, true)?;
        range("threat_scale_mps", self.threat_scale_mps, 0.0, false)?;
        range(
            "physical_sensing_radius_m",
            self.physical_sensing_radius_m,
            0.0,
            true,
        )?;
        range("lj_epsilon_m2_per_s", self.lj_epsilon_m2_per_s, 0.0, false)?;
        range("danger_radius_m", self.danger_radius_m, 0.0, true)?;
        range(
            "scatter_gain_per_m_s",
            self.scatter_gain_per_m_s,
            0.0,
            false,
        )?;
        range("viscosity_gain", self.viscosity_gain, 0.0, false)?;
        range("viscosity_band_m", self.viscosity_band_m, 0.0, false)?;
        range("gather_per_s", self.gather_per_s, 0.0, false)?;
        range("dock_per_s", self.dock_per_s, 0.0, false)?;
        range("avoid_range_m2", self.avoid_range_m2, 0.0, true)?;
        range("dock_range_m2", self.dock_range_m2, 0.0, true)?;
        range("tracking_gain_per_s", self.tracking_gain_per_s, 0.0, true)?;
        range("settle_error_m", self.settle_error_m, 0.0, true)?;
        range("settle_speed_mps", self.settle_speed_mps, 0.0, true)?;
        range("settle_hold_s", self.settle_hold_s, 0.0, false)?;
        if self.danger_center_hill_m.iter().any(|v| !v.is_finite()) {
            return Err(invalid(Invalid::keys(
                "danger_center_hill_m",
                format!(
                    "danger_center_hill_m = {:?} is out of range (allowed: finite)",
                    self.danger_center_hill_m
                ),
                "",
            )));
        }
        match (self.formation, &self.nodes_hill_m) {
            (Formation::Custom, None) => return Err(invalid(Invalid::keys("formation", "formation = \"custom\" needs nodes_hill_m (a list of [x, y, z] in metres, Hill \
                     frame, one per satellite)"
                    , ""))),
            (Formation::Rhombus | Formation::Hexagon, Some(_)) => return Err(invalid(Invalid::keys("nodes_hill_m", "nodes_hill_m is only read with formation = \"custom\" (the presets are set by \
                     side_m)"
                    , ""))),
            _ => {}
        }
        let key = match self.formation {
            Formation::Custom => "nodes_hill_m",
            Formation::Rhombus | Formation::Hexagon => "formation",
        };
        check_nodes(&self.nodes_hill_m())
            .map_err(|e| invalid(Invalid::keys(key, format!("{key}: {e}"), "")))?;
        if let Some(d) = self.escape_direction_hill {
            if self.escape != Escape::PerpCommon {
                return Err(invalid(Invalid::keys(
                    "escape_direction_hill",
                    "escape_direction_hill is only read with escape = \"perp-common\"",
                    "",
                )));
            }
            if !d.iter().all(|v| v.is_finite()) || Vector3::from(d).norm() == 0.0 {
                return Err(invalid(Invalid::keys(
                    "escape_direction_hill",
                    format!(
                        "escape_direction_hill = {d:?} is out of range (allowed: finite, non-zero)"
                    ),
                    "",
                )));
            }
        }
        if self.escape_seed > i64::MAX as u64 {
            return Err(invalid(Invalid::keys(
                "escape_seed",
                format!(
                    "escape_seed = {} is out of range (allowed: 0 ..= {})",
                    self.escape_seed,
                    i64::MAX
                ),
                "",
            )));
        }
        Ok(())
    }

    /// The desired nodes ξ_i, Hill frame relative to the LVLH origin \[m\], satellite i ↔ node i.
    pub fn nodes_hill_m(&self) -> Vec<Vector3<f64>> {
        let l = self.side_m;
        match self.formation {
            Formation::Rhombus => {
                let h = l * 3f64.sqrt() / 2.0;
                vec![
                    Vector3::new(-h, 0.0, 0.0),
                    Vector3::new(h, 0.0, 0.0),
                    Vector3::new(0.0, l / 2.0, 0.0),
                    Vector3::new(0.0, -l / 2.0, 0.0),
                ]
            }
            Formation::Hexagon => (0..6)
                .map(|k| {
                    let angle = k as f64 * std::f64::consts::PI / 3.0;
                    Vector3::new(l * angle.cos(), l * angle.sin(), 0.0)
                })
                .collect(),
            Formation::Custom => self
                .nodes_hill_m
                .as_deref()
                .unwrap_or_default()
                .iter()
                .map(|p| Vector3::from(*p))
                .collect(),
        }
    }

    /// The fixed gains of the gather/avoid/dock field.
    pub fn gather_avoid_dock(&self) -> GatherAvoidDock {
        GatherAvoidDock {
            gather_per_s: self.gather_per_s,
            dock_per_s: self.dock_per_s,
            avoid_range_m2: self.avoid_range_m2,
            dock_range_m2: self.dock_range_m2,
        }
    }

    /// Gaussian width of the physically sensed threat term, K = 2 (R_s/3)² \[m²\].
    pub fn physical_width_m2(&self) -> f64 {
        gaussian_width_m2(self.physical_sensing_radius_m)
    }
}

/// The threat term's Gaussian width K = 2 (R/3)² \[m²\] for a sensing radius `radius_m` \[m\] (its 3σ
/// point at the radius).
pub fn gaussian_width_m2(radius_m: f64) -> f64 {
    2.0 * (radius_m / 3.0).powi(2)
}

fn invalid(invalid: Invalid) -> LawError {
    LawError::invalid("equilibrium-shaping", invalid)
}
