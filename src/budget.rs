//! The perturbation budget of a satellite pair ([`budget`], `satflock budget`, `satflock.budget`):
//! for two satellites a given distance apart on a circular orbit, each perturbation's acceleration,
//! the difference between the two satellites' accelerations, and the along-track drift that
//! difference causes per orbit and per day. The numbers are orders of magnitude for deciding which
//! forces a swarm's dynamics may neglect, not a prediction of a trajectory.
//!
//! # The pair
//!
//! Satellite 1 is on the circular orbit of radius `r = R + altitude` (`R` the WGS-84 equatorial
//! radius, the spherical altitude of the drag model), inclination `i`, right ascension of the
//! ascending node 0 (the node on the EME2000 x axis), with the Keplerian circular speed
//! `v = sqrt(mu / r)`. Satellite 2 is on a circular orbit of its own,
//! `separation_m` = δ away from satellite 1 along one axis of satellite 1's Hill frame (x radial
//! out, y along-track, z orbit normal), measured along the arc:
//!
//! * **along-track**: the same orbit, δ/r ahead in argument of latitude;
//! * **radial**: the coplanar circular orbit of radius r + δ (its own circular speed), at the same
//!   argument of latitude;
//! * **cross-track**: the circular orbit of radius r and inclination i + δ/r about the same line of
//!   nodes, at the same argument of latitude u: the separation is then δ |sin u| (δ at the highest
//!   latitude, zero at the nodes).
//!
//! # The terms
//!
//! One row per term ([`Term`]), each force model alone, from `satflock::dynamics`: the zonal
//! harmonics J2, J3, J4, J5, J6 each alone (the EGM96 values of [`egm96_zonal_coefficients`], point
//! mass removed), drag (the [`DragConfig`] given: co-rotating atmosphere, spherical altitude;
//! Harris–Priester by default), solar radiation pressure (cannonball, no shadow: the worst case, the
//! satellite always lit), the Sun's and the Moon's point masses (indirect term included; their
//! analytic positions at the epoch), and the HCW linearisation error.
//!
//! The orbit is sampled at [`SAMPLES_PER_ORBIT`] (36) equally spaced points of argument of latitude
//! `u_k = 2 pi k / 36` of satellite 1, satellite 2 at the point of its orbit given above; every sample
//! is at the instant of the epoch (the Sun and the Moon, hence the atmosphere's diurnal bulge, held
//! where they are then: over one orbit of about 1.5 h they move about 0.06° and 0.8°, and holding
//! them makes every sampled quantity periodic in `u`, so that the mean over the 36 points is the
//! orbit mean of every harmonic below the 36th). For each term:
//!
//! * `acceleration_mps2` \[m/s²\]: the orbit mean of `|a_1(u_k)|`, the magnitude of the term's
//!   inertial acceleration on satellite 1;
//! * `differential_acceleration_mps2` \[m/s²\]: the orbit mean of `|a_2(u_k) − a_1(u_k)|`, the
//!   magnitude of the difference of the two inertial (ECI) accelerations, i.e. the relative
//!   acceleration the term causes;
//! * `mean_differential_acceleration_hill_mps2` \[m/s²\]: `Δā`, the orbit mean of
//!   `R_2(u_k) a_2(u_k) − R_1(u_k) a_1(u_k)`, each satellite's acceleration in its **own** Hill
//!   (RSW) frame `R_j` (radial, along-track, orbit normal), x, y, z;
//! * `drift_per_orbit_m`, `drift_per_day_m` \[m\]: the secular along-track drift caused by `Δā`
//!   after `t = T` and after `t = 86 400 s` ([`secular_along_track_drift_m`]).
//!
//! # How the drift is computed
//!
//! The HCW equations (Clohessy & Wiltshire, *J. Aerospace Sci.* 27(9), 1960, 653–658; Vallado,
//! *Fundamentals of Astrodynamics and Applications*, 4th ed., §6.8) forced by a constant
//! acceleration `(a_x, a_y, a_z)` in the Hill frame, from a zero relative state (any bounded free
//! motion adds only bounded terms), have the solution (the columns of
//! [`crate::relative::Hcw::control_input_matrix`]):
//!
//! ```text
//! x(t) = (a_x / n²)(1 − cos nt) + (2 a_y / n²)(nt − sin nt)
//! y(t) = −(2 a_x / n²)(nt − sin nt) + (4 a_y / n²)(1 − cos nt) − (3/2) a_y t²
//! z(t) = (a_z / n²)(1 − cos nt)
//! ```
//!
//! The along-track displacement's secular part is `y_sec(t) = −(3/2) a_y t² − 2 a_x t / n`: an
//! along-track acceleration drifts quadratically (it changes the semi-major axis, `ȧ = 2 a_y / n`,
//! hence the mean motion), a radial one linearly (it changes the mean motion directly); the
//! cross-track response is bounded (`|z| ≤ 2 |a_z| / n²`) and gives no drift. The drift reported is
//! `|y_sec(t)| = |(3/2) Δā_y t² + 2 Δā_x t / n|`.
//!
//! The constant acceleration is the orbit mean `Δā` of the difference of the two satellites'
//! accelerations, each in its own RSW frame. That is what Gauss's variational equations average for
//! near-circular orbits: `ȧ = 2 a_S / n` and `d(u + Ω cos i)/dt = n − 2 a_R / (n a)` give the same
//! `−(3/2) Δā_S t² − 2 Δā_R t / n` for the difference of two orbits' mean forcing; and it makes a
//! field both satellites cross in the same way (J2 on a pair sharing one orbit, a uniform force on
//! equal satellites) cause no drift, as it causes none. The rotation between the two Hill frames
//! (δ/r) is not a relative acceleration: differencing in one frame would turn the Earth's radial
//! pull on a pair along one orbit into a spurious along-track `|a| δ / r`.
//!
//! **Left out**, so the numbers are orders of magnitude: the periodic terms of the forced solution
//! (`2 a_x sin(nt) / n²`, `4 a_y (1 − cos nt) / n²`, bounded by `2 |a_x| / n² + 8 |a_y| / n²`;
//! exactly zero after whole orbits, so the drift per orbit is exact for a constant acceleration); the
//! response to the parts of the differential acceleration that vary around the orbit (twice per
//! orbit and faster: bounded oscillations and a drift of at most about `3 |Δa_k| t / (k n)` for the
//! k-th harmonic; the once-per-orbit part, e.g. a differential force nearly fixed in inertial space
//! such as SRP on satellites of different area, or the Sun's and Moon's tidal terms, averages out of
//! `Δā` and grows the relative eccentricity instead: an along-track excursion growing by about 3 to
//! 6 `|Δa| t / n`, depending on the force's direction); the motion of the Sun and the Moon; the
//! change of the differential acceleration as the pair drifts apart; eccentric orbits. The HCW row is the exception to the own-frame rule: it is the
//! error of the Cartesian HCW model itself (see [`Term::HcwLinearisation`]).

