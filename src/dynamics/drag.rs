//! Atmospheric drag ([`Drag`]): `a = -1/2 rho (C_d A / m) |v_rel| v_rel` with the density of an
//! [`Atmosphere`] at the satellite's height (above the sphere of the equatorial radius, or geodetic
//! above WGS-84: [`geodetic_altitude_m`]) and the velocity relative to an atmosphere that co-rotates
//! with the Earth (`v_rel = v - omega_E z × r`, [`EARTH_ROTATION_RAD_S`]) or is at rest in ECI. The
//! acceleration itself is one function, [`drag_acceleration_m_s2`], whose operation order the fused
//! SIMD kernel copies bit for bit, with the speed from [`speed_from_square_m_s`] (no double-precision
//! square root, the fused kernel's scarcest unit).

use nalgebra::Vector3;

use super::atmosphere::{self, Atmosphere, Exponential};
use super::config::{AltitudeName, AtmosphereName, DragConfig, ForceConfigError};
use super::{Bodies, ForceModel, Instant, PhysicalProperties};
use crate::orbit::EarthModel;

/// The Earth's rotation rate omega_E \[rad/s\] (the nominal mean angular velocity of WGS-84,
/// 7.292115e-5 rad/s, NGA.STND.0036 2014), about the ECI z axis.
pub const EARTH_ROTATION_RAD_S: f64 = 7.292_115e-5;

/// The WGS-84 ellipsoid's semi-major axis a \[m\] (NGA.STND.0036, 2014).
pub const WGS84_SEMI_MAJOR_AXIS_M: f64 = 6_378_137.0;
/// The WGS-84 ellipsoid's flattening f \[dimensionless\] (1 / 298.257223563).
pub const WGS84_FLATTENING: f64 = 1.0 / 298.257_223_563;

/// The geodetic height \[m\] above the WGS-84 ellipsoid of the point `position_eci_m` \[m, ECI\].
///
/// The ellipsoid is symmetric about the z axis, which ECI and the Earth-fixed frame share (the crate
/// neglects precession, nutation and polar motion), so the height depends only on the distance from
/// the axis `p = sqrt(x^2 + y^2)` and on `z`: no Earth rotation angle is needed and ECI coordinates
/// serve directly.
///
/// Heikkinen's closed form (M. Heikkinen, Z. Vermessungswesen 107, 1982, 207–211; as given by J. Zhu,
/// IEEE Trans. Aerosp. Electron. Syst. 30(3), 1994, 957–961): exact (no iteration) for every point
/// farther than ~43 km from the Earth's centre, including the poles (p = 0) and the equator (z = 0).
/// Round trips from (latitude, longitude, height) agree to a few nanometres from -5 to 2 000 km. Deep
/// inside the Earth (within ~43 km of the centre) the result may be NaN, which the engine treats as
/// below the floor.
pub fn geodetic_altitude_m(position_eci_m: &Vector3<f64>) -> f64 {
    let a = WGS84_SEMI_MAJOR_AXIS_M;
    let b = a * (1.0 - WGS84_FLATTENING);
    let e2 = WGS84_FLATTENING * (2.0 - WGS84_FLATTENING);
    let (x, y, z) = (position_eci_m.x, position_eci_m.y, position_eci_m.z);
    let p2 = x * x + y * y;
    let p = p2.sqrt();
    let z2 = z * z;
    let big_e2 = a * a - b * b;
    let f = 54.0 * b * b * z2;
    let g = p2 + (1.0 - e2) * z2 - e2 * big_e2;
    let c = e2 * e2 * f * p2 / (g * g * g);
    let s = (1.0 + c + (c * c + 2.0 * c).sqrt()).cbrt();
    let k = s + 1.0 + 1.0 / s;
    let big_p = f / (3.0 * k * k * g * g);
    let q = (1.0 + 2.0 * e2 * e2 * big_p).sqrt();
    // Analytically >= 0; at the poles it is 0 and rounding can make it -1e-19 (`<` keeps NaN).
    let radicand = 0.5 * a * a * (1.0 + 1.0 / q)
        - big_p * (1.0 - e2) * z2 / (q * (1.0 + q))
        - 0.5 * big_p * p2;
    let radicand = if radicand < 0.0 { 0.0 } else { radicand };
    let r0 = -(big_p * e2 * p) / (1.0 + q) + radicand.sqrt();
    let dp = p - e2 * r0;
    let u = (dp * dp + z2).sqrt();
    let v = (dp * dp + (1.0 - e2) * z2).sqrt();
    u * (1.0 - b * b / (a * v))
}

