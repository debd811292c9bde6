//! Guidance laws and their registry.
//!
//! A law implements [`crate::swarm::GuidanceLaw`] (wrapped as a [`crate::swarm::Law`] for the engine).
//! [`LawConfig`] is a `[law]` table of a scenario file: one variant per built-in law, each with its own
//! parameter table, and [`LawConfig::Registered`] for a law a program registered in the open
//! [`LawRegistry`] (module [`registry`]: a name and a builder from the law's typed parameters;
//! `docs/writing-a-law.md`). Adding a built-in law means a module here and a variant of [`LawConfig`];
//! adding a law of your own means registering it; the engine does not change either way.
//!
//! | name | module | what it does |
//! | --- | --- | --- |
//! | `none` | [`free_drift`] | no control: free drift under the truth dynamics |
//! | `hold` | [`hold`] | PD hold of each satellite's slot (its relative position when the law starts) |
//! | `bifurcating` | [`bifurcating`] | Gao et al. 2022 bifurcating potential field: formation, collision avoidance, damping |
//! | `j2-distance` | [`j2_distance`] | Takahashi–Sakai distance-based stabiliser under J2 (main or opposing), with centralised DT grouping |
//! | `equilibrium-shaping` | [`equilibrium_shaping`] | Nag–Summerer behaviour-based scatter under threat warnings: equilibrium-shaped velocity fields tracked on HCW, four strategies |
//! | `differential-drag` | [`differential_drag`] | propellant-free along-track phasing by switching each satellite's drag attitude (Leonard-style bang-bang on the phase plane; ours) |
//! | `pigeon` | [`pigeon`] | Qiu et al. pigeon-flock formation in the y–z plane with random egalitarian/hierarchical pattern switching, obstacles, radial PD, saturated CW thrust |

pub mod bifurcating;
pub mod differential_drag;
pub mod equilibrium_shaping;
pub mod free_drift;
pub mod hold;
pub mod j2_distance;
pub mod pigeon;
pub mod registry;

pub use registry::{LawRegistry, RegisteredLaw, RegistryError};

use serde::de::Error as _;
use serde::ser::SerializeMap as _;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::swarm::{Law, LawError, LawParameters};

/// The laws a scenario can name, with their parameters (the `[law]` table of a scenario file; the key
/// `name` selects the law): the built-in laws, and the laws registered in the process's
/// [`LawRegistry`] ([`LawConfig::Registered`]).
///
/// Deserialise it through the `Deserialize` trait (`toml::from_str`, `<LawConfig as
/// Deserialize>::deserialize`): the associated function `LawConfig::deserialize` (serde's derive for
/// the built-in variants) knows the built-in laws only.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "name", rename_all = "kebab-case", remote = "Self")]
pub enum LawConfig {
    /// No control.
    None(free_drift::FreeDriftParameters),
    /// PD slot hold.
    Hold(hold::HoldParameters),
    /// Bifurcating potential field (Gao et al. 2022).
    Bifurcating(bifurcating::BifurcatingParameters),
    /// Takahashi–Sakai distance-based stabiliser under J2.
    J2Distance(j2_distance::J2DistanceParameters),
    /// Behaviour-based scatter by equilibrium shaping (Nag & Summerer 2013). Boxed: its table is large.
    EquilibriumShaping(Box<equilibrium_shaping::EquilibriumShapingParameters>),
    /// Pigeon-flock formation with interaction-pattern switching (Qiu et al.). Boxed: its table is large.
    Pigeon(Box<pigeon::PigeonParameters>),
    /// Along-track phasing by differential drag (ours).
    DifferentialDrag(differential_drag::DifferentialDragParameters),
    /// A law registered in the process's [`LawRegistry`] (not a built-in).
    #[serde(skip)]
    Registered(RegisteredLaw),
}