use std::fmt;
use std::str::FromStr;

use hifitime::Epoch;
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

use crate::dynamics::{
    egm96_zonal_coefficients, AtmosphereName, Bodies, BodyName, Drag, DragConfig, ForceModel,
    Instant, PhysicalProperties, ShadowName, SolarRadiationPressure, ThirdBody, ZonalGravity,
};
use crate::orbit::EarthModel;

/// Lowest altitude of the orbit \[m\]: 100 km, the atmosphere models' floor.
pub const MIN_ALTITUDE_M: f64 = 100e3;
/// Highest altitude of the orbit \[m\]: 2 000 km (low Earth orbit; the Harris–Priester table ends at
/// 1 000 km, above which it gives no drag).
pub const MAX_ALTITUDE_M: f64 = 2_000e3;
/// Largest separation of the pair \[m\]: 100 km (the budget is a local, linear estimate).
pub const MAX_SEPARATION_M: f64 = 100e3;
/// Points of the orbit the accelerations are averaged over (every 10° of argument of latitude).
pub const SAMPLES_PER_ORBIT: usize = 36;
/// The length of the day of the per-day drift \[s\].
pub const SECONDS_PER_DAY: f64 = 86_400.0;

/// The axis of satellite 1's Hill frame along which satellite 2 is separated (see the module
/// documentation for the orbit of satellite 2 in each case).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SeparationDirection {
    /// Along-track (Hill y): the same orbit, ahead.
    AlongTrack,
    /// Radial (Hill x): a coplanar orbit, higher.
    Radial,
    /// Cross-track (Hill z, the orbit normal): an orbit inclined more, about the same nodes.
    CrossTrack,
}

impl SeparationDirection {
    /// Every direction.
    pub const ALL: [SeparationDirection; 3] = [Self::AlongTrack, Self::Radial, Self::CrossTrack];

    /// The direction's name: `along-track`, `radial`, `cross-track`.
    pub fn name(self) -> &'static str {
        match self {
            Self::AlongTrack => "along-track",
            Self::Radial => "radial",
            Self::CrossTrack => "cross-track",
        }
    }

    /// The unit vector of the direction in Hill axes (x radial, y along-track, z orbit normal).
    pub fn hill_unit(self) -> Vector3<f64> {
        match self {
            Self::AlongTrack => Vector3::y(),
            Self::Radial => Vector3::x(),
            Self::CrossTrack => Vector3::z(),
        }
    }
}

impl fmt::Display for SeparationDirection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for SeparationDirection {
    type Err = String;

    /// `along-track`, `radial` or `cross-track`; the error says which are allowed.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|d| d.name() == s)
            .ok_or_else(|| {
                format!("`{s}` is not a direction (allowed: along-track, radial, cross-track)")
            })
    }
}

/// What the budget is computed for. SI throughout.
#[derive(Clone, Debug, PartialEq)]
pub struct BudgetInput {
    /// Altitude of satellite 1's circular orbit above the WGS-84 equatorial radius \[m\]
    /// ([`MIN_ALTITUDE_M`] to [`MAX_ALTITUDE_M`]).
    pub altitude_m: f64,
    /// Inclination of the orbit to the EME2000 equator \[rad\] (0 to pi).
    pub inclination_rad: f64,
    /// The instant of every sample: the Sun's and the Moon's positions, hence the atmosphere's
    /// diurnal bulge, are those of the epoch.
    pub epoch: Epoch,
    /// Distance between the two satellites \[m\] (> 0 and at most [`MAX_SEPARATION_M`]), along the arc.
    pub separation_m: f64,
    /// The axis of satellite 1's Hill frame the separation is along.
    pub direction: SeparationDirection,
    /// Satellite 1's mass, drag area and coefficient, SRP area and reflectivity coefficient.
    pub satellite_1: PhysicalProperties,
    /// Satellite 2's properties. Differential drag comes mostly from different ballistic
    /// coefficients `C_d A / m`, so the two usually differ in drag area.
    pub satellite_2: PhysicalProperties,
    /// The atmosphere of the drag row ([`BudgetInput::harris_priester`] by default in the CLI and
    /// Python; [`BudgetInput::exponential_table`] for Vallado's static table).
    pub drag: DragConfig,
}

impl BudgetInput {
    /// The drag of the budget's default: Harris–Priester (Montenbruck & Gill's table, cosine exponent
    /// 4, bulge lag 30°), co-rotating, at spherical altitude.
    pub fn harris_priester() -> DragConfig {
        DragConfig::new(AtmosphereName::HarrisPriester)
    }

    /// Vallado's piecewise exponential table (static, no Sun), co-rotating, at spherical altitude.
    pub fn exponential_table() -> DragConfig {
        DragConfig::new(AtmosphereName::ExponentialTable)
    }

    /// Checks every value against its range. The error's key is the field (`altitude_m`,
    /// `satellite_2.drag_area_m2`, `drag.lag_deg`, ...).
    pub fn validate(&self) -> Result<(), BudgetError> {
        let check = |key: &str, value: f64, ok: bool, allowed: &str| {
            if value.is_finite() && ok {
                Ok(())
            } else {
                Err(BudgetError::new(key, value, allowed))
            }
        };
        check(
            "altitude_m",
            self.altitude_m,
            (MIN_ALTITUDE_M..=MAX_ALTITUDE_M).contains(&self.altitude_m),
            "an altitude from 100 000 to 2 000 000 m (100 to 2000 km)",
        )?;
        check(
            "inclination_rad",
            self.inclination_rad,
            (0.0..=std::f64::consts::PI).contains(&self.inclination_rad),
            "an inclination from 0 to pi rad (0 to 180 deg)",
        )?;
        check(
            "separation_m",
            self.separation_m,
            self.separation_m > 0.0 && self.separation_m <= MAX_SEPARATION_M,
            "a separation > 0 and at most 100 000 m (100 km)",
        )?;
        for (prefix, properties) in [
            ("satellite_1.", &self.satellite_1),
            ("satellite_2.", &self.satellite_2),
        ] {
            properties.validate(prefix).map_err(|e| BudgetError {
                key: e.key,
                value: e.value,
                allowed: e.allowed,
            })?;
        }
        Drag::from_config(&self.drag, &EarthModel::WGS84_EGM96).map_err(|e| BudgetError {
            key: e.key,
            value: e.value,
            allowed: e.allowed,
        })?;
        Ok(())
    }
}

