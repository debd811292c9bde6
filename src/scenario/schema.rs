//! The scenario file format: serde structures mirroring the TOML tables. Every dimensional key names its
//! unit. Unknown keys are refused. Range checks live in the private `validate` module.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::guidance::LawConfig;
use crate::integrate::IntegratorMethod;
use crate::output::OutputFormat;
use crate::swarm::LimitKind;

/// A whole scenario file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScenarioFile {
    /// Short name (used in outputs).
    pub name: String,
    /// What the scenario is, and which values come from a paper and which are defaults.
    #[serde(default)]
    pub description: String,
    /// Seed of every random draw.
    pub seed: u64,
    /// The instant of t = 0, ISO 8601 UTC (`"2026-03-20T12:00:00Z"`); absent: the epoch of the orbit
    /// files the scenario names (they must agree), else [`crate::time::DEFAULT_EPOCH_UTC`].
    #[serde(default)]
    pub epoch_utc: Option<String>,
    /// Length of the run \[s\].
    pub duration_s: f64,
    /// Recording cadence \[s\].
    pub record_interval_s: f64,
    /// Truth dynamics and integration.
    #[serde(default)]
    pub dynamics: DynamicsSection,
    /// Earth constants (defaults: WGS 84 / EGM96 values of [`crate::orbit::EarthModel::WGS84_EGM96`]).
    #[serde(default)]
    pub earth: EarthSection,
    /// Reference orbit and LVLH origin.
    pub reference: ReferenceSection,
    /// Control timing.
    #[serde(default)]
    pub control: ControlSection,
    /// The satellites.
    pub satellites: SatellitesSection,
    /// The guidance law (`name` selects it; other keys are its parameters).
    pub law: LawConfig,
    /// Sensors and links.
    #[serde(default)]
    pub sensing: SensingSection,
    /// Kinematic threats (`[[threats]]`), straight lines in the Hill frame.
    #[serde(default)]
    pub threats: Vec<ThreatSection>,
    /// Static spherical obstacles (`[[obstacles]]`) in the Hill frame.
    #[serde(default)]
    pub obstacles: Vec<ObstacleSection>,
    /// The event timeline.
    #[serde(default)]
    pub events: Vec<EventSection>,
    /// The conjunction monitor (`[conjunctions]`; absent: none).
    #[serde(default)]
    pub conjunctions: Option<ConjunctionsSection>,
    /// What to write.
    #[serde(default)]
    pub output: OutputSection,
}

/// Truth model names of the `[dynamics] model` key.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum ModelName {
    /// Inertial point mass + J2 (default).
    #[default]
    J2,
    /// Inertial point mass.
    TwoBody,
    /// Hill–Clohessy–Wiltshire linear relative dynamics.
    Hcw,
    /// Schweighart–Sedwick J2-linearised relative dynamics.
    J2Linear,
    /// Kinematic: Hill positions follow the law's commanded velocity (velocity-field laws only).
    Kinematic,
}

/// `[dynamics]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DynamicsSection {
    /// Truth model (default `j2`).
    #[serde(default)]
    pub model: ModelName,
    /// Integrator (default `rk4`).
    #[serde(default = "default_integrator")]
    pub integrator: IntegratorMethod,
    /// RK4 step, or longest step of the adaptive method \[s\] (default 1).
    #[serde(default = "default_step")]
    pub step_s: f64,
    /// Relative tolerance of the adaptive method (default 1e-10).
    #[serde(default = "default_rtol")]
    pub rtol: f64,
    /// Absolute tolerance of the adaptive method (default 1e-6, in m and m/s).
    #[serde(default = "default_atol")]
    pub atol: f64,
    /// A satellite farther than this from the LVLH origin stops the run \[m\] (default 1e6).
    #[serde(default = "default_max_distance")]
    pub max_distance_m: f64,
    /// Process (acceleration) noise, standard deviation per satellite and Hill axis \[m/s^2\], held over
    /// a control period or integration step (default 0; dynamic models only).
    #[serde(default)]
    pub process_noise_mps2: f64,
    /// `[dynamics.forces]`: the force set of inertial truth (gravity model, drag, SRP, third bodies);
    /// absent: the gravity `model` names (`j2` or `two-body`) alone.
    pub forces: Option<crate::dynamics::ForcesConfig>,
}