/// The drag acceleration \[m/s^2\], ECI: `-1/2 rho (C_d A / m) |v_rel| v_rel`, for the density
/// `density_kg_per_m3` \[kg/m^3\], the ballistic term `area_per_mass_m2_per_kg` = C_d A / m \[m^2/kg\]
/// ([`PhysicalProperties::drag_area_per_mass_m2_per_kg`]), the position `position_eci_m` \[m\] and
/// velocity `velocity_eci_mps` \[m/s\] (ECI). With `corotation` the air moves with the Earth,
/// `v_rel = v - omega_E z × r` ([`EARTH_ROTATION_RAD_S`]); else `v_rel = v`.
///
/// The scalar operation order is fixed (the fused SIMD kernel reproduces these bits); `|v_rel|` is
/// [`speed_from_square_m_s`].
#[inline]
pub fn drag_acceleration_m_s2(
    density_kg_per_m3: f64,
    area_per_mass_m2_per_kg: f64,
    position_eci_m: &Vector3<f64>,
    velocity_eci_mps: &Vector3<f64>,
    corotation: bool,
) -> Vector3<f64> {
    let (r, v) = (position_eci_m, velocity_eci_mps);
    let (vx, vy, vz) = if corotation {
        (
            v.x + EARTH_ROTATION_RAD_S * r.y,
            v.y - EARTH_ROTATION_RAD_S * r.x,
            v.z,
        )
    } else {
        (v.x, v.y, v.z)
    };
    let speed = speed_from_square_m_s(vx * vx + vy * vy + vz * vz);
    let k = density_kg_per_m3 * (-0.5 * area_per_mass_m2_per_kg) * speed;
    Vector3::new(k * vx, k * vy, k * vz)
}

/// Smallest square of a speed [`speed_from_square_m_s`] takes \[m^2/s^2\] (smaller ones are raised to
/// it): just above the least normal `f32`, a speed of 1.1e-19 m/s.
const SMALLEST_SPEED_SQUARED_M2_S2: f64 = 1.2e-38;

/// The speed \[m/s\] whose square is `speed_squared_m2_s2` \[m^2/s^2\], within 1 ulp of
/// `speed_squared_m2_s2.sqrt()` (tested), for squares from 1.2e-38 to 3.4e38 (speeds from 1.1e-19 to
/// 1.8e19 m/s; a smaller square is taken as 1.2e-38, a larger one gives NaN).
///
/// The double-precision square root (and division) unit is the fused kernel's bottleneck: on the
/// Intel Xeon where this was measured the J2 step alone keeps it busy (three divisions and one square
/// root per satellite and stage), so a second `f64` square root for drag costs a third more time. Here
/// the root is seeded in single precision (`f32` square root and reciprocal, correctly rounded IEEE
/// operations, a quarter of the unit's time, relative error below 1e-7) and refined by two Newton
/// steps for the root in `f64`, `s <- s + (1 / 2 s_0) (x - s^2)` (error about 1e-14 after the first,
/// below the rounding after the second). Plain IEEE operations without fused multiply-add: every SIMD
/// copy of the fused kernel and the generic path give the same bits.
#[inline(always)]
pub fn speed_from_square_m_s(speed_squared_m2_s2: f64) -> f64 {
    let square = speed_squared_m2_s2.max(SMALLEST_SPEED_SQUARED_M2_S2);
    let seed = (square as f32).sqrt();
    let half_reciprocal = f64::from(0.5_f32 / seed);
    let speed = f64::from(seed);
    let speed = speed + half_reciprocal * (square - speed * speed);
    speed + half_reciprocal * (square - speed * speed)
}

