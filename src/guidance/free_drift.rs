//! The `none` law: no control at all; satellites drift under the truth dynamics.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::swarm::{GuidanceLaw, LawContext, LawError, SatelliteView};

/// The `none` law has no parameters (any key is refused).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FreeDriftParameters {}

/// Free drift: the commanded acceleration is always zero.
#[derive(Clone, Copy, Debug, Default)]
pub struct FreeDrift;

impl GuidanceLaw for FreeDrift {
    type State = ();
    type Parameters = FreeDriftParameters;

    fn name(&self) -> &'static str {
        "none"
    }

    fn command(
        &self,
        _satellite: &SatelliteView<'_>,
        _state: &(),
        _context: &LawContext,
    ) -> Vector3<f64> {
        Vector3::zeros()
    }

    fn set_parameters(&mut self, _parameters: &FreeDriftParameters) -> Result<(), LawError> {
        Ok(())
    }

    fn senses_neighbours(&self) -> bool {
        false
    }

    fn commands_nothing(&self) -> bool {
        true
    }
}