fn default_integrator() -> IntegratorMethod {
    IntegratorMethod::Rk4
}
fn default_step() -> f64 {
    1.0
}
fn default_rtol() -> f64 {
    1e-10
}
fn default_atol() -> f64 {
    1e-6
}
fn default_max_distance() -> f64 {
    1e6
}

impl Default for DynamicsSection {
    fn default() -> Self {
        Self {
            model: ModelName::default(),
            integrator: default_integrator(),
            step_s: default_step(),
            rtol: default_rtol(),
            atol: default_atol(),
            max_distance_m: default_max_distance(),
            process_noise_mps2: 0.0,
            forces: None,
        }
    }
}

/// `[conjunctions]`: report every encounter of two satellites, or of a satellite and a threat or
/// obstacle, whose miss distance falls below the threshold (`conjunctions.csv` / `.parquet`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConjunctionsSection {
    /// Miss-distance threshold, centre to centre \[m\] (finite, >= 0).
    pub threshold_m: f64,
}

/// `[earth]`: optional overrides of the Earth constants.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EarthSection {
    /// Gravitational parameter \[m^3/s^2\].
    pub mu_m3_s2: Option<f64>,
    /// Equatorial radius \[m\].
    pub equatorial_radius_m: Option<f64>,
    /// Second zonal harmonic (unnormalised), dimensionless.
    pub j2: Option<f64>,
}

/// `[reference]`: the reference orbit at t = 0, by classical elements or by an ECI state, and the LVLH
/// origin.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceSection {
    /// Semi-major axis \[m\] (give this or `altitude_m`).
    pub semi_major_axis_m: Option<f64>,
    /// Altitude of the semi-major axis above the equatorial radius \[m\] (a = R + altitude).
    pub altitude_m: Option<f64>,
    /// Eccentricity (default 0).
    pub eccentricity: Option<f64>,
    /// Inclination \[deg\].
    pub inclination_deg: Option<f64>,
    /// Right ascension of the ascending node \[deg\] (default 0).
    pub raan_deg: Option<f64>,
    /// Argument of perigee \[deg\] (default 0).
    pub arg_perigee_deg: Option<f64>,
    /// True anomaly \[deg\] (default 0).
    pub true_anomaly_deg: Option<f64>,
    /// ECI position \[m\] (instead of elements; then `velocity_eci_mps` too).
    pub position_eci_m: Option<[f64; 3]>,
    /// ECI velocity \[m/s\].
    pub velocity_eci_mps: Option<[f64; 3]>,
    /// The inertial state at the scenario epoch, EME2000, `[x_m, y_m, z_m, vx_mps, vy_mps, vz_mps]`
    /// (instead of elements).
    pub state_eme2000: Option<[f64; 6]>,
    /// A CCSDS OEM file holding one object: its state at the scenario epoch.
    pub oem: Option<String>,
    /// A CCSDS OMM file holding one element set: its SGP4 state at the scenario epoch.
    pub omm: Option<String>,
    /// A TLE, its two lines (or a title line and the two): its SGP4 state at the scenario epoch.
    pub tle: Option<Vec<String>>,
    /// LVLH origin: `virtual` (default) or `member`.
    #[serde(default)]
    pub origin: OriginName,
    /// Index of the member satellite that is the origin (with `origin = "member"`).
    pub origin_member: Option<usize>,
    /// The virtual reference orbit's mass \[kg\], for drag and SRP (absent: the swarm's mean; likewise
    /// the four keys below).
    pub mass_kg: Option<f64>,
    /// The virtual reference orbit's drag reference area \[m^2\].
    pub drag_area_m2: Option<f64>,
    /// The virtual reference orbit's drag coefficient.
    pub drag_coefficient: Option<f64>,
    /// The virtual reference orbit's SRP area \[m^2\].
    pub srp_area_m2: Option<f64>,
    /// The virtual reference orbit's reflectivity coefficient.
    pub reflectivity_coefficient: Option<f64>,
}