/// A value of a [`BudgetInput`] out of its range: the field, the value given and what is allowed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("`{key}` = {value}: {allowed}")]
pub struct BudgetError {
    /// The field (`altitude_m`, `satellite_2.drag_area_m2`, `drag.lag_deg`).
    pub key: String,
    /// The value given, as written back.
    pub value: String,
    /// What is allowed.
    pub allowed: String,
}

impl BudgetError {
    /// An error for `key` with `value` and what is `allowed`.
    pub fn new(key: impl Into<String>, value: impl ToString, allowed: impl Into<String>) -> Self {
        Self {
            key: key.into(),
            value: value.to_string(),
            allowed: allowed.into(),
        }
    }
}

/// One row of the budget.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Term {
    /// The J2 zonal harmonic alone.
    #[serde(rename = "J2")]
    J2,
    /// The J3 zonal harmonic alone.
    #[serde(rename = "J3")]
    J3,
    /// The J4 zonal harmonic alone.
    #[serde(rename = "J4")]
    J4,
    /// The J5 zonal harmonic alone.
    #[serde(rename = "J5")]
    J5,
    /// The J6 zonal harmonic alone.
    #[serde(rename = "J6")]
    J6,
    /// Atmospheric drag.
    #[serde(rename = "drag")]
    Drag,
    /// Solar radiation pressure, no shadow.
    #[serde(rename = "srp")]
    Srp,
    /// The Sun's point mass (the tidal term: direct minus indirect).
    #[serde(rename = "sun")]
    Sun,
    /// The Moon's point mass (the tidal term).
    #[serde(rename = "moon")]
    Moon,
    /// The error of the HCW model's linear gravity difference: the exact two-body relative
    /// acceleration `−mu (r + ρ)/|r + ρ|³ + mu r/|r|³` minus its linearisation
    /// `(mu / r³)(3 (r̂·ρ) r̂ − ρ)`, for the Cartesian offset `ρ = δ ê` along the direction's Hill
    /// axis `ê` (the HCW model's own straight-line coordinates; for along-track and cross-track
    /// `≈ (3/2) mu δ² / r⁴` radially, for radial `≈ −3 mu δ² / r⁴`). It has no absolute acceleration;
    /// its drift is the drift of HCW coordinates from the truth.
    #[serde(rename = "hcw-linearisation")]
    HcwLinearisation,
}

impl Term {
    /// Every term, in the budget's order.
    pub const ALL: [Term; 10] = [
        Term::J2,
        Term::J3,
        Term::J4,
        Term::J5,
        Term::J6,
        Term::Drag,
        Term::Srp,
        Term::Sun,
        Term::Moon,
        Term::HcwLinearisation,
    ];

    /// The term's name, as in the JSON and the Python dict: `J2` … `J6`, `drag`, `srp`, `sun`,
    /// `moon`, `hcw-linearisation`.
    pub fn name(self) -> &'static str {
        match self {
            Term::J2 => "J2",
            Term::J3 => "J3",
            Term::J4 => "J4",
            Term::J5 => "J5",
            Term::J6 => "J6",
            Term::Drag => "drag",
            Term::Srp => "srp",
            Term::Sun => "sun",
            Term::Moon => "moon",
            Term::HcwLinearisation => "hcw-linearisation",
        }
    }
}

impl fmt::Display for Term {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One term's row (see the module documentation for how each number is computed).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BudgetTerm {
    /// The term.
    pub term: Term,
    /// Orbit mean of the magnitude of the term's inertial acceleration on satellite 1 \[m/s²\];
    /// `None` for the HCW linearisation error, which acts on no satellite.
    pub acceleration_mps2: Option<f64>,
    /// Orbit mean of the magnitude of the difference of the two satellites' inertial accelerations
    /// \[m/s²\] (for the HCW row: the magnitude of the linearisation error).
    pub differential_acceleration_mps2: f64,
    /// Orbit mean `Δā` of the difference of the two satellites' accelerations, each in its own Hill
    /// (RSW) frame: radial, along-track, orbit normal \[m/s²\] (for the HCW row: the error in
    /// satellite 1's Hill frame). The drift is computed from it.
    pub mean_differential_acceleration_hill_mps2: [f64; 3],
    /// Secular along-track drift after one orbit (the Keplerian period) \[m\].
    pub drift_per_orbit_m: f64,
    /// Secular along-track drift after [`SECONDS_PER_DAY`] \[m\].
    pub drift_per_day_m: f64,
}

/// The perturbation budget of a pair: the input restated and one row per [`Term`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Budget {
    /// Altitude of satellite 1's orbit \[m\].
    pub altitude_m: f64,
    /// Inclination \[rad\].
    pub inclination_rad: f64,
    /// The epoch, ISO 8601 UTC.
    pub epoch_utc: String,
    /// Separation of the pair \[m\].
    pub separation_m: f64,
    /// Its direction in satellite 1's Hill frame.
    pub direction: SeparationDirection,
    /// The drag row's atmosphere.
    pub atmosphere: AtmosphereName,
    /// Radius of satellite 1's orbit \[m\].
    pub orbit_radius_m: f64,
    /// Keplerian mean motion n of that orbit \[rad/s\].
    pub mean_motion_rad_s: f64,
    /// Keplerian period `2 pi / n` \[s\].
    pub period_s: f64,
    /// Points of the orbit averaged over ([`SAMPLES_PER_ORBIT`]).
    pub samples_per_orbit: usize,
    /// One row per term, in the order of [`Term::ALL`].
    pub terms: Vec<BudgetTerm>,
}

impl Budget {
    /// The row of `term`.
    pub fn term(&self, term: Term) -> &BudgetTerm {
        self.terms
            .iter()
            .find(|row| row.term == term)
            .expect("every term has a row")
    }
}

