//! The force set as written in a scenario's `[dynamics.forces]` table or a `propagate --forces` file:
//! serde structures mirroring the TOML tables, every dimensional key with its unit, and the typed error
//! a model's parameters give when they are out of range ([`ForceConfigError`]: key, value, allowed).

use serde::{Deserialize, Serialize};

use super::properties::PropertiesConfig;

/// `[dynamics.forces]` (or a whole `--forces` file): gravity, and drag, SRP and third bodies when their
/// tables are present.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForcesConfig {
    /// `[gravity]` (default: J2).
    #[serde(default)]
    pub gravity: GravityConfig,
    /// `[drag]` (absent: no drag).
    pub drag: Option<DragConfig>,
    /// `[srp]` (absent: no solar radiation pressure).
    pub srp: Option<SrpConfig>,
    /// `[third_body]` (absent: no third body).
    pub third_body: Option<ThirdBodyConfig>,
    /// `[satellite]`: the physical properties of the one satellite of `satflock propagate` (in a
    /// scenario these are `[satellites]` keys, and this table is refused).
    pub satellite: Option<PropertiesConfig>,
}

/// Which gravity field model acts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum GravityModelName {
    /// Point mass (Keplerian).
    PointMass,
    /// Point mass + J2 (the default; the same bits as `[dynamics] model = "j2"`).
    #[default]
    J2,
    /// Point mass + zonal harmonics J2..Jn.
    Zonal,
}

/// `[gravity]`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GravityConfig {
    /// `point-mass`, `j2` (default) or `zonal`.
    #[serde(default)]
    pub model: GravityModelName,
    /// Zonal only: the highest degree n of J2..Jn from the built-in EGM96 values (2 to 20; default 6
    /// when `zonal_coefficients` is absent).
    pub degree: Option<usize>,
    /// Zonal only: J2..Jn themselves (unnormalised, dimensionless), overriding the built-in values.
    pub zonal_coefficients: Option<Vec<f64>>,
}

/// Which density model the drag force uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum AtmosphereName {
    /// One exponential layer with explicit reference density, altitude and scale height.
    Exponential,
    /// The piecewise exponential table of Vallado, *Fundamentals of Astrodynamics*, Table 8-4.
    ExponentialTable,
    /// Harris–Priester with the Montenbruck & Gill table (Satellite Orbits, Table 3.1).
    HarrisPriester,
}

/// Which altitude the density is evaluated at.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum AltitudeName {
    /// Height above a sphere of the Earth's equatorial radius (default).
    #[default]
    Spherical,
    /// Geodetic height above the WGS-84 ellipsoid.
    Geodetic,
}

/// `[drag]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DragConfig {
    /// The density model.
    pub atmosphere: AtmosphereName,
    /// Exponential: density at the reference altitude \[kg/m^3\].
    pub reference_density_kg_per_m3: Option<f64>,
    /// Exponential: the reference altitude \[m\].
    pub reference_altitude_m: Option<f64>,
    /// Exponential: the scale height \[m\].
    pub scale_height_m: Option<f64>,
    /// Harris–Priester: the cosine exponent n (2 low inclination to 6 polar; default 4).
    pub cosine_exponent: Option<f64>,
    /// Harris–Priester: the lag of the diurnal bulge behind the Sun \[deg\] (default 30).
    pub lag_deg: Option<f64>,
    /// Whether the atmosphere co-rotates with the Earth (default true).
    #[serde(default = "yes")]
    pub corotation: bool,
    /// `spherical` (default) or `geodetic`.
    #[serde(default)]
    pub altitude: AltitudeName,
}

impl DragConfig {
    /// The `[drag]` table of `atmosphere` with its defaults: co-rotating air, spherical altitude, no
    /// atmosphere parameter given (an exponential layer still needs its three).
    pub fn new(atmosphere: AtmosphereName) -> Self {
        Self {
            atmosphere,
            reference_density_kg_per_m3: None,
            reference_altitude_m: None,
            scale_height_m: None,
            cosine_exponent: None,
            lag_deg: None,
            corotation: true,
            altitude: AltitudeName::Spherical,
        }
    }
}

fn yes() -> bool {
    true
}

/// The Earth's shadow model of solar radiation pressure.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShadowName {
    /// Always lit.
    None,
    /// A cylinder of the Earth's radius behind it (lit or not).
    Cylindrical,
    /// Umbra and penumbra cones, the lit fraction of the solar disc (default).
    #[default]
    Conical,
}

/// `[srp]`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SrpConfig {
    /// `none`, `cylindrical` or `conical` (default).
    #[serde(default)]
    pub shadow: ShadowName,
}

/// A third body whose point mass acts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BodyName {
    /// The Sun.
    Sun,
    /// The Moon.
    Moon,
}

/// `[third_body]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThirdBodyConfig {
    /// The bodies, each at most once.
    pub bodies: Vec<BodyName>,
}