/// A property of every satellite: one value for all, one per satellite (in id order), or drawn.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum PerSatellite {
    /// The same value for every satellite.
    All(f64),
    /// One value per satellite, `count` of them.
    Each(Vec<f64>),
    /// Drawn for each satellite from the run's random streams (seed, property, satellite).
    Drawn(PropertyDistribution),
}

impl<'de> Deserialize<'de> for PerSatellite {
    /// A number, a list of numbers or a distribution table; anything else is an error saying so
    /// (an untagged enum would only say that no variant matched).
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = PerSatellite;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(
                    "a number, a list of one number per satellite, or a distribution table \
                     { distribution = \"uniform\" | \"normal\", ... }",
                )
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<PerSatellite, E> {
                Ok(PerSatellite::All(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<PerSatellite, E> {
                Ok(PerSatellite::All(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<PerSatellite, E> {
                Ok(PerSatellite::All(v as f64))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                seq: A,
            ) -> Result<PerSatellite, A::Error> {
                Vec::<f64>::deserialize(serde::de::value::SeqAccessDeserializer::new(seq))
                    .map(PerSatellite::Each)
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> Result<PerSatellite, A::Error> {
                PropertyDistribution::deserialize(serde::de::value::MapAccessDeserializer::new(map))
                    .map(PerSatellite::Drawn)
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}

/// The distribution a property is drawn from, in the property's unit.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "distribution", rename_all = "kebab-case", deny_unknown_fields)]
pub enum PropertyDistribution {
    /// Uniform on `[min, max]`.
    Uniform {
        /// Smallest value.
        min: f64,
        /// Largest value.
        max: f64,
    },
    /// Normal of `mean` and standard deviation `sigma`, truncated to `[min, max]` (draws outside are
    /// drawn again).
    Normal {
        /// Mean.
        mean: f64,
        /// Standard deviation.
        sigma: f64,
        /// Smallest value kept.
        min: f64,
        /// Largest value kept.
        max: f64,
    },
}

/// LVLH origin names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum OriginName {
    /// The virtual reference orbit.
    #[default]
    Virtual,
    /// A member satellite.
    Member,
}

/// Control timing names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum ControlMode {
    /// Law inside the integrator's right-hand side (default).
    #[default]
    Continuous,
    /// Law every `period_s`, zero-order hold.
    Sampled,
}

/// `[control]`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ControlSection {
    /// `continuous` (default) or `sampled`.
    #[serde(default)]
    pub mode: ControlMode,
    /// Control period \[s\] (sampled mode only; required there).
    pub period_s: Option<f64>,
}

/// `[satellites]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SatellitesSection {
    /// Number of satellites (for `list` and `csv` initial states, must match the rows).
    pub count: usize,
    /// Mass of each satellite \[kg\] (a value, a list or a distribution; or a column of
    /// `properties_file`).
    pub mass_kg: Option<PerSatellite>,
    /// Physical radius of each satellite \[m\] (collisions, d_min; default 0; a value, a list or a
    /// distribution).
    pub radius_m: Option<PerSatellite>,
    /// A CSV of per-satellite properties (`sat` then any of `mass_kg`, `drag_area_m2`,
    /// `drag_coefficient`, `srp_area_m2`, `reflectivity_coefficient`, `radius_m`), relative to the
    /// scenario file.
    pub properties_file: Option<String>,
    /// Actuator acceleration limit \[m/s^2\] (absent: unlimited).
    pub max_accel_mps2: Option<f64>,
    /// How the limit applies: `norm` (default) or `per-axis`.
    #[serde(default)]
    pub accel_limit: LimitKind,
    /// Drag reference area of each satellite \[m^2\] (required when drag acts; a value or a list).
    pub drag_area_m2: Option<PerSatellite>,
    /// Drag coefficient C_d of each satellite (default 2.2 when drag acts).
    pub drag_coefficient: Option<PerSatellite>,
    /// Area of each satellite facing the Sun \[m^2\] (required when SRP acts).
    pub srp_area_m2: Option<PerSatellite>,
    /// Reflectivity coefficient C_r of each satellite (default 1.5 when SRP acts).
    pub reflectivity_coefficient: Option<PerSatellite>,
    /// Named drag modes (attitudes) a law may command, name → drag area \[m^2\] (1 to 4 modes, e.g.
    /// `{ low = 0.01, high = 0.035 }`); needs drag in `[dynamics.forces]`. The initial area
    /// (`drag_area_m2`) must be one of them (default: the smallest).
    #[serde(default)]
    pub drag_modes_m2: Option<std::collections::BTreeMap<String, f64>>,
    /// Instead of modes, a continuous range of drag areas `[min, max]` \[m^2\] a law may command.
    pub drag_area_range_m2: Option<[f64; 2]>,
    /// Shortest time between two changes of a satellite's drag area \[s\] (absent: none beyond one
    /// control tick; if given, at least one tick).
    pub drag_min_dwell_s: Option<f64>,
    /// Initial relative states.
    pub initial: InitialSection,
    /// Per-satellite overrides (heterogeneous clusters).
    #[serde(default)]
    pub overrides: Vec<OverrideSection>,
    /// Accept satellites that overlap at t = 0 (centres closer than the sum of their radii, or
    /// coincident). Default `false`: such a start is refused, since every overlapping pair counts as a
    /// collision from the first step.
    #[serde(default)]
    pub allow_initial_overlap: bool,
    /// Accept satellites that start inside an obstacle (closer to its centre than its radius). Default
    /// `false`: such a start is refused, since the obstacle monitor counts an incursion at t = 0.
    #[serde(default)]
    pub allow_start_in_obstacle: bool,
}

/// Frames an explicit list of initial states can be written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum ListFrame {
    /// Hill/RSW: x radial out, y along-track, z orbit normal (default).
    #[default]
    Hill,
    /// Gao o-xyz: x along-track, y minus orbit normal, z toward Earth's centre.
    Gao,
    /// Inertial EME2000 (J2000 mean equator and equinox), at the scenario epoch: the satellite's own
    /// state, not relative to the reference orbit.
    Eme2000,
}

/// Initial relative velocity of randomly placed satellites.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum InitialVelocity {
    /// Zero velocity relative to the rotating LVLH frame (default).
    #[default]
    Zero,
    /// The HCW no-drift condition v_y = −2 n x (bounded relative orbits on HCW dynamics).
    HcwNoDrift,
}

/// `[satellites.initial]`: the initial states, relative to the reference orbit (Hill or Gao frame) or
/// inertial (EME2000 lists and CSV files, OEM, OMM and TLE files).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "distribution", rename_all = "kebab-case", deny_unknown_fields)]
pub enum InitialSection {
    /// Uniform in a ball.
    Sphere {
        /// Radius of the ball \[m\].
        radius_m: f64,
        /// Centre of the ball, Hill frame \[m\] (default origin).
        #[serde(default)]
        center_hill_m: [f64; 3],
        /// Initial velocity (default zero).
        #[serde(default)]
        velocity: InitialVelocity,
    },
    /// Uniform in an axis-aligned box.
    Box {
        /// Edge lengths along Hill x, y, z \[m\].
        size_hill_m: [f64; 3],
        /// Centre of the box, Hill frame \[m\] (default origin).
        #[serde(default)]
        center_hill_m: [f64; 3],
        /// Initial velocity (default zero).
        #[serde(default)]
        velocity: InitialVelocity,
    },
    /// Uniform in a spherical shell.
    Shell {
        /// Inner radius \[m\].
        inner_radius_m: f64,
        /// Outer radius \[m\].
        outer_radius_m: f64,
        /// Centre, Hill frame \[m\] (default origin).
        #[serde(default)]
        center_hill_m: [f64; 3],
        /// Initial velocity (default zero).
        #[serde(default)]
        velocity: InitialVelocity,
    },
    /// Averaged-J2 relative orbital parameters C₁…C₆ (Takahashi & Sakai; our reconstruction `docs/methods/j2-distance.md` §3, §10.1), drawn
    /// independently and uniformly per satellite: |C₁| ≤ `c1_max_m`, |C₄| ≤ `c4_max_m`, and C₂, C₃, C₅, C₆
    /// within ±`amplitude_max_m`; converted to Hill states with the Schweighart–Sedwick model of the
    /// reference orbit (`docs/methods/j2-distance.md` §3.2). The member origin (if any) sits at C = 0 (the reference satellite).
    AveragedJ2 {
        /// Bound of |C₁| \[m\].
        c1_max_m: f64,
        /// Bound of |C₄| \[m\].
        c4_max_m: f64,
        /// Bound of |C₂|, |C₃|, |C₅|, |C₆| \[m\].
        amplitude_max_m: f64,
    },
    /// Satellites released one after another from one dispenser at the LVLH origin: satellite i (of N)
    /// starts `(i − (N − 1)/2) spacing_m` along-track, with an along-track release velocity spaced
    /// linearly from `release_speed_mps[0]` (satellite 0) to `release_speed_mps[1]` (satellite N − 1),
    /// plus an independent Gaussian dispersion of `release_dispersion_mps` (1 σ) per Hill axis.
    Dispenser {
        /// Along-track distance between consecutive satellites at release \[m\].
        spacing_m: f64,
        /// Along-track release velocities of the first and the last satellite \[m/s\].
        release_speed_mps: [f64; 2],
        /// Release velocity dispersion, 1 σ per Hill axis \[m/s\] (default 0).
        #[serde(default)]
        release_dispersion_mps: f64,
    },
    /// An explicit list of states [x, y, z, vx, vy, vz] in m and m/s.
    List {
        /// Frame of the listed states (default `hill`).
        #[serde(default)]
        frame: ListFrame,
        /// One state per satellite.
        states: Vec<[f64; 6]>,
    },
    /// A CSV file with the header `x_m,y_m,z_m,vx_mps,vy_mps,vz_mps`, optionally led by a `sat` column
    /// (the satellite id of each row) and followed by a `frame` column (each row's frame); the file
    /// is named relative to the scenario file, inside its folder.
    Csv {
        /// The file (`path` is accepted as its old name).
        #[serde(alias = "path")]
        file: String,
        /// Frame of the rows without a `frame` column (default `hill`).
        #[serde(default)]
        frame: ListFrame,
    },
    /// CCSDS OEM files (2.0 or 3.0 KVN): one satellite per object, in file order, each at the
    /// scenario epoch interpolated with its segment's own method and degree.
    Oem {
        /// The files, relative to the scenario file.
        files: Vec<String>,
    },
    /// A CCSDS OMM file (KVN, XML or JSON): one satellite per element set, in file order, propagated
    /// by SGP4 to the scenario epoch (TEME, converted to EME2000).
    Omm {
        /// The file, relative to the scenario file.
        file: String,
    },
    /// A TLE file (two- or three-line element sets): one satellite per element set, in file order,
    /// propagated by SGP4 to the scenario epoch (TEME, converted to EME2000).
    Tle {
        /// The file, relative to the scenario file.
        file: String,
    },
}

/// `[[satellites.overrides]]`: values that differ for some satellites.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OverrideSection {
    /// Satellite indices concerned.
    pub ids: Vec<usize>,
    /// Mass \[kg\].
    pub mass_kg: Option<f64>,
    /// Physical radius \[m\].
    pub radius_m: Option<f64>,
    /// Actuator limit \[m/s^2\].
    pub max_accel_mps2: Option<f64>,
    /// Drag reference area \[m^2\].
    pub drag_area_m2: Option<f64>,
    /// Drag coefficient.
    pub drag_coefficient: Option<f64>,
    /// SRP area \[m^2\].
    pub srp_area_m2: Option<f64>,
    /// Reflectivity coefficient.
    pub reflectivity_coefficient: Option<f64>,
}

/// `[sensing]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensingSection {
    /// Range of sensors and links \[m\] (default 1000).
    #[serde(default = "default_range")]
    pub range_m: f64,
    /// Navigation position noise, standard deviation per axis \[m\] (default 0).
    #[serde(default)]
    pub position_noise_m: f64,
    /// Navigation velocity noise, standard deviation per axis \[m/s\] (default 0).
    #[serde(default)]
    pub velocity_noise_mps: f64,
    /// Ring neighbourhood: each satellite senses this many satellites nearest ahead along the orbit
    /// and as many behind, at any distance, instead of those within `range_m` (absent: by range).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ring_neighbours: Option<u32>,
}