/// Atmospheric drag on a cannonball satellite: the density of an [`Atmosphere`] at the satellite's
/// height, its C_d A / m, and the velocity relative to the (co-rotating or inertial) air.
#[derive(Debug)]
pub struct Drag {
    atmosphere: Box<dyn Atmosphere>,
    /// The one-layer exponential atmosphere when that is the model (the fused kernel's form).
    exponential: Option<Exponential>,
    /// Whether the atmosphere co-rotates with the Earth.
    corotation: bool,
    /// Which height the density is evaluated at.
    altitude: AltitudeName,
    /// The sphere's radius of the spherical height \[m\] (the Earth model's equatorial radius).
    equatorial_radius_m: f64,
}

impl Drag {
    /// The drag a `[drag]` table describes, for the Earth constants `earth` (whose equatorial radius
    /// is the sphere of the spherical height; the geodetic height uses WGS-84 whatever `earth` is).
    ///
    /// # Errors
    /// A [`ForceConfigError`] naming the key when an atmosphere's parameter is missing, out of range
    /// or given to a model that does not read it.
    pub fn from_config(config: &DragConfig, earth: &EarthModel) -> Result<Self, ForceConfigError> {
        let atmosphere = atmosphere::build(config)?;
        let exponential = match config.atmosphere {
            AtmosphereName::Exponential => Some(Exponential::from_config(config)?),
            AtmosphereName::ExponentialTable | AtmosphereName::HarrisPriester => None,
        };
        Ok(Self {
            atmosphere,
            exponential,
            corotation: config.corotation,
            altitude: config.altitude,
            equatorial_radius_m: earth.equatorial_radius_m,
        })
    }

    /// The height \[m\] the density is evaluated at, of a satellite at `position_eci_m` \[m, ECI\]:
    /// spherical, exactly `(x * x + y * y + z * z).sqrt() - equatorial_radius_m` (the fused kernel's
    /// bits), or geodetic above WGS-84 ([`geodetic_altitude_m`]).
    #[inline]
    pub fn altitude_m(&self, position_eci_m: &Vector3<f64>) -> f64 {
        match self.altitude {
            AltitudeName::Spherical => {
                let (x, y, z) = (position_eci_m.x, position_eci_m.y, position_eci_m.z);
                (x * x + y * y + z * z).sqrt() - self.equatorial_radius_m
            }
            AltitudeName::Geodetic => geodetic_altitude_m(position_eci_m),
        }
    }

    /// A distance from the Earth's centre \[m\] beyond which every position is surely above the
    /// atmosphere's floor, whichever height is used: a geodetic height is at least the distance from
    /// the centre less WGS-84's equatorial radius, and 100 m more cover the heights' rounding (far
    /// below a millimetre).
    pub fn clear_of_floor_radius_m(&self) -> f64 {
        self.equatorial_radius_m.max(WGS84_SEMI_MAJOR_AXIS_M)
            + self.atmosphere.floor_altitude_m()
            + 100.0
    }

    /// The one-layer exponential atmosphere and the co-rotation flag, when this drag is the fused
    /// kernel's form (exponential density at spherical altitude); else `None`.
    pub fn fast_exponential(&self) -> Option<(Exponential, bool)> {
        match (self.exponential, self.altitude) {
            (Some(exponential), AltitudeName::Spherical) => Some((exponential, self.corotation)),
            _ => None,
        }
    }

    /// The density model.
    pub fn atmosphere(&self) -> &dyn Atmosphere {
        self.atmosphere.as_ref()
    }

    /// Whether the atmosphere co-rotates with the Earth.
    pub fn corotation(&self) -> bool {
        self.corotation
    }

    /// Which height the density is evaluated at.
    pub fn altitude_kind(&self) -> AltitudeName {
        self.altitude
    }