/// A force model's parameter out of its range: the key (relative to the force table, e.g.
/// `drag.scale_height_m`), the value given and what is allowed. The scenario layer adds the file.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("`{key}` = {value}: {allowed}")]
pub struct ForceConfigError {
    /// The key, dotted from the force table (`drag.scale_height_m`).
    pub key: String,
    /// The value given, as written back.
    pub value: String,
    /// What is allowed.
    pub allowed: String,
}

impl ForceConfigError {
    /// An error for `key` with `value` and what is `allowed`.
    pub fn new(key: impl Into<String>, value: impl ToString, allowed: impl Into<String>) -> Self {
        Self {
            key: key.into(),
            value: value.to_string(),
            allowed: allowed.into(),
        }
    }
}

impl From<ForceConfigError> for crate::invalid::Invalid {
    /// The force model's parameter error as the one typed error: `VALUE is out of range (allowed: …)`.
    fn from(e: ForceConfigError) -> Self {
        Self::range(e.key, e.value, e.allowed)
    }
}

/// `value` if it is finite and inside `(low, high]`-style bounds given by `ok`, else the error for `key`.
pub(crate) fn check(
    key: &str,
    value: f64,
    ok: impl Fn(f64) -> bool,
    allowed: &str,
) -> Result<f64, ForceConfigError> {
    if value.is_finite() && ok(value) {
        Ok(value)
    } else {
        Err(ForceConfigError::new(key, value, allowed))
    }
}

/// Largest force file read \[bytes\]: a force table is a few hundred bytes; anything near this is not
/// one.
pub const MAX_FORCES_FILE_BYTES: u64 = 1 << 20;

/// Why a force file could not be read or parsed.
#[derive(Debug, thiserror::Error)]
pub enum ForcesFileError {
    /// Not a regular file, too large, or unreadable.
    #[error("{path}: {reason}")]
    Read {
        /// The file.
        path: String,
        /// What went wrong.
        reason: String,
    },
    /// Not TOML of the force table (an unknown key, a wrong type).
    #[error("{path}: {message}")]
    Parse {
        /// The file.
        path: String,
        /// The parser's message (naming the key).
        message: String,
    },
    /// A value out of range.
    #[error("{path}: {error}")]
    Invalid {
        /// The file.
        path: String,
        /// The key, value and allowed range.
        error: ForceConfigError,
    },
}

impl ForcesConfig {
    /// Parses a force table from TOML text; `source` names it in errors.
    pub fn from_toml(text: &str, source: &str) -> Result<Self, ForcesFileError> {
        toml::from_str(text).map_err(|e| ForcesFileError::Parse {
            path: source.to_owned(),
            message: e.to_string(),
        })
    }

    /// Reads and parses a force file (`satflock propagate --forces`): a regular file of at most
    /// [`MAX_FORCES_FILE_BYTES`].
    pub fn from_file(path: &std::path::Path) -> Result<Self, ForcesFileError> {
        let shown = path.display().to_string();
        let read = |reason: String| ForcesFileError::Read {
            path: shown.clone(),
            reason,
        };
        let text = crate::input_file::read_to_string(path, MAX_FORCES_FILE_BYTES)
            .map_err(|e| read(e.to_string()))?;
        Self::from_toml(&text, &shown)
    }

    /// The physical properties of the satellite of `[satellite]` for the forces of this table: a mass
    /// and a drag area are required when drag acts, a mass and an SRP area when SRP acts (C_d defaults
    /// to 2.2 and C_r to 1.5); keys no force reads are refused.
    pub fn satellite_properties(&self) -> Result<super::PhysicalProperties, ForceConfigError> {
        let given = self.satellite.clone().unwrap_or_default();
        let drag = self.drag.is_some();
        let srp = self.srp.is_some();
        let pick = |name: &str, value: Option<f64>, used: bool, default: Option<f64>| match (
            value, used, default,
        ) {
            (Some(v), false, _) => Err(ForceConfigError::new(
                format!("satellite.{name}"),
                v,
                "a key only when a force reads it (drag keys with [drag], SRP keys with [srp])",
            )),
            (Some(v), true, _) => Ok(v),
            (None, false, _) => Ok(0.0),
            (None, true, Some(d)) => Ok(d),
            (None, true, None) => Err(ForceConfigError::new(
                format!("satellite.{name}"),
                "missing",
                "a value: a force of the table reads it",
            )),
        };
        let mass_kg = match (given.mass_kg, drag || srp) {
            (Some(m), _) => m,
            (None, false) => 1.0,
            (None, true) => pick("mass_kg", None, true, None)?,
        };
        let properties = super::PhysicalProperties {
            mass_kg,
            drag_area_m2: pick("drag_area_m2", given.drag_area_m2, drag, None)?,
            drag_coefficient: pick("drag_coefficient", given.drag_coefficient, drag, Some(2.2))?,
            srp_area_m2: pick("srp_area_m2", given.srp_area_m2, srp, None)?,
            reflectivity_coefficient: pick(
                "reflectivity_coefficient",
                given.reflectivity_coefficient,
                srp,
                Some(1.5),
            )?,
        };
        properties.validate("satellite.")?;
        Ok(properties)
    }
}