fn default_range() -> f64 {
    1000.0
}

impl Default for SensingSection {
    fn default() -> Self {
        Self {
            range_m: default_range(),
            position_noise_m: 0.0,
            velocity_noise_mps: 0.0,
            ring_neighbours: None,
        }
    }
}

/// `[[threats]]`: a kinematic threat on a straight line in the Hill frame, given either by its state at a
/// time (`position_hill_m`, `velocity_hill_mps`, `at_time_s`) or by an aim (`aim_point_hill_m`,
/// `direction_hill`, `speed_mps`, `arrival_time_s`: it passes the aim point at that time); or a real
/// object, given by its orbit (`omm`, `tle` or `state_eme2000`, with `propagation`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThreatSection {
    /// Name (outputs; default `threat-K`).
    pub name: Option<String>,
    /// Radius of the danger sphere \[m\].
    pub danger_radius_m: f64,
    /// Range at which satellites detect it \[m\] (default: their sensing range).
    pub detection_range_m: Option<f64>,
    /// Position at `at_time_s`, Hill frame \[m\].
    pub position_hill_m: Option<[f64; 3]>,
    /// Constant velocity, Hill frame \[m/s\].
    pub velocity_hill_mps: Option<[f64; 3]>,
    /// Time of `position_hill_m` \[s\] (default 0).
    pub at_time_s: Option<f64>,
    /// Point the threat passes at `arrival_time_s`, Hill frame \[m\].
    pub aim_point_hill_m: Option<[f64; 3]>,
    /// Direction of travel, Hill frame (any length > 0; normalised).
    pub direction_hill: Option<[f64; 3]>,
    /// Speed \[m/s\].
    pub speed_mps: Option<f64>,
    /// Time it passes the aim point \[s\].
    pub arrival_time_s: Option<f64>,
    /// A real object: a CCSDS OMM file (KVN, XML or JSON) holding its one element set.
    pub omm: Option<String>,
    /// A real object: its TLE, the two lines (or a title line and the two).
    pub tle: Option<Vec<String>>,
    /// A real object: its state at the scenario epoch, EME2000, `[x_m, y_m, z_m, vx_mps, vy_mps,
    /// vz_mps]` (propagated by the truth dynamics).
    pub state_eme2000: Option<[f64; 6]>,
    /// How a real object moves during the run: `sgp4` (default for `omm` and `tle`) or `truth`.
    pub propagation: Option<ObjectPropagation>,
}

