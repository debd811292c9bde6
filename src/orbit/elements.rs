//! Classical Keplerian elements of an elliptic orbit ([`KeplerianElements`]), their conversion to and
//! from an inertial Cartesian state, and the error type of the `orbit` module ([`OrbitError`]).
//!
//! # Conventions for the singular cases
//!
//! The classical angles are undefined for circular or equatorial orbits. The conversions never return
//! NaN; they use these conventions instead:
//!
//! * **circular** (`e <= CIRCULAR_ECCENTRICITY_TOLERANCE`): `eccentricity = 0`, `arg_perigee_rad = 0`
//!   and `true_anomaly_rad` is the argument of latitude (angle from the ascending node to the
//!   satellite);
//! * **equatorial** (`sin i <= EQUATORIAL_SIN_INCLINATION_TOLERANCE`): `inclination_rad` is exactly
//!   `0` (prograde) or `pi` (retrograde), `raan_rad = 0`, and the line of nodes is taken as the ECI
//!   x axis, so `arg_perigee_rad` is measured from the x axis (longitude of perigee for `i = 0`);
//! * **both**: `true_anomaly_rad` is the true longitude measured from the x axis (for `i = pi` the
//!   angle is measured in the retrograde sense, i.e. about the orbit normal `-z`).
//!
//! Only the sums of the undefined angles are physical (`raan + arg_perigee + true_anomaly` when
//! equatorial prograde, `arg_perigee + true_anomaly` when circular), and both conversions use them
//! consistently, so a Cartesian state survives a round trip to rounding in every case, except that a
//! state within the two thresholds is moved onto the exactly circular or equatorial orbit (a change
//! of at most 1e-13 relative, see the constants).

use std::f64::consts::{PI, TAU};

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::state::CartesianState;

/// Eccentricity at or below which an orbit is reported as circular (see the module docs). The
/// eccentricity vector computed from the Cartesian state of an exactly circular orbit carries rounding
/// noise up to ~1e-15 (measured over 10^4 LEO-to-GEO states); the threshold sits 100 times above that.
/// Treating an orbit of true eccentricity `e <= 1e-13` as circular moves the reconstructed position by
/// at most `a e`, i.e. 1e-13 relative (0.7 um in LEO).
pub const CIRCULAR_ECCENTRICITY_TOLERANCE: f64 = 1e-13;

/// Value of `sin(inclination)` at or below which an orbit is reported as equatorial (see the module
/// docs). The rounding noise of `sin i` for an exactly equatorial state is `sin(pi)` = 1.2e-16 for
/// retrograde orbits built from `i = pi` (zero for `i = 0`); the threshold sits ~100 times above it.
/// Snapping moves the reconstructed position out of plane by at most `r sin i`, 1e-14 relative.
pub const EQUATORIAL_SIN_INCLINATION_TOLERANCE: f64 = 1e-14;

/// Errors of the `orbit` module. Each message names the offending value and the allowed range.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum OrbitError {
    /// Eccentricity outside the elliptic range `[0, 1)`.
    #[error("eccentricity {eccentricity} is outside the elliptic range [0, 1)")]
    InvalidEccentricity {
        /// The rejected eccentricity \[dimensionless\].
        eccentricity: f64,
    },
    /// Semi-major axis that is not a positive finite length.
    #[error("semi-major axis {semi_major_axis_m} m must be finite and > 0 (elliptic orbits only)")]
    NonPositiveSemiMajorAxis {
        /// The rejected semi-major axis \[m\].
        semi_major_axis_m: f64,
    },
    /// Inclination outside `[0, pi]`.
    #[error("inclination {inclination_rad} rad is outside [0, pi]")]
    InvalidInclination {
        /// The rejected inclination \[rad\].
        inclination_rad: f64,
    },
    /// An angle (RAAN, argument of perigee or true anomaly) that is NaN or infinite.
    #[error("{name} {value} rad must be finite")]
    NonFiniteAngle {
        /// Which element (`"raan"`, `"arg_perigee"` or `"true_anomaly"`).
        name: &'static str,
        /// The rejected value \[rad\].
        value: f64,
    },
    /// Gravitational parameter that is not a positive finite number.
    #[error("gravitational parameter {mu_m3_s2} m^3/s^2 must be finite and > 0")]
    InvalidGravitationalParameter {
        /// The rejected parameter \[m^3/s^2\].
        mu_m3_s2: f64,
    },
    /// A position or velocity component that is NaN or infinite.
    #[error("Cartesian state has a non-finite component (position {position_m:?} m, velocity {velocity_mps:?} m/s); all must be finite")]
    NonFiniteState {
        /// The rejected ECI position \[m\].
        position_m: [f64; 3],
        /// The rejected ECI velocity \[m/s\].
        velocity_mps: [f64; 3],
    },
    /// Position at the Earth's centre, where no orbit is defined.
    #[error("position vector has zero length; orbital elements need |r| > 0 m")]
    ZeroPosition,
    /// Position and velocity parallel: a rectilinear (radial) trajectory has no orbital plane.
    #[error("specific angular momentum |r x v| is zero (rectilinear trajectory); orbital elements need |r x v| > 0 m^2/s")]
    ZeroAngularMomentum,
    /// The state is on a parabolic or hyperbolic trajectory; only elliptic orbits are supported.
    #[error("trajectory is not elliptic: specific energy {specific_energy_j_kg} J/kg (must be < 0), eccentricity {eccentricity} (must be < 1)")]
    NotElliptic {
        /// Two-body specific energy of the state \[J/kg\].
        specific_energy_j_kg: f64,
        /// Eccentricity of the state \[dimensionless\].
        eccentricity: f64,
    },
    /// A gravity model name that is not recognised.
    #[error("unknown gravity model \"{name}\"; valid names: {valid}")]
    UnknownGravityModel {
        /// The rejected name.
        name: String,
        /// The accepted names, comma-separated.
        valid: &'static str,
    },
}

