//! The open law registry: the laws a scenario's `[law]` table (and a `switch-law` event, a controller
//! file) can name. [`LawRegistry::builtin`] holds the built-in laws ([`super::LawConfig`]); a program
//! adds its own law with [`LawRegistry::register`] (a name and a builder from the law's typed
//! parameters) and makes the registry the process's with [`LawRegistry::install`]. From then on a
//! scenario file naming the law is parsed, validated, run, compared and sampled by a campaign exactly as
//! one naming a built-in: its table is deserialised into the law's parameters (unknown keys and wrong
//! types refused at parse time), the builder checks their ranges (refused at load time, naming the key
//! `law` or the event), and a `set-law-parameters` event merges its keys into the table and hands the
//! law the result.
//!
//! The registry is process-wide because a scenario file is parsed without context (`Scenario::load` and
//! the serde schema behind it); install it once at start, before loading any scenario
//! (`satflock_cli::main_with` does).
//!
//! ```
//! use satflock::guidance::hold::{Hold, HoldParameters};
//! use satflock::guidance::LawRegistry;
//!
//! // A "law" of our own: here the built-in hold under another name, with its own parameter table.
//! let mut registry = LawRegistry::builtin();
//! registry
//!     .register("my-hold", |p: HoldParameters| Hold::new(p).map(Renamed))
//!     .unwrap();
//! assert!(registry.names().contains(&"my-hold"));
//!
//! # use satflock::swarm::{GuidanceLaw, LawContext, LawError, SatelliteView};
//! # use nalgebra::Vector3;
//! # struct Renamed(Hold);
//! # impl GuidanceLaw for Renamed {
//! #     type State = <Hold as GuidanceLaw>::State;
//! #     type Parameters = HoldParameters;
//! #     fn name(&self) -> &'static str { "my-hold" }
//! #     fn command(&self, s: &SatelliteView<'_>, st: &Self::State, c: &LawContext) -> Vector3<f64> {
//! #         self.0.command(s, st, c)
//! #     }
//! #     fn set_parameters(&mut self, p: &HoldParameters) -> Result<(), LawError> {
//! #         self.0.set_parameters(p)
//! #     }
//! # }
//! ```

use std::marker::PhantomData;
use std::sync::{Arc, RwLock};

use serde::de::DeserializeOwned;
use thiserror::Error;

use super::LawConfig;
use crate::swarm::{GuidanceLaw, Law, LawError, LawParameters};

/// Why a law could not be registered.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum RegistryError {
    /// The name is a built-in law's or was registered before.
    #[error("law `{name}` is already registered (a built-in law or an earlier registration)")]
    NameTaken {
        /// The name.
        name: String,
    },
    /// The name is not one a scenario file can write.
    #[error("law name `{name}` is not valid (allowed: lowercase ASCII letters, digits and `-`, starting with a letter)")]
    InvalidName {
        /// The name.
        name: String,
    },
}

/// The laws a scenario can name: the built-in ones and those a program registered.
#[derive(Clone, Default)]
pub struct LawRegistry {
    /// The registered laws (after the built-ins), in registration order.
    laws: Vec<Arc<Entry>>,
}

/// Deserialises a parameter table (without `name`) into a law's typed parameters.
type ParameterParser =
    Box<dyn Fn(&toml::Table) -> Result<Arc<dyn ParsedLaw>, toml::de::Error> + Send + Sync>;

/// A registered law: its name and how to read its parameter table.
struct Entry {
    name: &'static str,
    /// Deserialises the parameter table (without `name`) into the law's typed parameters.
    parse: ParameterParser,
}

/// A registered law's typed parameters, with its builder.
trait ParsedLaw: Send + Sync {
    fn build(&self) -> Result<Law, LawError>;
    fn parameters(&self) -> LawParameters;
}

struct Parsed<P, L, F> {
    parameters: P,
    build: Arc<F>,
    law: PhantomData<fn() -> L>,
}

impl<P, L, F> ParsedLaw for Parsed<P, L, F>
where
    P: Clone + Send + Sync + 'static,
    L: GuidanceLaw<Parameters = P>,
    F: Fn(P) -> Result<L, LawError> + Send + Sync + 'static,
{
    fn build(&self) -> Result<Law, LawError> {
        (self.build)(self.parameters.clone()).map(Law::new)
    }

    fn parameters(&self) -> LawParameters {
        LawParameters::new(self.parameters.clone())
    }
}

/// The registry [`LawRegistry::install`] made the process's (`None`: the built-ins only).
static INSTALLED: RwLock<Option<Arc<LawRegistry>>> = RwLock::new(None);

impl LawRegistry {
    /// The built-in laws only ([`LawConfig::NAMES`]).
    pub fn builtin() -> Self {
        Self::default()
    }