    /// The density \[kg/m^3\] at a satellite at `position_eci_m` \[m, ECI\] at `at` (the Sun's position
    /// is read only when the atmosphere uses it).
    #[inline]
    pub fn density_kg_per_m3(&self, at: &Instant, position_eci_m: &Vector3<f64>) -> f64 {
        let altitude_m = self.altitude_m(position_eci_m);
        let sun_eci_m = if self.atmosphere.uses_sun() {
            at.sun_eci_m()
        } else {
            Vector3::zeros()
        };
        self.atmosphere
            .density_kg_per_m3(altitude_m, position_eci_m, &sun_eci_m)
    }
}

impl ForceModel for Drag {
    /// `drag (<atmosphere>, co-rotating|inertial atmosphere, spherical|geodetic altitude)`.
    fn name(&self) -> String {
        format!(
            "drag ({}, {}, {} altitude)",
            self.atmosphere.name(),
            if self.corotation {
                "co-rotating"
            } else {
                "inertial atmosphere"
            },
            match self.altitude {
                AltitudeName::Spherical => "spherical",
                AltitudeName::Geodetic => "geodetic",
            }
        )
    }

    #[inline]
    fn acceleration_eci_m_s2(
        &self,
        at: &Instant,
        position_eci_m: &Vector3<f64>,
        velocity_eci_mps: &Vector3<f64>,
        properties: &PhysicalProperties,
    ) -> Vector3<f64> {
        drag_acceleration_m_s2(
            self.density_kg_per_m3(at, position_eci_m),
            properties.drag_area_per_mass_m2_per_kg(),
            position_eci_m,
            velocity_eci_mps,
            self.corotation,
        )
    }

