//! The `hold` law: a proportional-derivative hold of each satellite's slot, with optional cancellation of
//! the Hill–Clohessy–Wiltshire natural acceleration.
//!
//! Slot = the satellite's relative position (Hill frame, relative to the LVLH origin) when the law starts
//! (run start, or the event that switches it in), shifted by the current `slot_offset_hill_m` (so an
//! event that changes the offset moves every slot). Command:
//!
//! u = −k_p (r − r_slot) − k_d v − a_nat,HCW(r, v)   (the last term only with `feedforward = "hcw"`)
//!
//! where a_nat,HCW = (3n²x + 2n ẏ, −2n ẋ, −n²z) is the HCW natural acceleration. With the feed-forward
//! on HCW dynamics the closed loop is exactly r̈ + k_d ṙ + k_p (r − r_slot) = 0 on each axis.
//! This law exists to test the engine; it needs no neighbours.

use crate::invalid::Invalid;
use std::sync::Arc;

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::relative::Hcw;
use crate::swarm::{GuidanceLaw, LawContext, LawError, SatelliteView, SwarmView, TargetFormation};

/// Natural-acceleration feed-forward of the `hold` law.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Feedforward {
    /// No feed-forward.
    #[default]
    None,
    /// Cancel the HCW natural acceleration of the reference's mean motion.
    Hcw,
}

/// Parameters of the `hold` law.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HoldParameters {
    /// Proportional gain k_p \[1/s^2\] (acceleration per metre of slot error); > 0.
    pub stiffness_per_s2: f64,
    /// Derivative gain k_d \[1/s\] (acceleration per m/s of relative velocity); >= 0.
    pub damping_per_s: f64,
    /// Feed-forward of the natural relative acceleration (default: none).
    #[serde(default)]
    pub feedforward: Feedforward,
    /// Offset added to every slot, Hill frame \[m\] (default: zero).
    #[serde(default)]
    pub slot_offset_hill_m: [f64; 3],
}

/// The `hold` law.
#[derive(Clone, Debug)]
pub struct Hold {
    parameters: HoldParameters,
    /// Relative positions when the law started, Hill frame \[m\].
    start_positions_hill_m: Arc<Vec<Vector3<f64>>>,
}

impl Hold {
    /// Builds the law, checking the gains.
    pub fn new(parameters: HoldParameters) -> Result<Self, LawError> {
        check(&parameters)?;
        Ok(Self {
            parameters,
            start_positions_hill_m: Arc::new(Vec::new()),
        })
    }

    /// Slot of satellite `id`, Hill frame \[m\]. Panics before the law has started.
    pub fn slot_hill_m(&self, id: usize) -> Vector3<f64> {
        self.start_positions_hill_m[id] + Vector3::from(self.parameters.slot_offset_hill_m)
    }
}

fn check(p: &HoldParameters) -> Result<(), LawError> {
    let invalid = |invalid: Invalid| LawError::invalid("hold", invalid);
    if !(p.stiffness_per_s2 > 0.0 && p.stiffness_per_s2.is_finite()) {
        return Err(invalid(Invalid::range(
            "stiffness_per_s2",
            p.stiffness_per_s2,
            "finite, > 0",
        )));
    }
    if !(p.damping_per_s >= 0.0 && p.damping_per_s.is_finite()) {
        return Err(invalid(Invalid::range(
            "damping_per_s",
            p.damping_per_s,
            "finite, >= 0",
        )));
    }
    if p.slot_offset_hill_m.iter().any(|v| !v.is_finite()) {
        return Err(invalid(Invalid::keys(
            "slot_offset_hill_m",
            "slot_offset_hill_m must be finite",
            "",
        )));
    }
    Ok(())
}

impl GuidanceLaw for Hold {
    type State = ();
    type Parameters = HoldParameters;
    crate::capabilities!(TargetFormation);

    fn name(&self) -> &'static str {
        "hold"
    }

    fn initialise(&mut self, swarm: &SwarmView<'_>, _states: &mut [()]) -> Result<(), LawError> {
        self.start_positions_hill_m =
            Arc::new(swarm.relative_states.iter().map(|s| s.position_m).collect());
        Ok(())
    }

    fn command(
        &self,
        satellite: &SatelliteView<'_>,
        _state: &(),
        _context: &LawContext,
    ) -> Vector3<f64> {
        let p = &self.parameters;
        let own = satellite.own_state();
        let slot = self.slot_hill_m(satellite.id());
        let mut u =
            -p.stiffness_per_s2 * (own.position_m - slot) - p.damping_per_s * own.velocity_mps;
        if p.feedforward == Feedforward::Hcw {
            let hcw = Hcw::new(satellite.shared().mean_motion_rad_s);
            u -= hcw.natural_acceleration_m_s2(&own.position_m, &own.velocity_mps);
        }
        u
    }

    /// Starts loading the satellite's start position (read by id: scattered in memory on a large
    /// swarm evaluated in cell order).
    fn prefetch(&self, id: usize) {
        if let Some(start) = self.start_positions_hill_m.get(id) {
            crate::prefetch::read(start);
        }
    }

    fn set_parameters(&mut self, parameters: &HoldParameters) -> Result<(), LawError> {
        check(parameters)?;
        self.parameters = parameters.clone();
        Ok(())
    }

    /// Largest |root| of s² + k_d s + k_p = 0.
    fn fastest_rate_per_s(&self, _mass_kg: f64) -> Option<f64> {
        let (kp, kd) = (
            self.parameters.stiffness_per_s2,
            self.parameters.damping_per_s,
        );
        let disc = kd * kd - 4.0 * kp;
        Some(if disc > 0.0 {
            0.5 * (kd + disc.sqrt())
        } else {
            kp.sqrt()
        })
    }
}

impl TargetFormation for Hold {
    /// Every satellite's slot (once the law has started).
    fn target_formation_hill_m(&self) -> Option<Vec<Vector3<f64>>> {
        (!self.start_positions_hill_m.is_empty()).then(|| {
            (0..self.start_positions_hill_m.len())
                .map(|id| self.slot_hill_m(id))
                .collect()
        })
    }
}