/// The magnitude \[m\] of the secular along-track displacement after `t_s` \[s\] of the HCW model of
/// mean motion `mean_motion_rad_s` \[rad/s\] forced by the constant Hill-frame acceleration
/// `acceleration_hill_mps2` \[m/s², x radial, y along-track, z orbit normal\] from a zero relative
/// state: `|(3/2) a_y t² + 2 a_x t / n|` (the periodic terms of the forced solution, at most
/// `2 |a_x| / n² + 8 |a_y| / n²` and zero after whole orbits, are left out; `a_z` gives no drift).
/// See the module documentation for the derivation.
pub fn secular_along_track_drift_m(
    acceleration_hill_mps2: &Vector3<f64>,
    mean_motion_rad_s: f64,
    t_s: f64,
) -> f64 {
    let a = acceleration_hill_mps2;
    (1.5 * a.y * t_s * t_s + 2.0 * a.x * t_s / mean_motion_rad_s).abs()
}

/// A point of a circular orbit with its ascending node on the EME2000 x axis: position, velocity
/// and the rotation from ECI to its Hill (RSW) axes.
#[derive(Clone, Copy, Debug)]
struct OnCircle {
    position_eci_m: Vector3<f64>,
    velocity_eci_mps: Vector3<f64>,
    eci_to_hill: Matrix3<f64>,
}

impl OnCircle {
    /// The point at argument of latitude `u_rad` of the circle of `radius_m` and `inclination_rad`,
    /// moving at the circular speed for `mu_m3_s2`.
    fn new(radius_m: f64, inclination_rad: f64, u_rad: f64, mu_m3_s2: f64) -> Self {
        let (su, cu) = u_rad.sin_cos();
        let (si, ci) = inclination_rad.sin_cos();
        let x_hat = Vector3::new(cu, su * ci, su * si);
        let y_hat = Vector3::new(-su, cu * ci, cu * si);
        let z_hat = Vector3::new(0.0, -si, ci);
        let speed_mps = (mu_m3_s2 / radius_m).sqrt();
        Self {
            position_eci_m: radius_m * x_hat,
            velocity_eci_mps: speed_mps * y_hat,
            eci_to_hill: Matrix3::from_rows(&[
                x_hat.transpose(),
                y_hat.transpose(),
                z_hat.transpose(),
            ]),
        }
    }
}

/// The force model of one physical row.
#[derive(Debug)]
enum Model {
    /// One zonal harmonic (the field of J_n alone, point mass removed).
    Zonal(ZonalGravity),
    Drag(Drag),
    Srp(SolarRadiationPressure),
    Body(ThirdBody),
}

impl Model {
    /// The row's inertial acceleration \[m/s², ECI\].
    fn acceleration_eci_m_s2(
        &self,
        at: &Instant,
        point: &OnCircle,
        properties: &PhysicalProperties,
        mu_m3_s2: f64,
    ) -> Vector3<f64> {
        let (r, v) = (&point.position_eci_m, &point.velocity_eci_mps);
        match self {
            Model::Zonal(field) => {
                let r2 = r.norm_squared();
                field.acceleration_m_s2(r) + r * (mu_m3_s2 / (r2 * r2.sqrt()))
            }
            Model::Drag(m) => m.acceleration_eci_m_s2(at, r, v, properties),
            Model::Srp(m) => m.acceleration_eci_m_s2(at, r, v, properties),
            Model::Body(m) => m.acceleration_eci_m_s2(at, r, v, properties),
        }
    }
}

/// The pair of a budget: both orbits and the instant of the samples.
struct Pair<'a> {
    input: &'a BudgetInput,
    earth: EarthModel,
    radius_m: f64,
    mean_motion_rad_s: f64,
    /// The epoch, with the Sun's and the Moon's positions.
    epoch: Instant,
}

/// One sample of one term: satellite 1's inertial acceleration, the inertial difference and the
/// own-frame (Hill) difference.
struct Sample {
    acceleration_1_eci_m_s2: Vector3<f64>,
    difference_eci_m_s2: Vector3<f64>,
    difference_hill_m_s2: Vector3<f64>,
}

impl<'a> Pair<'a> {
    fn new(input: &'a BudgetInput) -> Self {
        let earth = EarthModel::WGS84_EGM96;
        let radius_m = earth.equatorial_radius_m + input.altitude_m;
        Self {
            input,
            earth,
            radius_m,
            mean_motion_rad_s: earth.mean_motion_rad_s(radius_m),
            epoch: Instant::new(
                input.epoch.to_tt_since_j2k().to_seconds(),
                Bodies {
                    sun: true,
                    moon: true,
                },
            ),
        }
    }

    /// Satellite 1 at argument of latitude `u_rad` and satellite 2 beside it.
    fn points(&self, u_rad: f64) -> (OnCircle, OnCircle) {
        let (r, i, mu) = (
            self.radius_m,
            self.input.inclination_rad,
            self.earth.mu_m3_s2,
        );
        let u = u_rad;
        let delta = self.input.separation_m;
        let second = match self.input.direction {
            SeparationDirection::AlongTrack => OnCircle::new(r, i, u + delta / r, mu),
            SeparationDirection::Radial => OnCircle::new(r + delta, i, u, mu),
            SeparationDirection::CrossTrack => OnCircle::new(r, i + delta / r, u, mu),
        };
        (OnCircle::new(r, i, u, mu), second)
    }

    /// `model`'s sample with satellite 1 at argument of latitude `u_rad`, at the epoch.
    fn sample(&self, model: &Model, u_rad: f64) -> Sample {
        let (one, two) = self.points(u_rad);
        let mu = self.earth.mu_m3_s2;
        let a1 = model.acceleration_eci_m_s2(&self.epoch, &one, &self.input.satellite_1, mu);
        let a2 = model.acceleration_eci_m_s2(&self.epoch, &two, &self.input.satellite_2, mu);
        Sample {
            acceleration_1_eci_m_s2: a1,
            difference_eci_m_s2: a2 - a1,
            difference_hill_m_s2: two.eci_to_hill * a2 - one.eci_to_hill * a1,
        }
    }