/// How a real object (a threat or an obstacle from `omm`, `tle` or `state_eme2000`) moves during the run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ObjectPropagation {
    /// SGP4 from its element set (OMM, TLE only).
    Sgp4,
    /// The run's uncontrolled dynamics (the virtual reference's force set and physical properties)
    /// from its state at the scenario epoch.
    Truth,
}

/// `[[obstacles]]`: a sphere static in the Hill frame (`center_hill_m`), or centred on a real object
/// given by its orbit (`omm`, `tle` or `state_eme2000`, with `propagation`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstacleSection {
    /// Name (outputs; default `obstacle-K`).
    pub name: Option<String>,
    /// Centre, Hill frame \[m\] (a static obstacle).
    pub center_hill_m: Option<[f64; 3]>,
    /// A real object: a CCSDS OMM file (KVN, XML or JSON) holding its one element set.
    pub omm: Option<String>,
    /// A real object: its TLE, the two lines (or a title line and the two).
    pub tle: Option<Vec<String>>,
    /// A real object: its state at the scenario epoch, EME2000 `[x_m, y_m, z_m, vx_mps, vy_mps,
    /// vz_mps]` (propagated by the truth dynamics).
    pub state_eme2000: Option<[f64; 6]>,
    /// How a real object moves during the run: `sgp4` (default for `omm` and `tle`) or `truth`.
    pub propagation: Option<ObjectPropagation>,
    /// Radius \[m\].
    pub radius_m: f64,
    /// Range at which satellites detect it, measured to its surface \[m\] (default: their sensing range).
    pub detection_range_m: Option<f64>,
}

