//! `scene.json`: the geometry a run's pictures need beside the trajectories — threats (straight lines
//! in the Hill frame), obstacles (spheres) and the law's target formation — resolved from the scenario
//! and written once when the run starts, so plots, the report and exports work from the run directory
//! alone. A real object (a threat or obstacle from an element set or a state) is marked `tracked`: its
//! position and velocity are its Hill state at t = 0, not a line it keeps to.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::run_data::RunDataError;
use crate::swarm::SimulationConfig;

/// The scene's file name in a run directory.
pub const SCENE_FILE: &str = "scene.json";

/// A threat's straight line in the Hill frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SceneThreat {
    /// Name.
    pub name: String,
    /// Danger-sphere radius \[m\].
    pub danger_radius_m: f64,
    /// Position at t = 0, Hill LVLH \[m\].
    pub position_at_t0_lvlh_m: [f64; 3],
    /// Constant velocity, Hill LVLH \[m/s\] (a tracked object's: at t = 0).
    pub velocity_lvlh_mps: [f64; 3],
    /// A real object on a tracked path (its orbit, not a line in the Hill frame); the figures do not
    /// draw it.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub tracked: bool,
}

impl SceneThreat {
    /// Position at `t_s`, Hill LVLH \[m\].
    pub fn position_lvlh_m(&self, t_s: f64) -> [f64; 3] {
        std::array::from_fn(|k| self.position_at_t0_lvlh_m[k] + self.velocity_lvlh_mps[k] * t_s)
    }
}

/// A static spherical obstacle in the Hill frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SceneObstacle {
    /// Name.
    pub name: String,
    /// Centre, Hill LVLH \[m\].
    pub center_lvlh_m: [f64; 3],
    /// Radius \[m\].
    pub radius_m: f64,
    /// Centred on a real object on a tracked path (`center_lvlh_m` is its centre at t = 0); the
    /// figures do not draw it.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub tracked: bool,
}

/// The content of `scene.json`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Scene {
    /// Threats.
    pub threats: Vec<SceneThreat>,
    /// Obstacles.
    pub obstacles: Vec<SceneObstacle>,
    /// The formation the law at t = 0 steers to, Hill LVLH relative to the LVLH origin \[m\]: one point
    /// per slot, or points sampled on a target ring or surface
    /// ([`crate::swarm::TargetFormation::target_formation_hill_m`]; absent when the law has none).
    pub target_formation_lvlh_m: Option<Vec<[f64; 3]>>,
}

impl Scene {
    /// The threats and obstacles of a simulation's configuration (no target formation).
    pub fn from_config(config: &SimulationConfig) -> Self {
        Self {
            threats: config
                .threats
                .iter()
                .map(|t| {
                    let p = t.position_hill_m(0.0);
                    let v = t.velocity_hill_mps(0.0);
                    SceneThreat {
                        name: t.name().to_string(),
                        danger_radius_m: t.danger_radius_m(),
                        position_at_t0_lvlh_m: [p.x, p.y, p.z],
                        velocity_lvlh_mps: [v.x, v.y, v.z],
                        tracked: t.motion().is_tracked(),
                    }
                })
                .collect(),
            obstacles: config
                .obstacles
                .iter()
                .map(|o| {
                    let c = o.center_hill_m(0.0);
                    SceneObstacle {
                        name: o.name().to_string(),
                        center_lvlh_m: [c.x, c.y, c.z],
                        radius_m: o.radius_m(),
                        tracked: o.motion().is_tracked(),
                    }
                })
                .collect(),
            target_formation_lvlh_m: None,
        }
    }

    /// Writes `dir/scene.json` whole (a failed write, e.g. a full disk, leaves no partial file).
    pub fn write(&self, dir: &Path) -> std::io::Result<()> {
        let text = serde_json::to_string_pretty(self).expect("the scene serialises");
        super::export::write_whole(&dir.join(SCENE_FILE), (text + "\n").as_bytes())
            .map_err(|e| std::io::Error::other(e.to_string()))
    }

    /// Reads `dir/scene.json` (through [`crate::input_file`]); a run directory without one (written by
    /// an older satflock) has an empty scene. Radii must be at least 0 (JSON numbers are finite).
    pub fn read(dir: &Path) -> Result<Self, RunDataError> {
        let path = dir.join(SCENE_FILE);
        let fail = |message: String| RunDataError {
            path: path.display().to_string(),
            message,
        };
        let scene: Self = match crate::input_file::read_document(&path) {
            Ok(text) => serde_json::from_str(&text).map_err(|e| fail(e.to_string()))?,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Self::default()),
            Err(e) => return Err(fail(e.to_string())),
        };
        let radii = scene
            .threats
            .iter()
            .enumerate()
            .map(|(k, t)| (format!("threats[{k}].danger_radius_m"), t.danger_radius_m))
            .chain(
                scene
                    .obstacles
                    .iter()
                    .enumerate()
                    .map(|(k, o)| (format!("obstacles[{k}].radius_m"), o.radius_m)),
            );
        for (key, r) in radii {
            if r < 0.0 {
                return Err(fail(format!(
                    "`{key}` = {r} is out of range (allowed: >= 0 m)"
                )));
            }
        }
        Ok(scene)
    }
}