/// Classical (osculating) Keplerian elements of an elliptic orbit about the ECI origin. Angles are
/// referred to the ECI frame (x axis = reference direction, z axis = Earth's polar axis). See the
/// module docs for the values of the undefined angles on circular and equatorial orbits.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct KeplerianElements {
    /// Semi-major axis `a` \[m\], `> 0`.
    pub semi_major_axis_m: f64,
    /// Eccentricity `e` \[dimensionless\], `0 <= e < 1`.
    pub eccentricity: f64,
    /// Inclination `i` of the orbit normal to the ECI z axis \[rad\], `0 <= i <= pi`.
    pub inclination_rad: f64,
    /// Right ascension of the ascending node `Omega`, from the ECI x axis \[rad\]; any finite value on
    /// input, `[0, 2 pi)` on output.
    pub raan_rad: f64,
    /// Argument of perigee `omega`, from the ascending node \[rad\]; any finite value on input,
    /// `[0, 2 pi)` on output.
    pub arg_perigee_rad: f64,
    /// True anomaly `nu`, from perigee \[rad\]; any finite value on input, `[0, 2 pi)` on output.
    pub true_anomaly_rad: f64,
}

impl KeplerianElements {
    /// ECI position and velocity of these elements about a body of gravitational parameter
    /// `mu_m3_s2` \[m^3/s^2\].
    ///
    /// # Errors
    /// [`OrbitError`] if `mu` is not positive and finite, `a <= 0` or non-finite, `e` outside
    /// `[0, 1)`, `i` outside `[0, pi]`, or an angle is non-finite.
    pub fn to_cartesian(&self, mu_m3_s2: f64) -> Result<CartesianState, OrbitError> {
        check_mu(mu_m3_s2)?;
        self.validate()?;
        let e = self.eccentricity;
        // Semi-latus rectum p = a (1 - e^2), factored to keep precision as e -> 1.
        let p = self.semi_major_axis_m * (1.0 - e) * (1.0 + e);
        let cos_nu = self.true_anomaly_rad.cos();
        let (sin_w, cos_w) = self.arg_perigee_rad.sin_cos();
        let (sin_u, cos_u) = (self.arg_perigee_rad + self.true_anomaly_rad).sin_cos();
        let (sin_raan, cos_raan) = self.raan_rad.sin_cos();
        let (sin_i, cos_i) = self.inclination_rad.sin_cos();
        // Unit vectors of the orbital plane: n toward the ascending node, m = h_hat x n.
        let n_hat = Vector3::new(cos_raan, sin_raan, 0.0);
        let m_hat = Vector3::new(-sin_raan * cos_i, cos_raan * cos_i, sin_i);
        let radius = p / (1.0 + e * cos_nu);
        let speed_scale = (mu_m3_s2 / p).sqrt();
        let position_m = radius * (cos_u * n_hat + sin_u * m_hat);
        // v = sqrt(mu/p) [-(sin u + e sin w) n + (cos u + e cos w) m]: the perifocal velocity
        // sqrt(mu/p) (-sin nu, e + cos nu) rotated by the argument of perigee.
        let velocity_mps =
            speed_scale * (-(sin_u + e * sin_w) * n_hat + (cos_u + e * cos_w) * m_hat);
        Ok(CartesianState::new(position_m, velocity_mps))
    }