/// Satellites an event concerns: `"all"` or a list of indices.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum SelectionSection {
    /// The word `all`.
    Word(String),
    /// Indices.
    Ids(Vec<usize>),
}

/// Thrust axes an event can fail.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum AxisName {
    /// Hill x.
    X,
    /// Hill y.
    Y,
    /// Hill z.
    Z,
    /// Every axis.
    All,
}

/// `[[events]]`: when — `time_s` or a `condition` (one of them) — and an `action` with its keys
/// (unknown keys are refused by the action).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EventSection {
    /// When \[s\] (an event fires at a time or on a condition).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time_s: Option<f64>,
    /// On what state of the swarm it fires (instead of `time_s`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub condition: Option<ConditionSection>,
    /// What.
    #[serde(flatten)]
    pub action: ActionSection,
}

impl EventSection {
    /// The event that fires at `time_s` \[s\].
    pub fn at(time_s: f64, action: ActionSection) -> Self {
        Self {
            time_s: Some(time_s),
            condition: None,
            action,
        }
    }
}

/// An event's `condition`: one test (`min_separation_below_m`, `threat_within_m`,
/// `formation_reached`, `satellites_lost_at_least` or `law_outcome`) with its own keys, how often it
/// fires (`repeat`) and its hysteresis (`docs/scenarios.md`, "Condition events").
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConditionSection {
    /// Fires when the minimum separation between two live satellites is below this \[m\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_separation_below_m: Option<f64>,
    /// Fires when a live satellite comes within this distance of a threat \[m\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub threat_within_m: Option<f64>,
    /// `true`: fires when the formation is reached (the law's own report, or `uniformity_l` within
    /// `uniformity_tolerance`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub formation_reached: Option<bool>,
    /// With `formation_reached`: the target uniformity L of the five elements (dimensionless).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uniformity_l: Option<f64>,
    /// With `uniformity_l`: the largest |L − target| that counts as reached (dimensionless).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uniformity_tolerance: Option<f64>,
    /// Fires when at least this many satellites have been removed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub satellites_lost_at_least: Option<usize>,
    /// `true`: fires when the conjunction monitor (`[conjunctions] threshold_m`) finds an encounter.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub conjunction: Option<bool>,
    /// Fires when this declared outcome of the running law crosses `above` or `below`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub law_outcome: Option<String>,
    /// With `law_outcome`: fires when it is greater than this (in the outcome's unit).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub above: Option<f64>,
    /// With `law_outcome`: fires when it is less than this (in the outcome's unit).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub below: Option<f64>,
    /// With a distance condition: how far back past the threshold the distance must come before a
    /// repeating condition re-arms \[m\] (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hysteresis_m: Option<f64>,
    /// With `law_outcome` or `uniformity_l`: the same, in the outcome's unit (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hysteresis: Option<f64>,
    /// Fire at every crossing (after re-arming), not only the first (default false).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub repeat: Option<bool>,
}

