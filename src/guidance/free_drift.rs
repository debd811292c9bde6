//! The `none` law: no control at all; satellites drift under the truth dynamics.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::guidance::parameters::merge_parameters;
use crate::swarm::{GuidanceLaw, LawError, SatelliteView};

/// The `none` law has no parameters (any key is refused).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FreeDriftParameters {}

/// Free drift: the commanded acceleration is always zero.
#[derive(Clone, Copy, Debug, Default)]
pub struct FreeDrift;

impl GuidanceLaw for FreeDrift {
    fn name(&self) -> &'static str {
        "none"
    }

    fn command_m_s2(&self, _satellite: &SatelliteView<'_>) -> Vector3<f64> {
        Vector3::zeros()
    }

    fn set_parameters(&mut self, parameters: &toml::Table) -> Result<(), LawError> {
        merge_parameters(self.name(), &FreeDriftParameters {}, parameters).map(|_| ())
    }
}