    /// The Sun when the atmosphere reads it (Harris–Priester), else nothing.
    fn bodies(&self) -> Bodies {
        Bodies {
            sun: self.atmosphere.uses_sun(),
            moon: false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Within 1 ulp of the correctly rounded `f64::sqrt` for squares over the whole range (every
    /// binade, 4 000 mantissas each) and densely over LEO speeds (3 to 11 km/s); the smallest squares
    /// are raised to the floor, and a zero speed gives the floor's root (a drag of zero for every
    /// purpose: it multiplies a zero relative velocity).
    #[test]
    fn speed_within_one_ulp_of_the_square_root() {
        let mut exact = 0;
        let mut total = 0;
        let mut check = |square: f64| {
            let want = square.sqrt();
            let got = speed_from_square_m_s(square);
            let ulp = f64::from_bits(want.to_bits() + 1) - want;
            let err = (got - want).abs() / ulp;
            assert!(
                err <= 1.0,
                "speed of {square}: {got}, sqrt {want}: {err} ulp"
            );
            exact += usize::from(got == want);
            total += 1;
        };
        let mut binade = SMALLEST_SPEED_SQUARED_M2_S2;
        while binade < 1.6e38 {
            for k in 0..4000 {
                check(binade * (1.0 + k as f64 / 4000.0 + 1e-9 * (k % 7) as f64));
            }
            binade *= 2.0;
        }
        for i in 0..=200_000 {
            let speed = 3e3 + 8e3 * i as f64 / 200_000.0;
            check(speed * speed);
        }
        assert!(
            total > 500_000 && exact > total / 2,
            "{exact} of {total} exact"
        );
        let floor = SMALLEST_SPEED_SQUARED_M2_S2.sqrt();
        for tiny in [0.0, 1e-300, 1e-40] {
            assert!((speed_from_square_m_s(tiny) - floor).abs() <= 1e-16 * floor);
        }
    }

    fn exponential_config() -> DragConfig {
        let mut c = DragConfig::new(AtmosphereName::Exponential);
        c.reference_density_kg_per_m3 = Some(3.725e-12);
        c.reference_altitude_m = Some(400e3);
        c.scale_height_m = Some(58_515.0);
        c
    }

    /// WGS-84 b = a (1 - f) = 6 356 752.314245179 m (NGA.STND.0036 prints 6 356 752.3142 m).
    const B: f64 = 6_356_752.314_245_179;

    /// (latitude, longitude, height) to the Earth-fixed position by the standard closed form, with
    /// the prime-vertical radius N = a / sqrt(1 - e^2 sin^2 lat): x = (N + h) cos lat cos lon,
    /// y = (N + h) cos lat sin lon, z = (N (1 - e^2) + h) sin lat.
    fn geodetic_to_cartesian(lat: f64, lon: f64, h: f64) -> Vector3<f64> {
        let a = 6_378_137.0;
        let f = 1.0 / 298.257_223_563;
        let e2: f64 = f * (2.0 - f);
        let (s, c) = lat.sin_cos();
        let n = a / (1.0 - e2 * s * s).sqrt();
        Vector3::new(
            (n + h) * c * lon.cos(),
            (n + h) * c * lon.sin(),
            (n * (1.0 - e2) + h) * s,
        )
    }

    /// Heights on the equator (x = a + h) and over the poles (z = ±(b + h)) are h. Tolerance 1e-8 m:
    /// the coordinates are ~7e6 m, whose double spacing is 9.3e-10 m, and the closed form's roundings
    /// amount to a few of those (measured < 2e-9 m).
    #[test]
    fn geodetic_altitude_on_the_equator_and_at_the_poles() {
        for h in [0.0, 100e3, 400e3, 1000e3, 2000e3] {
            for (lon, sign) in [(0.0_f64, 1.0), (1.0, -1.0), (-2.5, 1.0)] {
                let r = Vector3::new(
                    (6_378_137.0 + h) * lon.cos(),
                    (6_378_137.0 + h) * lon.sin(),
                    0.0,
                );
                let got = geodetic_altitude_m(&r);
                assert!((got - h).abs() < 1e-8, "equator {h}: {got}");
                let pole = Vector3::new(0.0, 0.0, sign * (B + h));
                let got = geodetic_altitude_m(&pole);
                assert!((got - h).abs() < 1e-8, "pole {h}: {got}");
            }
        }
    }

    /// (lat, lon, h) -> Earth-fixed Cartesian (closed form above) -> [`geodetic_altitude_m`] gives h
    /// back, over latitudes from pole to pole (including within 1e-6 deg of a pole and of the equator)
    /// and heights from -5 km to 2 000 km. Tolerance 1e-8 m as above (the closed form of the forward
    /// map rounds too: a few 1e-9 m).
    #[test]
    fn geodetic_altitude_round_trip() {
        let mut worst: f64 = 0.0;
        for h in [-5e3, 0.0, 100e3, 250e3, 400e3, 780e3, 1000e3, 2000e3] {
            for lat_deg in [
                -90.0,
                -89.999_999,
                -64.3,
                -30.0,
                -1e-6,
                0.0,
                1e-6,
                10.0,
                45.0,
                51.6,
                80.0,
                89.9,
                89.999_999,
                90.0,
            ] {
                for lon_deg in [0.0, 37.0, -123.4, 180.0] {
                    let r = geodetic_to_cartesian(
                        f64::to_radians(lat_deg),
                        f64::to_radians(lon_deg),
                        h,
                    );
                    let err = geodetic_altitude_m(&r) - h;
                    worst = worst.max(err.abs());
                    assert!(err.abs() < 1e-8, "lat {lat_deg} lon {lon_deg} h {h}: {err}");
                }
            }
        }
        assert!(worst < 1e-8, "{worst}");
    }

    /// The drag acceleration against numbers worked out independently (30-digit arithmetic, mpmath).
    /// Satellite on +x at r = 6 778 137 m moving along +y at 7 668.56 m/s; rho = 3.725e-12 kg/m^3;
    /// C_d A / m = 2.2 * 0.1 / 10 = 0.022 m^2/kg. Co-rotating: omega_E r = 7.292115e-5 * 6 778 137 =
    /// 494.26954489755 m/s, so v_rel = (0, 7 174.29045510245, 0) m/s and
    /// a_y = -0.5 * 3.725e-12 * 0.022 * 7 174.29045510245^2 = -2.1090014238127845e-6 m/s^2. Inertial
    /// air: a_y = -0.5 * 3.725e-12 * 0.022 * 7 668.56^2 = -2.4096091411057600e-6 m/s^2. Relative
    /// tolerance 2e-15: about ten roundings of 1.1e-16 (inputs, the product, the square root).
    #[test]
    fn drag_acceleration_hand_values() {
        let r = Vector3::new(6_778_137.0, 0.0, 0.0);
        let v = Vector3::new(0.0, 7_668.56, 0.0);
        let a = drag_acceleration_m_s2(3.725e-12, 0.022, &r, &v, true);
        assert_eq!((a.x, a.z), (0.0, 0.0));
        assert!(
            (a.y / -2.109_001_423_812_784_7e-6 - 1.0).abs() < 2e-15,
            "{a}"
        );
        let a = drag_acceleration_m_s2(3.725e-12, 0.022, &r, &v, false);
        assert_eq!((a.x, a.z), (0.0, 0.0));
        assert!((a.y / -2.409_609_141_105_76e-6 - 1.0).abs() < 2e-15, "{a}");
        // Anti-parallel to v_rel in general, with |a| = 1/2 rho B |v_rel|^2: the same quantity by
        // nalgebra's cross product and norm, a different operation order (a few roundings of 1.1e-16
        // each, so < 1e-15 relative).
        let r = Vector3::new(4.0e6, -3.0e6, 4.5e6);
        let v = Vector3::new(2.0e3, 6.0e3, -3.0e3);
        let a = drag_acceleration_m_s2(1e-11, 0.05, &r, &v, true);
        let v_rel = v - Vector3::new(0.0, 0.0, EARTH_ROTATION_RAD_S).cross(&r);
        let want = -0.5 * 1e-11 * 0.05 * v_rel.norm() * v_rel;
        assert!((a - want).norm() < 1e-15 * want.norm(), "{a} vs {want}");
    }

    #[test]
    fn spherical_and_geodetic_altitudes() {
        let earth = EarthModel::WGS84_EGM96;
        let spherical = Drag::from_config(&exponential_config(), &earth).unwrap();
        let mut geodetic_config = exponential_config();
        geodetic_config.altitude = AltitudeName::Geodetic;
        let geodetic = Drag::from_config(&geodetic_config, &earth).unwrap();
        let over_pole = Vector3::new(0.0, 0.0, B + 400e3);
        // Over the pole the sphere of the equatorial radius is a - b = 21 384.685754821 m above the
        // ellipsoid. Tolerances 1e-8 m: the double spacing at 6.8e6 m is 9.3e-10 m and the decimal
        // values carry 1e-9 m.
        assert!((geodetic.altitude_m(&over_pole) - 400e3).abs() < 1e-8);
        let want = B + 400e3 - 6_378_137.0;
        assert_eq!(spherical.altitude_m(&over_pole), want);
        assert!((spherical.altitude_m(&over_pole) - (400e3 - 21_384.685_754_821)).abs() < 1e-8);
    }

    #[test]
    fn fast_form_bodies_and_names() {
        let earth = EarthModel::WGS84_EGM96;
        let drag = Drag::from_config(&exponential_config(), &earth).unwrap();
        let (layer, corotation) = drag.fast_exponential().unwrap();
        assert_eq!(layer, Exponential::new(3.725e-12, 400e3, 58_515.0).unwrap());
        assert!(corotation);
        assert_eq!(drag.bodies(), Bodies::default());
        assert_eq!(
            drag.name(),
            "drag (exponential, co-rotating, spherical altitude)"
        );

        let mut c = exponential_config();
        c.corotation = false;
        let drag = Drag::from_config(&c, &earth).unwrap();
        assert!(!drag.fast_exponential().unwrap().1);
        assert_eq!(
            drag.name(),
            "drag (exponential, inertial atmosphere, spherical altitude)"
        );

        let mut c = exponential_config();
        c.altitude = AltitudeName::Geodetic;
        let drag = Drag::from_config(&c, &earth).unwrap();
        assert_eq!(drag.fast_exponential(), None);
        assert_eq!(
            drag.name(),
            "drag (exponential, co-rotating, geodetic altitude)"
        );

        let drag =
            Drag::from_config(&DragConfig::new(AtmosphereName::ExponentialTable), &earth).unwrap();
        assert_eq!(drag.fast_exponential(), None);
        assert_eq!(drag.bodies(), Bodies::default());
        assert_eq!(
            drag.name(),
            "drag (exponential-table, co-rotating, spherical altitude)"
        );

        let drag =
            Drag::from_config(&DragConfig::new(AtmosphereName::HarrisPriester), &earth).unwrap();
        assert_eq!(drag.fast_exponential(), None);
        assert_eq!(
            drag.bodies(),
            Bodies {
                sun: true,
                moon: false
            }
        );
        assert_eq!(drag.atmosphere().name(), "harris-priester");
        assert_eq!(drag.atmosphere().floor_altitude_m(), 100e3);
    }

    #[test]
    fn config_errors_name_the_key() {
        let earth = EarthModel::WGS84_EGM96;
        let mut c = exponential_config();
        c.scale_height_m = Some(-1.0);
        let e = Drag::from_config(&c, &earth).unwrap_err();
        assert_eq!(e.key, "drag.scale_height_m");
        assert_eq!(e.value, "-1");
        let mut c = exponential_config();
        c.reference_altitude_m = None;
        let e = Drag::from_config(&c, &earth).unwrap_err();
        assert_eq!(
            (e.key.as_str(), e.value.as_str()),
            ("drag.reference_altitude_m", "missing")
        );
        let mut c = DragConfig::new(AtmosphereName::HarrisPriester);
        c.cosine_exponent = Some(7.0);
        assert_eq!(
            Drag::from_config(&c, &earth).unwrap_err().key,
            "drag.cosine_exponent"
        );
    }

    /// The force model evaluates the density at the satellite's own height and feeds the same bits
    /// through [`drag_acceleration_m_s2`]; Harris–Priester reads the Sun from the instant. The instant
    /// here carries the Sun (on +x, 1 AU) so that no ephemeris is evaluated.
    #[test]
    fn force_model_uses_atmosphere_and_properties() {
        let earth = EarthModel::WGS84_EGM96;
        let properties = PhysicalProperties {
            mass_kg: 10.0,
            drag_area_m2: 0.1,
            drag_coefficient: 2.2,
            srp_area_m2: 0.0,
            reflectivity_coefficient: 0.0,
        };
        let at = Instant {
            tt_s_past_j2000: 0.0,
            sun_eci_m: Some(Vector3::new(1.495_978_707e11, 0.0, 0.0)),
            moon_eci_m: None,
        };
        let r = Vector3::new(6_378_137.0 + 420e3, 0.0, 0.0);
        let v = Vector3::new(0.0, 7_600.0, 100.0);

        let drag = Drag::from_config(&exponential_config(), &earth).unwrap();
        // The layer's formula with the library's exponential: the crate's own is within 2 ulp of it
        // and the reciprocal scale height adds at most one rounding of the exponent (|x| < 1: 1e-16).
        let want = 3.725e-12 * ((400e3 - 420e3) / 58_515.0_f64).exp();
        let rho = drag.density_kg_per_m3(&at, &r);
        assert!(((rho - want) / want).abs() < 1e-15, "{rho} vs {want}");
        assert_eq!(
            drag.acceleration_eci_m_s2(&at, &r, &v, &properties),
            drag_acceleration_m_s2(rho, properties.drag_area_per_mass_m2_per_kg(), &r, &v, true)
        );

        let drag =
            Drag::from_config(&DragConfig::new(AtmosphereName::HarrisPriester), &earth).unwrap();
        // The satellite on +x at 420 km (a table row: rho_min = 1.558e-12, rho_max = 5.684e-12), the
        // apex 30° east of the Sun: psi = 30°, cos^4(15°) = ((1 + cos 30°)/2)^2 =
        // 0.87051270189221932 (mpmath). Tolerance 2e-15: the apex rotation, normalisation and dot
        // product round cos psi by ~1e-16, the power and the combination add a few 1e-16.
        let rho_hp = drag.density_kg_per_m3(&at, &r);
        let want = 1.558e-12 + (5.684e-12 - 1.558e-12) * 0.870_512_701_892_219_3;
        assert!(((rho_hp - want) / want).abs() < 2e-15, "{rho_hp} vs {want}");
    }
}