    /// The HCW linearisation error with satellite 1 at `u_rad`: ECI and in satellite 1's Hill frame.
    fn hcw_error(&self, u_rad: f64) -> (Vector3<f64>, Vector3<f64>) {
        let (one, _) = self.points(u_rad);
        let mu = self.earth.mu_m3_s2;
        let r = one.position_eci_m;
        let rho_eci = one.eci_to_hill.transpose()
            * (self.input.separation_m * self.input.direction.hill_unit());
        // g(r + ρ) − g(r), g = −mu r/|r|³, without cancellation: Battin's form with the "body" at −r.
        let exact = ThirdBody::point_mass_perturbation_m_s2(mu, &(-r), &rho_eci);
        let r_norm = r.norm();
        let r_hat = r / r_norm;
        let linear =
            (3.0 * r_hat.dot(&rho_eci) * r_hat - rho_eci) * (mu / (r_norm * r_norm * r_norm));
        let error = exact - linear;
        (error, one.eci_to_hill * error)
    }

    /// The argument of latitude of sample `k` \[rad\].
    fn sample_u_rad(k: usize) -> f64 {
        std::f64::consts::TAU * k as f64 / SAMPLES_PER_ORBIT as f64
    }

    /// The row of `term` from the orbit means of its samples.
    fn row(
        &self,
        term: Term,
        acceleration_mps2: Option<f64>,
        differential_acceleration_mps2: f64,
        mean_hill: Vector3<f64>,
    ) -> BudgetTerm {
        let n = self.mean_motion_rad_s;
        BudgetTerm {
            term,
            acceleration_mps2,
            differential_acceleration_mps2,
            mean_differential_acceleration_hill_mps2: mean_hill.into(),
            drift_per_orbit_m: secular_along_track_drift_m(
                &mean_hill,
                n,
                std::f64::consts::TAU / n,
            ),
            drift_per_day_m: secular_along_track_drift_m(&mean_hill, n, SECONDS_PER_DAY),
        }
    }
}

/// The force model of each physical term (every row but the HCW one), in the budget's order.
fn models(input: &BudgetInput, earth: &EarthModel) -> Result<Vec<(Term, Model)>, BudgetError> {
    let zonal = egm96_zonal_coefficients(6);
    let mut models = Vec::with_capacity(9);
    for (k, term) in [Term::J2, Term::J3, Term::J4, Term::J5, Term::J6]
        .into_iter()
        .enumerate()
    {
        let mut alone = vec![0.0; k + 1];
        alone[k] = zonal[k];
        models.push((term, Model::Zonal(ZonalGravity::new(earth, alone))));
    }
    let drag = Drag::from_config(&input.drag, earth).map_err(|e| BudgetError {
        key: e.key,
        value: e.value,
        allowed: e.allowed,
    })?;
    models.push((Term::Drag, Model::Drag(drag)));
    models.push((
        Term::Srp,
        Model::Srp(SolarRadiationPressure::new(
            ShadowName::None,
            earth.equatorial_radius_m,
        )),
    ));
    models.push((Term::Sun, Model::Body(ThirdBody::new(BodyName::Sun))));
    models.push((Term::Moon, Model::Body(ThirdBody::new(BodyName::Moon))));
    Ok(models)
}