    /// Elements of the ECI state `state` about a body of gravitational parameter `mu_m3_s2`
    /// \[m^3/s^2\]. Angles are returned in `[0, 2 pi)` (inclination in `[0, pi]`); see the module docs
    /// for circular and equatorial orbits.
    ///
    /// # Errors
    /// [`OrbitError`] if `mu` is not positive and finite, the state is non-finite, the position is
    /// zero, `r x v = 0`, or the orbit is parabolic or hyperbolic.
    pub fn from_cartesian(
        state: &CartesianState,
        mu_m3_s2: f64,
    ) -> Result<KeplerianElements, OrbitError> {
        check_mu(mu_m3_s2)?;
        let r_vec = state.position_m;
        let v_vec = state.velocity_mps;
        if !(r_vec.iter().all(|c| c.is_finite()) && v_vec.iter().all(|c| c.is_finite())) {
            return Err(OrbitError::NonFiniteState {
                position_m: r_vec.into(),
                velocity_mps: v_vec.into(),
            });
        }
        let r = r_vec.norm();
        if r == 0.0 {
            return Err(OrbitError::ZeroPosition);
        }
        let h_vec = r_vec.cross(&v_vec);
        let h = h_vec.norm();
        if h == 0.0 {
            return Err(OrbitError::ZeroAngularMomentum);
        }
        let v2 = v_vec.norm_squared();
        let energy = 0.5 * v2 - mu_m3_s2 / r;
        let e_vec = ((v2 - mu_m3_s2 / r) * r_vec - r_vec.dot(&v_vec) * v_vec) / mu_m3_s2;
        let e = e_vec.norm();
        if !(energy < 0.0 && e < 1.0) {
            return Err(OrbitError::NotElliptic {
                specific_energy_j_kg: energy,
                eccentricity: e,
            });
        }
        let a = -mu_m3_s2 / (2.0 * energy);

        // Line of nodes n = z x h = (-h_y, h_x, 0), |n| = h sin i.
        let node_norm = h_vec.x.hypot(h_vec.y);
        let (inclination, raan, cos_raan, sin_raan, cos_i, sin_i) =
            if node_norm <= EQUATORIAL_SIN_INCLINATION_TOLERANCE * h {
                // Equatorial: node along +x, i exactly 0 or pi.
                let retrograde = h_vec.z < 0.0;
                let i = if retrograde { PI } else { 0.0 };
                let cos_i = if retrograde { -1.0 } else { 1.0 };
                (i, 0.0, 1.0, 0.0, cos_i, 0.0)
            } else {
                let cos_raan = -h_vec.y / node_norm;
                let sin_raan = h_vec.x / node_norm;
                (
                    node_norm.atan2(h_vec.z),
                    wrap_two_pi(sin_raan.atan2(cos_raan)),
                    cos_raan,
                    sin_raan,
                    h_vec.z / h,
                    node_norm / h,
                )
            };
        // Same in-plane basis as `to_cartesian` builds from (raan, i).
        let n_hat = Vector3::new(cos_raan, sin_raan, 0.0);
        let m_hat = Vector3::new(-sin_raan * cos_i, cos_raan * cos_i, sin_i);
        let arg_latitude = r_vec.dot(&m_hat).atan2(r_vec.dot(&n_hat));

        let (eccentricity, arg_perigee) = if e <= CIRCULAR_ECCENTRICITY_TOLERANCE {
            (0.0, 0.0)
        } else {
            (e, e_vec.dot(&m_hat).atan2(e_vec.dot(&n_hat)))
        };
        Ok(KeplerianElements {
            semi_major_axis_m: a,
            eccentricity,
            inclination_rad: inclination,
            raan_rad: raan,
            arg_perigee_rad: wrap_two_pi(arg_perigee),
            true_anomaly_rad: wrap_two_pi(arg_latitude - arg_perigee),
        })
    }

    /// Argument of latitude `u = omega + nu` \[rad\] in `[0, 2 pi)`: the angle from the ascending node
    /// (the ECI x axis for equatorial orbits) to the satellite, in the direction of motion.
    pub fn argument_of_latitude_rad(&self) -> f64 {
        wrap_two_pi(self.arg_perigee_rad + self.true_anomaly_rad)
    }

