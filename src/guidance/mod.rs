//! Guidance laws and their registry.
//!
//! A law implements [`crate::swarm::GuidanceLaw`]; the registry ([`LawConfig`]) is the closed set of
//! laws a scenario file can name, each with its own parameter table. Adding a law means a module here
//! and a variant of [`LawConfig`]; the engine does not change.
//!
//! | name | module | what it does |
//! | --- | --- | --- |
//! | `none` | [`free_drift`] | no control: free drift under the truth dynamics |
//! | `hold` | [`hold`] | PD hold of each satellite's slot (its relative position when the law starts) |
//! | `bifurcating` | [`bifurcating`] | Gao et al. 2022 bifurcating potential field: formation, collision avoidance, damping |
//! | `j2-distance` | [`j2_distance`] | Takahashi–Sakai distance-based stabiliser under J2 (main or opposing), with centralised DT grouping |

pub mod bifurcating;
pub mod free_drift;
pub mod hold;
pub mod j2_distance;
pub mod parameters;

use serde::{Deserialize, Serialize};

use crate::swarm::{GuidanceLaw, LawError};

/// The laws a scenario can name, with their parameters (the `[law]` table of a scenario file; the key
/// `name` selects the law).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "name", rename_all = "kebab-case")]
pub enum LawConfig {
    /// No control.
    None(free_drift::FreeDriftParameters),
    /// PD slot hold.
    Hold(hold::HoldParameters),
    /// Bifurcating potential field (Gao et al. 2022).
    Bifurcating(bifurcating::BifurcatingParameters),
    /// Takahashi–Sakai distance-based stabiliser under J2.
    J2Distance(j2_distance::J2DistanceParameters),
}

impl LawConfig {
    /// Registry names of every law, for error messages and `satflock scenarios`.
    pub const NAMES: &'static [&'static str] = &["none", "hold", "bifurcating", "j2-distance"];

    /// Builds the law, checking its parameters.
    pub fn build(&self) -> Result<Box<dyn GuidanceLaw>, LawError> {
        Ok(match self {
            LawConfig::None(_) => Box::new(free_drift::FreeDrift),
            LawConfig::Hold(p) => Box::new(hold::Hold::new(p.clone())?),
            LawConfig::Bifurcating(p) => Box::new(bifurcating::Bifurcating::new(p.clone())?),
            LawConfig::J2Distance(p) => Box::new(j2_distance::J2Distance::new(p.clone())?),
        })
    }
}
