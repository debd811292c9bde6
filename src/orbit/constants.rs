//! Earth constants: gravitational parameter, equatorial radius and the J2 zonal coefficient
//! ([`EarthModel`]), with the mean motion and period of a Keplerian orbit they imply.

use serde::{Deserialize, Serialize};

/// The Earth's gravity field constants used by the point-mass and J2 models.
///
/// All values are SI. The model is a plain value type so that a scenario can override any constant
/// (for example to reproduce a paper that used `mu = 398600 km^3/s^2`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct EarthModel {
    /// Geocentric gravitational parameter `mu = G M` \[m^3/s^2\].
    pub mu_m3_s2: f64,
    /// Reference (equatorial) radius `R` of the spherical-harmonic expansion \[m\].
    pub equatorial_radius_m: f64,
    /// Unnormalised second zonal harmonic coefficient `J2` \[dimensionless\]. The potential is
    /// `U = (mu/r) (1 - J2 (R/r)^2 P2(z/r))` with `P2(s) = (3 s^2 - 1)/2`.
    pub j2: f64,
}

impl EarthModel {
    /// The project's default Earth constants: WGS 84 mu and radius with the EGM96 J2, the set most
    /// astrodynamics software uses. Sources:
    ///
    /// * `mu_m3_s2 = 3.986004418e14` m^3/s^2: WGS 84 (NGA.STND.0036, 2014) and IERS Conventions (2010)
    ///   Table 1.1 (TCG-compatible). The EGM2008 coefficient file itself carries
    ///   `GM = 3.986004415e14` (TT-compatible), 7.5e-10 relative smaller;
    /// * `equatorial_radius_m = 6378137.0` m: WGS 84 semi-major axis. The EGM2008 file's reference
    ///   radius is `6378136.3` m, 1.1e-7 relative smaller;
    /// * `j2 = 1.08262668e-3`: `J2 = -sqrt(5) C̄20` with the **EGM96** fully normalised coefficient
    ///   `C̄20 = -0.484165371736e-3` (Lemoine et al., NASA/TP-1998-206861), i.e. 1.0826266836e-3
    ///   rounded to 9 significant figures. The EGM2008 tide-free `C̄20 = -0.484165143790815e-3`
    ///   (Pavlis et al., J. Geophys. Res. 117, B04406, 2012) gives `J2 = 1.0826261739e-3`,
    ///   4.7e-7 relative smaller, far below anything a J2-only model resolves.
    pub const WGS84_EGM96: EarthModel = EarthModel {
        mu_m3_s2: 3.986004418e14,
        equatorial_radius_m: 6_378_137.0,
        j2: 1.082_626_68e-3,
    };

    /// Keplerian mean motion `n = sqrt(mu / a^3)` \[rad/s\] of an orbit with semi-major axis
    /// `semi_major_axis_m` \[m\]. Returns NaN for a negative axis and infinity for zero.
    pub fn mean_motion_rad_s(&self, semi_major_axis_m: f64) -> f64 {
        (self.mu_m3_s2 / (semi_major_axis_m * semi_major_axis_m * semi_major_axis_m)).sqrt()
    }

    /// Keplerian period `T = 2 pi sqrt(a^3 / mu)` \[s\] of an orbit with semi-major axis
    /// `semi_major_axis_m` \[m\]. Returns NaN for a negative axis and zero for a zero axis.
    pub fn period_s(&self, semi_major_axis_m: f64) -> f64 {
        std::f64::consts::TAU / self.mean_motion_rad_s(semi_major_axis_m)
    }
}

impl Default for EarthModel {
    /// [`EarthModel::WGS84_EGM96`].
    fn default() -> Self {
        EarthModel::WGS84_EGM96
    }
}