/// The perturbation budget of `input`'s pair (see the module documentation for what each number
/// is and how the drift is computed).
///
/// # Errors
/// A [`BudgetError`] naming the field when a value is out of range ([`BudgetInput::validate`]).
pub fn budget(input: &BudgetInput) -> Result<Budget, BudgetError> {
    input.validate()?;
    let pair = Pair::new(input);
    let count = SAMPLES_PER_ORBIT as f64;
    let mut terms = Vec::with_capacity(Term::ALL.len());
    for (term, model) in models(input, &pair.earth)? {
        let (mut absolute, mut differential, mut mean_hill) = (0.0, 0.0, Vector3::zeros());
        for k in 0..SAMPLES_PER_ORBIT {
            let s = pair.sample(&model, Pair::sample_u_rad(k));
            absolute += s.acceleration_1_eci_m_s2.norm();
            differential += s.difference_eci_m_s2.norm();
            mean_hill += s.difference_hill_m_s2;
        }
        terms.push(pair.row(
            term,
            Some(absolute / count),
            differential / count,
            mean_hill / count,
        ));
    }
    let (mut differential, mut mean_hill) = (0.0, Vector3::zeros());
    for k in 0..SAMPLES_PER_ORBIT {
        let (eci, hill) = pair.hcw_error(Pair::sample_u_rad(k));
        differential += eci.norm();
        mean_hill += hill;
    }
    terms.push(pair.row(
        Term::HcwLinearisation,
        None,
        differential / count,
        mean_hill / count,
    ));
    Ok(Budget {
        altitude_m: input.altitude_m,
        inclination_rad: input.inclination_rad,
        epoch_utc: crate::time::utc_iso(input.epoch),
        separation_m: input.separation_m,
        direction: input.direction,
        atmosphere: input.drag.atmosphere,
        orbit_radius_m: pair.radius_m,
        mean_motion_rad_s: pair.mean_motion_rad_s,
        period_s: std::f64::consts::TAU / pair.mean_motion_rad_s,
        samples_per_orbit: SAMPLES_PER_ORBIT,
        terms,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::Rk4;
    use crate::relative::Hcw;
    use nalgebra::Vector6;

    /// WGS-84 mu \[m^3/s^2\] and equatorial radius \[m\], EGM96 J2..J4, restated from their sources
    /// (NGA.STND.0036; the EGM96 values as the crate's documentation quotes them, 9 figures).
    const MU: f64 = 3.986_004_418e14;
    const RE: f64 = 6_378_137.0;
    const J2: f64 = 1.082_626_68e-3;
    const J3: f64 = -2.532_656_49e-6;
    const J4: f64 = -1.619_621_59e-6;

    fn epoch() -> Epoch {
        crate::time::parse_epoch_utc(crate::time::DEFAULT_EPOCH_UTC).unwrap()
    }

    fn satellite(mass_kg: f64, area_m2: f64) -> PhysicalProperties {
        PhysicalProperties {
            mass_kg,
            drag_area_m2: area_m2,
            drag_coefficient: 2.2,
            srp_area_m2: area_m2,
            reflectivity_coefficient: 1.5,
        }
    }

    fn input(altitude_m: f64, inclination_deg: f64, direction: SeparationDirection) -> BudgetInput {
        BudgetInput {
            altitude_m,
            inclination_rad: inclination_deg.to_radians(),
            epoch: epoch(),
            separation_m: 1000.0,
            direction,
            satellite_1: satellite(100.0, 1.0),
            satellite_2: satellite(100.0, 2.0),
            drag: BudgetInput::harris_priester(),
        }
    }

    fn relative(got: f64, want: f64) -> f64 {
        (got - want).abs() / want.abs()
    }

    /// On the equator of an equatorial orbit (s = sin(latitude) = 0) each zonal term alone has the
    /// closed form `|a_n| = |J_n| (mu/r^2) (R/r)^n c_n` with `c_n = |(n+1) P_n(0)|` for even n and
    /// `|P_n'(0)|` for odd n: 3/2 for J2 and J3, 15/8 for J4. Every sample is on the equator, so the
    /// orbit mean is that value (9 figures: the constants above are quoted to 9).
    #[test]
    fn budget_zonal_terms_on_the_equator_are_the_closed_forms() {
        let b = budget(&input(500e3, 0.0, SeparationDirection::AlongTrack)).unwrap();
        let r = RE + 500e3;
        let g = MU / (r * r);
        let q = RE / r;
        for (term, want) in [
            (Term::J2, 1.5 * J2 * g * q * q),
            (Term::J3, 1.5 * J3.abs() * g * q.powi(3)),
            (Term::J4, 15.0 / 8.0 * J4.abs() * g * q.powi(4)),
        ] {
            let got = b.term(term).acceleration_mps2.unwrap();
            assert!(relative(got, want) < 1e-8, "{term}: {got} vs {want}");
        }
        // J2 at 500 km is about 1.2e-2 m/s^2, J3 ~ 2.7e-5, J4 ~ 2.5e-5: the ratios to J2 are the
        // coefficients' ratios times (R/r)^(n-2) (and the c_n).
        let j2 = b.term(Term::J2).acceleration_mps2.unwrap();
        assert!((1.1e-2..1.3e-2).contains(&j2), "{j2}");
    }

    /// A radial pair on the equator: both Hill frames coincide, the J2 radial acceleration is
    /// `−(3/2) J2 mu R^2 / r^4`, so the differential is its difference between r and r + δ, with no
    /// along-track part; the drift per orbit is `2 Δa_x T / n`.
    #[test]
    fn budget_j2_radial_differential_and_its_drift() {
        let b = budget(&input(500e3, 0.0, SeparationDirection::Radial)).unwrap();
        let r = RE + 500e3;
        let a_x = |r: f64| -1.5 * J2 * MU * RE * RE / r.powi(4);
        let want = a_x(r + 1000.0) - a_x(r);
        let row = b.term(Term::J2);
        let [x, y, z] = row.mean_differential_acceleration_hill_mps2;
        assert!(relative(x, want) < 1e-7, "{x} vs {want}");
        assert!(y.abs() < 1e-9 * want && z.abs() < 1e-9 * want, "{y} {z}");
        assert!(relative(row.differential_acceleration_mps2, want) < 1e-7);
        let n = (MU / r.powi(3)).sqrt();
        let period = std::f64::consts::TAU / n;
        assert!(relative(row.drift_per_orbit_m, 2.0 * want * period / n) < 1e-7);
        assert!(relative(row.drift_per_day_m, 2.0 * want * SECONDS_PER_DAY / n) < 1e-7);
    }

    /// The HCW linearisation error is the second-order term of the gravity difference: radially
    /// `−3 mu δ^2 / r^4` for a radial δ (next term `+4 mu δ^3 / r^5`), `(3/2) mu δ^2 / r^4` radially
    /// for an along-track or cross-track δ (next terms of relative order (δ/r)^2).
    #[test]
    fn budget_hcw_linearisation_error_is_second_order() {
        let r = RE + 400e3;
        let delta = 1000.0;
        let second = MU * delta * delta / r.powi(4);
        for (direction, want_x, tolerance) in [
            (SeparationDirection::Radial, -3.0 * second, 2.0 * delta / r),
            (SeparationDirection::AlongTrack, 1.5 * second, 1e-6),
            (SeparationDirection::CrossTrack, 1.5 * second, 1e-6),
        ] {
            let b = budget(&input(400e3, 51.6, direction)).unwrap();
            let row = b.term(Term::HcwLinearisation);
            assert_eq!(row.acceleration_mps2, None);
            let [x, y, z] = row.mean_differential_acceleration_hill_mps2;
            assert!(
                relative(x, want_x) < tolerance,
                "{direction}: {x} vs {want_x}"
            );
            // Off the radial axis only the third-order term, (3/2) mu δ^3 / r^5 for along-track.
            let third = 2.0 * second * delta / r;
            assert!(y.abs() < third && z.abs() < third, "{y} {z}");
            assert!(relative(row.differential_acceleration_mps2, want_x.abs()) < tolerance);
            // A radial constant acceleration drifts 2 a_x T / n per orbit: 6 pi δ^2 / r for the
            // straight-line along-track offset (its orbit is 2 δ^2 / r higher); the third-order
            // along-track term adds (3/2) a_y T^2, 7e-4 of it at 1 km.
            if direction == SeparationDirection::AlongTrack {
                let want = 6.0 * std::f64::consts::PI * delta * delta / r;
                assert!(relative(row.drift_per_orbit_m, want) < 1e-3);
            }
        }
    }

    /// Along-track pair on an equatorial orbit in Vallado's static table: both at the same altitude,
    /// with the same speed relative to the co-rotating air `(n − omega_E) r`, so the differential is
    /// `(1/2) rho v_rel^2 |ΔB|` along-track, `ΔB = C_d (A_2 − A_1) / m`, with rho from Vallado's
    /// Table 8-4 printed values (420 km: 3.725e-12 kg/m^3 at 400 km, scale height 58.515 km).
    #[test]
    fn budget_differential_drag_is_half_rho_v2_delta_b() {
        let mut given = input(420e3, 0.0, SeparationDirection::AlongTrack);
        given.drag = BudgetInput::exponential_table();
        let b = budget(&given).unwrap();
        let r = RE + 420e3;
        let rho = 3.725e-12 * (-20.0 / 58.515_f64).exp();
        let v_rel = ((MU / r.powi(3)).sqrt() - 7.292_115e-5) * r;
        let delta_b = 2.2 * (2.0 - 1.0) / 100.0;
        let want = 0.5 * rho * v_rel * v_rel * delta_b;
        let row = b.term(Term::Drag);
        assert!(relative(row.differential_acceleration_mps2, want) < 1e-7);
        let [x, y, _] = row.mean_differential_acceleration_hill_mps2;
        assert!(relative(-y, want) < 1e-9, "{y} vs {want}");
        assert!(x.abs() < 1e-9 * want);
        // Satellite 2 (twice the area) falls behind: (3/2) Δa T^2 per orbit.
        let period = b.period_s;
        assert!(relative(row.drift_per_orbit_m, 1.5 * want * period * period) < 1e-9);
        // Satellite 1's own drag: (1/2) rho v_rel^2 B_1, the same as the differential here.
        assert!(relative(row.acceleration_mps2.unwrap(), want) < 1e-9);
    }

    /// In any atmosphere, an along-track pair on one orbit sees the same density and speed, so the
    /// differential drag is the absolute drag times `|B_2 − B_1| / B_1` (here 1; the inclined orbit
    /// and Harris–Priester's bulge change both alike).
    #[test]
    fn budget_differential_drag_scales_with_the_ballistic_difference() {
        for (area_2, ratio) in [(2.0, 1.0), (1.5, 0.5), (0.25, 0.75)] {
            let mut given = input(400e3, 51.6, SeparationDirection::AlongTrack);
            given.satellite_2 = satellite(100.0, area_2);
            let row = budget(&given).unwrap().term(Term::Drag).clone();
            let got = row.differential_acceleration_mps2 / row.acceleration_mps2.unwrap();
            assert!((got - ratio).abs() < 1e-3, "{area_2}: {got} vs {ratio}");
        }
    }

    /// The tidal acceleration of a body of GM at distance d is `(GM / d^3)(3 (d̂·ρ) d̂ − ρ)`, of
    /// magnitude `GM δ / d^3` to `2 GM δ / d^3` depending on the angle; with the Moon 356 400 to
    /// 406 700 km away (perigee and apogee extremes) and the satellite at most r nearer or farther,
    /// and the Sun 0.983 to 1.017 au away, the differential lies in those bounds (GM of the Moon
    /// 4.9028e12 and of the Sun 1.32712e20 m^3/s^2, JPL DE430).
    #[test]
    fn budget_tidal_differentials_are_gm_delta_over_d_cubed() {
        let r = RE + 400e3;
        let delta = 1000.0;
        let au = 1.495_978_707e11;
        for direction in SeparationDirection::ALL {
            let b = budget(&input(400e3, 51.6, direction)).unwrap();
            // Cross-track: the separation is δ |sin u|, 2δ/π on average.
            let scale = if direction == SeparationDirection::CrossTrack {
                2.0 / std::f64::consts::PI
            } else {
                1.0
            };
            for (term, gm, d_min, d_max) in [
                (Term::Moon, 4.9028e12, 356_400e3 - r, 406_700e3 + r),
                (Term::Sun, 1.327_12e20, 0.983 * au, 1.017 * au),
            ] {
                let got = b.term(term).differential_acceleration_mps2;
                let low = 0.99 * scale * gm * delta / d_max.powi(3);
                let high = 2.01 * gm * delta / d_min.powi(3);
                assert!(
                    (low..high).contains(&got),
                    "{term} {direction}: {got} not in [{low}, {high}]"
                );
            }
        }
    }

    /// Two identical satellites on one orbit (along-track) share every field's history: no physical
    /// term makes them drift apart. Only the HCW row, the error of straight-line coordinates, does.
    #[test]
    fn budget_identical_satellites_on_one_orbit_do_not_drift() {
        let mut given = input(400e3, 51.6, SeparationDirection::AlongTrack);
        given.satellite_2 = given.satellite_1;
        let b = budget(&given).unwrap();
        for row in &b.terms {
            if row.term == Term::HcwLinearisation {
                assert!(row.drift_per_day_m > 1.0, "{row:?}");
            } else {
                // Rounding: each zonal term alone is the zonal field minus the point mass (8.7 m/s^2).
                assert!(row.drift_per_day_m < 1e-4, "{row:?}");
            }
        }
        // With twice the area, drag and SRP differ, but J2's differential still averages out.
        let b = budget(&input(400e3, 51.6, SeparationDirection::AlongTrack)).unwrap();
        assert!(b.term(Term::J2).drift_per_day_m < 1e-4);
        assert!(b.term(Term::J2).differential_acceleration_mps2 > 1e-6);
        assert!(b.term(Term::Drag).drift_per_day_m > 1e3);
    }

    /// The drift formula against the forced HCW solution itself: the exact zero-order-hold response
    /// of [`Hcw::control_input_matrix`] and an RK4 integration of the HCW equations with the constant
    /// acceleration. After one orbit they agree to rounding (the periodic terms vanish); after a day,
    /// to within the periodic terms' bound `2 |a_x| / n^2 + 8 |a_y| / n^2`.
    #[test]
    fn budget_drift_formula_matches_the_forced_hcw_solution() {
        let n = EarthModel::WGS84_EGM96.mean_motion_rad_s(RE + 400e3);
        let hcw = Hcw::new(n);
        let period = std::f64::consts::TAU / n;
        for a in [
            Vector3::new(0.0, 1e-7, 0.0),
            Vector3::new(2e-7, 0.0, 5e-7),
            Vector3::new(-3e-8, 7e-8, 1e-8),
        ] {
            let closed = |t: f64| (hcw.control_input_matrix(t) * a)[1].abs();
            let formula = |t: f64| secular_along_track_drift_m(&a, n, t);
            assert!(relative(formula(period), closed(period)) < 1e-9);
            let bound = 2.0 * a.x.abs() / (n * n) + 8.0 * a.y.abs() / (n * n);
            let day = SECONDS_PER_DAY;
            assert!((formula(day) - closed(day)).abs() <= bound, "{a:?}");
            let system = |_t: f64, s: &[f64], d: &mut [f64]| {
                let ds = hcw.derivative(&Vector6::from_column_slice(s), &a);
                d.copy_from_slice(ds.as_slice());
            };
            let mut state = [0.0; 6];
            Rk4::new(6).integrate(&system, 0.0, period, &mut state, period / 2000.0);
            assert!(
                relative(state[1].abs(), formula(period)) < 1e-8,
                "{state:?}"
            );
            assert!((state[2].abs()) <= 2.0 * a.z.abs() / (n * n) + 1e-12);
        }
    }

    /// What the mean leaves out, checked: the HCW equations integrated over a day (RK4) with the
    /// differential drag sampled along the orbit (Harris–Priester, whose bulge makes it vary around
    /// the orbit) move the pair apart by the drift of the orbit mean, to a few percent.
    #[test]
    fn budget_mean_drag_drift_matches_hcw_forced_by_the_varying_drag() {
        let given = input(400e3, 51.6, SeparationDirection::AlongTrack);
        let b = budget(&given).unwrap();
        let pair = Pair::new(&given);
        let drag = Drag::from_config(&given.drag, &pair.earth).unwrap();
        let model = Model::Drag(drag);
        let n = pair.mean_motion_rad_s;
        let hcw = Hcw::new(n);
        let system = |t: f64, s: &[f64], d: &mut [f64]| {
            let a = pair.sample(&model, n * t).difference_hill_m_s2;
            let ds = hcw.derivative(&Vector6::from_column_slice(s), &a);
            d.copy_from_slice(ds.as_slice());
        };
        let mut state = [0.0; 6];
        Rk4::new(6).integrate(&system, 0.0, SECONDS_PER_DAY, &mut state, 20.0);
        let want = b.term(Term::Drag).drift_per_day_m;
        assert!(
            relative(state[1].abs(), want) < 0.05,
            "{} vs {want}",
            state[1]
        );
        // The profile does vary: its samples spread by more than 10 % about the mean.
        let samples: Vec<f64> = (0..SAMPLES_PER_ORBIT)
            .map(|k| {
                pair.sample(&model, Pair::sample_u_rad(k))
                    .difference_hill_m_s2
                    .y
            })
            .collect();
        let mean = b.term(Term::Drag).mean_differential_acceleration_hill_mps2[1];
        let spread = samples.iter().map(|s| (s - mean).abs()).fold(0.0, f64::max);
        assert!(spread > 0.1 * mean.abs(), "{spread} {mean}");
    }

    /// The documented size of what is left out for a force fixed in inertial space: its Hill-frame
    /// mean is zero (no drift here), and the HCW response is an along-track excursion reaching about
    /// 3 to 6 `|a| t / n` over a day, depending on the force's direction (measured: 2.9 to 5.9).
    #[test]
    fn budget_inertially_fixed_force_excursion_is_three_to_six_a_t_over_n() {
        let n = EarthModel::WGS84_EGM96.mean_motion_rad_s(RE + 400e3);
        let hcw = Hcw::new(n);
        let a = 1e-8;
        for phase in [0.0, 0.7, std::f64::consts::FRAC_PI_2] {
            let force =
                |t: f64| Vector3::new(a * (n * t + phase).cos(), -a * (n * t + phase).sin(), 0.0);
            let mean: Vector3<f64> = (0..SAMPLES_PER_ORBIT)
                .map(|k| force(Pair::sample_u_rad(k) / n))
                .sum::<Vector3<f64>>()
                / SAMPLES_PER_ORBIT as f64;
            assert!(secular_along_track_drift_m(&mean, n, SECONDS_PER_DAY) < 1e-9);
            let system = |t: f64, s: &[f64], d: &mut [f64]| {
                let ds = hcw.derivative(&Vector6::from_column_slice(s), &force(t));
                d.copy_from_slice(ds.as_slice());
            };
            let (mut state, mut t, mut largest) = ([0.0; 6], 0.0, 0.0_f64);
            let mut rk4 = Rk4::new(6);
            while t < SECONDS_PER_DAY {
                rk4.step(&system, t, &mut state, 10.0);
                t += 10.0;
                largest = largest.max(state[1].abs());
            }
            let unit = a * SECONDS_PER_DAY / n;
            assert!(
                (2.8 * unit..6.1 * unit).contains(&largest),
                "{phase}: {}",
                largest / unit
            );
        }
    }

    #[test]
    fn budget_refuses_values_out_of_range_naming_the_field() {
        type Spoil = fn(&mut BudgetInput);
        let cases: [(Spoil, &str); 8] = [
            (|i| i.altitude_m = 99e3, "altitude_m"),
            (|i| i.altitude_m = 2001e3, "altitude_m"),
            (|i| i.inclination_rad = f64::NAN, "inclination_rad"),
            (|i| i.inclination_rad = -0.1, "inclination_rad"),
            (|i| i.separation_m = 0.0, "separation_m"),
            (|i| i.separation_m = 100_001.0, "separation_m"),
            (
                |i| i.satellite_2.drag_area_m2 = -1.0,
                "satellite_2.drag_area_m2",
            ),
            (|i| i.satellite_1.mass_kg = 0.0, "satellite_1.mass_kg"),
        ];
        for (spoil, key) in cases {
            let mut given = input(400e3, 51.6, SeparationDirection::Radial);
            spoil(&mut given);
            let e = budget(&given).unwrap_err();
            assert_eq!(e.key, key, "{e}");
            assert!(e.to_string().contains("allowed") || !e.allowed.is_empty());
        }
        let mut given = input(400e3, 51.6, SeparationDirection::Radial);
        given.drag.scale_height_m = Some(1.0);
        assert_eq!(budget(&given).unwrap_err().key, "drag.scale_height_m");
        // The limits themselves are allowed.
        for (altitude_m, separation_m) in [(100e3, 1e-3), (2000e3, 100e3)] {
            let mut given = input(altitude_m, 180.0, SeparationDirection::CrossTrack);
            given.separation_m = separation_m;
            let b = budget(&given).unwrap();
            assert_eq!(b.terms.len(), Term::ALL.len());
            assert!(b.terms.iter().all(|t| t.drift_per_day_m.is_finite()));
        }
    }

    #[test]
    fn budget_names_and_json() {
        for d in SeparationDirection::ALL {
            assert_eq!(d.name().parse::<SeparationDirection>(), Ok(d));
        }
        assert!("sideways"
            .parse::<SeparationDirection>()
            .unwrap_err()
            .contains("along-track"));
        let b = budget(&input(400e3, 51.6, SeparationDirection::AlongTrack)).unwrap();
        let json: serde_json::Value = serde_json::to_value(&b).unwrap();
        assert_eq!(json["direction"], "along-track");
        assert_eq!(json["atmosphere"], "harris-priester");
        let names: Vec<&str> = json["terms"]
            .as_array()
            .unwrap()
            .iter()
            .map(|t| t["term"].as_str().unwrap())
            .collect();
        assert_eq!(names, Term::ALL.map(Term::name));
        assert!(json["terms"][9]["acceleration_mps2"].is_null());
    }
}