impl Serialize for LawConfig {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            LawConfig::Registered(law) => {
                let mut map = serializer.serialize_map(Some(law.table().len() + 1))?;
                map.serialize_entry("name", law.name())?;
                for (key, value) in law.table() {
                    map.serialize_entry(key, value)?;
                }
                map.end()
            }
            // serde's derive for the built-in variants (`remote = "Self"`).
            builtin => LawConfig::serialize(builtin, serializer),
        }
    }
}

impl<'de> Deserialize<'de> for LawConfig {
    /// A built-in law's table, or a law registered in the process's [`LawRegistry`]; any other name is
    /// refused, naming every law the registry knows.
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let mut table = toml::Table::deserialize(deserializer)?;
        let message = |e: toml::de::Error| D::Error::custom(e.message());
        let name = match table.get("name") {
            Some(toml::Value::String(name)) if !LawConfig::NAMES.contains(&name.as_str()) => {
                name.clone()
            }
            // A built-in law, or a table without a (string) name: serde's derive says what is wrong.
            _ => return LawConfig::deserialize(table).map_err(message),
        };
        let registry = LawRegistry::installed();
        table.remove("name");
        match registry.parse_registered(&name, table) {
            Some(law) => law.map(LawConfig::Registered).map_err(message),
            None => Err(D::Error::custom(format!(
                "unknown variant `{name}`, expected one of {}",
                registry
                    .names()
                    .iter()
                    .map(|n| format!("`{n}`"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ))),
        }
    }
}

impl LawConfig {
    /// Names of the built-in laws (with the registered ones: [`LawRegistry::names`]).
    pub const NAMES: &'static [&'static str] = &[
        "none",
        "hold",
        "bifurcating",
        "j2-distance",
        "equilibrium-shaping",
        "pigeon",
        "differential-drag",
    ];

    /// Builds the law, checking its parameters.
    pub fn build(&self) -> Result<Law, LawError> {
        Ok(match self {
            LawConfig::None(_) => Law::new(free_drift::FreeDrift),
            LawConfig::Hold(p) => Law::new(hold::Hold::new(p.clone())?),
            LawConfig::Bifurcating(p) => Law::new(bifurcating::Bifurcating::new(p.clone())?),
            LawConfig::J2Distance(p) => Law::new(j2_distance::J2Distance::new(p.clone())?),
            LawConfig::EquilibriumShaping(p) => {
                Law::new(equilibrium_shaping::EquilibriumShaping::new((**p).clone())?)
            }
            LawConfig::Pigeon(p) => Law::new(pigeon::Pigeon::new((**p).clone())?),
            LawConfig::DifferentialDrag(p) => {
                Law::new(differential_drag::DifferentialDrag::new(p.clone())?)
            }
            LawConfig::Registered(law) => law.build()?,
        })
    }

    /// The registry name of the law.
    pub fn name(&self) -> &'static str {
        match self {
            LawConfig::None(_) => "none",
            LawConfig::Hold(_) => "hold",
            LawConfig::Bifurcating(_) => "bifurcating",
            LawConfig::J2Distance(_) => "j2-distance",
            LawConfig::EquilibriumShaping(_) => "equilibrium-shaping",
            LawConfig::Pigeon(_) => "pigeon",
            LawConfig::DifferentialDrag(_) => "differential-drag",
            LawConfig::Registered(law) => law.name(),
        }
    }

    /// The typed parameter set, for a `set-law-parameters` event of the running law.
    pub fn into_parameters(self) -> LawParameters {
        match self {
            LawConfig::None(p) => LawParameters::new(p),
            LawConfig::Hold(p) => LawParameters::new(p),
            LawConfig::Bifurcating(p) => LawParameters::new(p),
            LawConfig::J2Distance(p) => LawParameters::new(p),
            LawConfig::EquilibriumShaping(p) => LawParameters::new(*p),
            LawConfig::Pigeon(p) => LawParameters::new(*p),
            LawConfig::DifferentialDrag(p) => LawParameters::new(p),
            LawConfig::Registered(law) => law.parameters(),
        }
    }
}