    fn validate(&self) -> Result<(), OrbitError> {
        let a = self.semi_major_axis_m;
        if !(a.is_finite() && a > 0.0) {
            return Err(OrbitError::NonPositiveSemiMajorAxis {
                semi_major_axis_m: a,
            });
        }
        let e = self.eccentricity;
        if !((0.0..1.0).contains(&e)) {
            return Err(OrbitError::InvalidEccentricity { eccentricity: e });
        }
        let i = self.inclination_rad;
        if !((0.0..=PI).contains(&i)) {
            return Err(OrbitError::InvalidInclination { inclination_rad: i });
        }
        for (name, value) in [
            ("raan", self.raan_rad),
            ("arg_perigee", self.arg_perigee_rad),
            ("true_anomaly", self.true_anomaly_rad),
        ] {
            if !value.is_finite() {
                return Err(OrbitError::NonFiniteAngle { name, value });
            }
        }
        Ok(())
    }
}

fn check_mu(mu_m3_s2: f64) -> Result<(), OrbitError> {
    if mu_m3_s2.is_finite() && mu_m3_s2 > 0.0 {
        Ok(())
    } else {
        Err(OrbitError::InvalidGravitationalParameter { mu_m3_s2 })
    }
}

/// Angle reduced to `[0, 2 pi)`.
fn wrap_two_pi(angle_rad: f64) -> f64 {
    let wrapped = angle_rad.rem_euclid(TAU);
    // rem_euclid may round a tiny negative angle up to exactly 2 pi.
    if wrapped >= TAU {
        0.0
    } else {
        wrapped
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_keeps_result_below_two_pi() {
        assert_eq!(wrap_two_pi(-1e-300), 0.0);
        assert_eq!(wrap_two_pi(TAU), 0.0);
        assert!((wrap_two_pi(-0.5) - (TAU - 0.5)).abs() < 1e-15);
    }

    #[test]
    fn invalid_elements_are_rejected_with_their_value() {
        let good = KeplerianElements {
            semi_major_axis_m: 7.0e6,
            eccentricity: 0.1,
            inclination_rad: 1.0,
            raan_rad: 0.0,
            arg_perigee_rad: 0.0,
            true_anomaly_rad: 0.0,
        };
        let mu = 3.986004418e14;
        let cases = [
            (
                KeplerianElements {
                    eccentricity: 1.0,
                    ..good
                },
                OrbitError::InvalidEccentricity { eccentricity: 1.0 },
            ),
            (
                KeplerianElements {
                    semi_major_axis_m: -1.0,
                    ..good
                },
                OrbitError::NonPositiveSemiMajorAxis {
                    semi_major_axis_m: -1.0,
                },
            ),
            (
                KeplerianElements {
                    inclination_rad: 4.0,
                    ..good
                },
                OrbitError::InvalidInclination {
                    inclination_rad: 4.0,
                },
            ),
            (
                KeplerianElements {
                    raan_rad: f64::INFINITY,
                    ..good
                },
                OrbitError::NonFiniteAngle {
                    name: "raan",
                    value: f64::INFINITY,
                },
            ),
        ];
        for (elements, expected) in cases {
            assert_eq!(elements.to_cartesian(mu), Err(expected));
        }
        assert_eq!(
            good.to_cartesian(-1.0),
            Err(OrbitError::InvalidGravitationalParameter { mu_m3_s2: -1.0 })
        );
        let msg = OrbitError::InvalidEccentricity { eccentricity: 1.5 }.to_string();
        assert!(msg.contains("1.5") && msg.contains("[0, 1)"), "{msg}");
    }

    #[test]
    fn degenerate_states_are_rejected() {
        let mu = 3.986004418e14;
        let r = Vector3::new(7.0e6, 0.0, 0.0);
        let zero = CartesianState::new(Vector3::zeros(), Vector3::new(0.0, 7.5e3, 0.0));
        assert_eq!(
            KeplerianElements::from_cartesian(&zero, mu),
            Err(OrbitError::ZeroPosition)
        );
        let radial = CartesianState::new(r, Vector3::new(100.0, 0.0, 0.0));
        assert_eq!(
            KeplerianElements::from_cartesian(&radial, mu),
            Err(OrbitError::ZeroAngularMomentum)
        );
        // Escape speed at 7000 km is sqrt(2 mu / r) = 10.67 km/s; 11 km/s is hyperbolic.
        let hyperbolic = CartesianState::new(r, Vector3::new(0.0, 11.0e3, 0.0));
        assert!(matches!(
            KeplerianElements::from_cartesian(&hyperbolic, mu),
            Err(OrbitError::NotElliptic { .. })
        ));
        let nan = CartesianState::new(Vector3::new(f64::NAN, 0.0, 0.0), Vector3::zeros());
        assert!(matches!(
            KeplerianElements::from_cartesian(&nan, mu),
            Err(OrbitError::NonFiniteState { .. })
        ));
    }
}