    /// Registers the law `name`: a `[law]` table with `name = "NAME"` is deserialised into `P` (the
    /// table without `name`; declare `P` with `#[serde(deny_unknown_fields)]` so a misspelt key is
    /// refused) and `build` makes the law from it, checking the values (return
    /// [`LawError::InvalidParameters`] naming the key and the allowed range). The law's
    /// [`GuidanceLaw::name`] must be `name`. A `set-law-parameters` event's merged table reaches the
    /// running law's [`GuidanceLaw::set_parameters`] as a `P`, after `build` accepted it.
    pub fn register<P, L, F>(
        &mut self,
        name: &'static str,
        build: F,
    ) -> Result<&mut Self, RegistryError>
    where
        P: DeserializeOwned + Clone + Send + Sync + 'static,
        L: GuidanceLaw<Parameters = P>,
        F: Fn(P) -> Result<L, LawError> + Send + Sync + 'static,
    {
        let valid = name.starts_with(|c: char| c.is_ascii_lowercase())
            && name
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-');
        if !valid {
            return Err(RegistryError::InvalidName { name: name.into() });
        }
        if self.contains(name) {
            return Err(RegistryError::NameTaken { name: name.into() });
        }
        let build = Arc::new(build);
        let parse = move |table: &toml::Table| -> Result<Arc<dyn ParsedLaw>, toml::de::Error> {
            let parameters: P = table.clone().try_into()?;
            Ok(Arc::new(Parsed {
                parameters,
                build: build.clone(),
                law: PhantomData::<fn() -> L>,
            }))
        };
        self.laws.push(Arc::new(Entry {
            name,
            parse: Box::new(parse),
        }));
        Ok(self)
    }

    /// Every law's name: the built-ins, then the registered laws in registration order.
    pub fn names(&self) -> Vec<&'static str> {
        LawConfig::NAMES
            .iter()
            .copied()
            .chain(self.laws.iter().map(|e| e.name))
            .collect()
    }

    /// Whether a law of this name is built in or registered.
    pub fn contains(&self, name: &str) -> bool {
        LawConfig::NAMES.contains(&name) || self.entry(name).is_some()
    }

    fn entry(&self, name: &str) -> Option<&Arc<Entry>> {
        self.laws.iter().find(|e| e.name == name)
    }

    /// Makes this registry the process's: every scenario, controller file and law event parsed from now
    /// on may name its laws. Replaces a registry installed before.
    pub fn install(self) {
        let mut installed = INSTALLED.write().unwrap_or_else(|e| e.into_inner());
        *installed = Some(Arc::new(self));
    }

    /// The process's registry: the one last installed, or the built-ins only.
    pub fn installed() -> Arc<LawRegistry> {
        let installed = INSTALLED.read().unwrap_or_else(|e| e.into_inner());
        installed
            .clone()
            .unwrap_or_else(|| Arc::new(LawRegistry::builtin()))
    }

    /// A registered (not built-in) law's configuration from its parameter table (without `name`):
    /// `None` when no law of that name is registered, else the table deserialised into its parameters.
    pub(crate) fn parse_registered(
        &self,
        name: &str,
        table: toml::Table,
    ) -> Option<Result<RegisteredLaw, toml::de::Error>> {
        let entry = self.entry(name)?;
        Some((entry.parse)(&table).map(|parsed| RegisteredLaw {
            name: entry.name,
            table,
            parsed,
        }))
    }
}

impl std::fmt::Debug for LawRegistry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LawRegistry")
            .field("names", &self.names())
            .finish()
    }
}

/// A registered law's `[law]` table (a variant of [`LawConfig`]): its name, its parameter table as
/// written (without `name`) and its typed parameters, deserialised when the table was read.
#[derive(Clone)]
pub struct RegisteredLaw {
    name: &'static str,
    table: toml::Table,
    parsed: Arc<dyn ParsedLaw>,
}

impl RegisteredLaw {
    /// The law's registry name.
    pub fn name(&self) -> &'static str {
        self.name
    }

    /// The parameter table as written (without `name`).
    pub fn table(&self) -> &toml::Table {
        &self.table
    }

    /// Builds the law with the registered builder, which checks the parameters.
    pub fn build(&self) -> Result<Law, LawError> {
        let law = self.parsed.build()?;
        if law.name() != self.name {
            return Err(LawError::invalid(
                self.name,
                crate::invalid::Invalid::new(
                    "name",
                    format!("`{}`", law.name()),
                    format!("is what the law registered as `{}` calls itself", self.name),
                    "GuidanceLaw::name must return the registered name",
                ),
            ));
        }
        Ok(law)
    }

    /// The typed parameters, for a `set-law-parameters` event of the running law.
    pub fn parameters(&self) -> LawParameters {
        self.parsed.parameters()
    }
}

impl std::fmt::Debug for RegisteredLaw {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RegisteredLaw")
            .field("name", &self.name)
            .field("table", &self.table)
            .finish()
    }
}

impl PartialEq for RegisteredLaw {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name && self.table == other.table
    }
}