/// Event actions.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "action", rename_all = "kebab-case", deny_unknown_fields)]
pub enum ActionSection {
    /// Replace some law parameters.
    SetLawParameters {
        /// The keys to replace.
        parameters: toml::Table,
    },
    /// Switch law.
    SwitchLaw {
        /// The new law.
        law: LawConfig,
    },
    /// A ground message: raise or clear the warning about one threat.
    ThreatWarning {
        /// Index of the threat in `[[threats]]`.
        threat: usize,
        /// Whether the warning is in force from now on.
        active: bool,
    },
    /// Cut links.
    CutLinks {
        /// Who.
        satellites: SelectionSection,
    },
    /// Restore links.
    RestoreLinks {
        /// Who.
        satellites: SelectionSection,
    },
    /// Remove a satellite.
    RemoveSatellite {
        /// Which.
        satellite: usize,
    },
    /// Fail a thruster axis.
    FailThruster {
        /// Which satellite.
        satellite: usize,
        /// Which axis.
        axis: AxisName,
    },
    /// End the run (`summary.json` `status = "stopped"`, naming the event).
    StopRun,
    /// An extra recorder snapshot (a row of the tables) at this time.
    RecordSnapshot,
}

/// `[output]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSection {
    /// Write the trajectory table (default true; large swarms may turn it off).
    #[serde(default = "default_true")]
    pub trajectory: bool,
    /// File format of the tables, `"csv"` or `"parquet"` (absent: CSV for the metrics, and for the
    /// trajectory up to [`crate::output::recorder::CSV_TRAJECTORY_MAX_SATELLITES`] satellites, Parquet
    /// above; `satflock run --format` overrides it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub format: Option<OutputFormat>,
    /// Extra metadata copied into `summary.json`.
    #[serde(default)]
    pub tags: BTreeMap<String, String>,
    /// Delta-v budget per satellite \[m/s\]: a satellite spending more gives a warning (stderr and
    /// `summary.json`'s `warnings`). Absent: no budget.
    #[serde(default)]
    pub delta_v_budget_mps: Option<f64>,
    /// Accept runs beyond 10^10 satellite-steps and outputs beyond 5·10^7 CSV rows (default false: such
    /// sizes are refused as a likely unit mistake).
    #[serde(default)]
    pub allow_large: bool,
    /// Write `oem/sat-NNNNN.oem` (CCSDS OEM 2.0 of each satellite's inertial states, one file per
    /// satellite, from the trajectory)
    /// after a completed run (default false; needs `trajectory = true`).
    #[serde(default)]
    pub oem: bool,
    /// Record the control history (default false): the trajectory gains each satellite's commanded
    /// and applied acceleration (Hill frame \[m/s^2\]) and whether the actuator limited the command,
    /// and `metrics` the saturated fraction and the mean command norm (`docs/outputs.md`). Not written
    /// for the kinematic model (its command is a velocity).
    #[serde(default)]
    pub control_history: bool,
}

fn default_true() -> bool {
    true
}

impl Default for OutputSection {
    fn default() -> Self {
        Self {
            trajectory: true,
            format: None,
            tags: BTreeMap::new(),
            delta_v_budget_mps: None,
            allow_large: false,
            oem: false,
            control_history: false,
        }
    }
}
