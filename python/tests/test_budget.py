"""satflock.budget against independent physics: the J2 acceleration's closed form along the orbit, the
zonal terms' ratios, differential drag (1/2) rho v^2 dB, the solar radiation pressure at the Sun's
distance, the tidal differentials GM delta / d^3, the HCW linearisation error's second order, the drift
laws (t^2 for along-track forcing); bad values raise ValueError naming the argument; the same numbers as
`satflock budget --json`."""

import json
import math
import subprocess

import numpy as np
import pytest

import satflock

MU = 3.986004418e14  # WGS 84, m^3/s^2
RE = 6378137.0  # m
J2 = 1.08262668e-3  # EGM96
J3 = -2.53265649e-6  # EGM96, -sqrt(7) C30
OMEGA_E = 7.292115e-5  # rad/s, WGS 84
P_SUN = 4.56e-6  # N/m^2 at 1 au (Montenbruck & Gill eq. 3.72)
GM_MOON = 4.9028e12  # m^3/s^2, JPL DE430
DAY = 86400.0

TERMS = ["J2", "J3", "J4", "J5", "J6", "drag", "srp", "sun", "moon", "hcw-linearisation"]
PAIR = dict(mass_kg=100.0, drag_area_m2=1.0)


def test_rows_and_keys():
    b = satflock.budget(400e3, 51.6, **PAIR)
    assert list(b) == TERMS
    for term, row in b.items():
        assert set(row) == {
            "acceleration_mps2",
            "differential_acceleration_mps2",
            "drift_per_orbit_m",
            "drift_per_day_m",
        }
        assert (row["acceleration_mps2"] is None) == (term == "hcw-linearisation")
        assert row["differential_acceleration_mps2"] >= 0.0


@pytest.mark.parametrize("inclination_deg", [0.0, 51.6, 97.8])
def test_j2_acceleration_is_the_closed_form_averaged_over_the_orbit(inclination_deg):
    # J2 alone: a = (3/2) J2 mu R^2 / r^4 * sqrt(5 s^4 - 2 s^2 + 1), s = sin(latitude) = sin i sin u
    # (from grad of -(mu/r) J2 (R/r)^2 P2(s): radial (3/2)(3 s^2 - 1), northward 3 s cos(latitude)).
    r = RE + 400e3
    u = 2 * math.pi * np.arange(36) / 36
    s = math.sin(math.radians(inclination_deg)) * np.sin(u)
    want = 1.5 * J2 * MU * RE**2 / r**4 * np.mean(np.sqrt(5 * s**4 - 2 * s**2 + 1))
    got = satflock.budget(400e3, inclination_deg, **PAIR)["J2"]["acceleration_mps2"]
    assert got == pytest.approx(want, rel=1e-9)


def test_zonal_ratio_on_the_equator():
    # On the equator J2 is radial, (3/2) J2 (R/r)^2 mu/r^2, and J3 northward, (3/2) |J3| (R/r)^3 mu/r^2.
    b = satflock.budget(600e3, 0.0, **PAIR)
    ratio = b["J3"]["acceleration_mps2"] / b["J2"]["acceleration_mps2"]
    assert ratio == pytest.approx(abs(J3) / J2 * RE / (RE + 600e3), rel=1e-8)
    # And the higher harmonics are each at least two orders below J2.
    for term in ["J3", "J4", "J5", "J6"]:
        assert b[term]["acceleration_mps2"] < 1e-2 * b["J2"]["acceleration_mps2"]


def test_differential_drag_is_half_rho_v2_delta_b_and_drifts_as_t_squared():
    # Equatorial, Vallado's static table at 420 km: rho = 3.725e-12 exp(-20/58.515) kg/m^3 (Table 8-4),
    # speed relative to the co-rotating air (n - omega_E) r, dB = C_d (A2 - A1) / m.
    r = RE + 420e3
    n = math.sqrt(MU / r**3)
    rho = 3.725e-12 * math.exp(-20.0 / 58.515)
    v_rel = (n - OMEGA_E) * r
    delta_b = 2.2 * (3.0 - 1.0) / 100.0
    b = satflock.budget(
        420e3, 0.0, atmosphere="exponential-table", mass_kg=100.0, drag_area_m2=1.0, drag_area_2_m2=3.0
    )
    drag = b["drag"]
    want = 0.5 * rho * v_rel**2 * delta_b
    assert drag["differential_acceleration_mps2"] == pytest.approx(want, rel=1e-7)
    assert drag["acceleration_mps2"] == pytest.approx(want / 2, rel=1e-9)
    # An along-track acceleration a drifts (3/2) a t^2: per orbit T = 2 pi / n, per day 86400 s.
    period = 2 * math.pi / n
    assert drag["drift_per_orbit_m"] == pytest.approx(1.5 * want * period**2, rel=1e-7)
    assert drag["drift_per_day_m"] / drag["drift_per_orbit_m"] == pytest.approx((DAY / period) ** 2, rel=1e-9)


def test_differential_drag_follows_the_ballistic_difference_in_harris_priester():
    # Same orbit, same air: |da| / |a| = |B2 - B1| / B1, whatever the density's bulge does.
    for area_2, ratio in [(2.0, 1.0), (1.25, 0.25), (0.5, 0.5)]:
        drag = satflock.budget(350e3, 97.0, mass_kg=50.0, drag_area_m2=1.0, drag_area_2_m2=area_2)["drag"]
        got = drag["differential_acceleration_mps2"] / drag["acceleration_mps2"]
        assert got == pytest.approx(ratio, rel=1e-3)
    # The default second satellite has twice the area: the differential equals satellite 1's drag.
    drag = satflock.budget(350e3, 97.0, mass_kg=50.0, drag_area_m2=1.0)["drag"]
    assert drag["differential_acceleration_mps2"] == pytest.approx(drag["acceleration_mps2"], rel=1e-3)


def test_srp_is_the_solar_pressure_at_the_suns_distance():
    # Cannonball, always lit: P C_r A / m (au / d)^2, d from 0.983 to 1.017 au over the year (early
    # January: perihelion). The Earth's 1e-4 au offset from the Sun line is within those bounds.
    satellite = dict(mass_kg=10.0, drag_area_m2=0.1, srp_area_m2=0.2, reflectivity_coefficient=1.3)
    srp = satflock.budget(700e3, 98.0, **satellite)["srp"]
    base = P_SUN * 1.3 * 0.2 / 10.0
    assert base / 1.017**2 <= srp["acceleration_mps2"] <= base / 0.983**2
    january = satflock.budget(700e3, 98.0, epoch_utc="2026-01-03T12:00:00Z", **satellite)["srp"]
    july = satflock.budget(700e3, 98.0, epoch_utc="2026-07-04T12:00:00Z", **satellite)["srp"]
    ratio = january["acceleration_mps2"] / july["acceleration_mps2"]
    assert ratio == pytest.approx((1.0167 / 0.9833) ** 2, rel=2e-3)


def test_moon_tidal_differential_is_gm_delta_over_d_cubed():
    # |(GM/d^3)(3 (d.rho) d - rho)| is GM delta / d^3 to 2 GM delta / d^3; the Moon is 356 400 to
    # 406 700 km away, the satellite at most r nearer or farther.
    r = RE + 500e3
    for separation in [100.0, 10e3]:
        got = satflock.budget(500e3, 30.0, separation, "radial", **PAIR)["moon"]["differential_acceleration_mps2"]
        low = GM_MOON * separation / (406700e3 + r) ** 3
        high = 2 * GM_MOON * separation / (356400e3 - r) ** 3
        assert low < got < high


@pytest.mark.parametrize("direction, factor", [("radial", 3.0), ("along-track", 1.5), ("cross-track", 1.5)])
def test_hcw_linearisation_error_is_the_second_order_term(direction, factor):
    # exact - linear gravity difference: -3 mu d^2 / r^4 for a radial d, (3/2) mu d^2 / r^4 otherwise.
    r = RE + 400e3
    small = satflock.budget(400e3, 51.6, 500.0, direction, **PAIR)["hcw-linearisation"]
    large = satflock.budget(400e3, 51.6, 2000.0, direction, **PAIR)["hcw-linearisation"]
    assert small["differential_acceleration_mps2"] == pytest.approx(factor * MU * 500.0**2 / r**4, rel=1e-3)
    # Second order: four times the separation, sixteen times the error.
    ratio = large["differential_acceleration_mps2"] / small["differential_acceleration_mps2"]
    assert ratio == pytest.approx(16.0, rel=1e-3)


def test_a_radial_pair_on_the_equator_drifts_linearly_under_j2():
    # The radial J2 acceleration -(3/2) J2 mu R^2 / r^4 differs between r and r + d; a radial constant
    # acceleration drifts 2 a t / n: linear in time, so per day / per orbit = 86400 / T.
    r = RE + 500e3
    n = math.sqrt(MU / r**3)
    a_x = lambda rr: -1.5 * J2 * MU * RE**2 / rr**4  # noqa: E731
    delta_a = a_x(r + 1000.0) - a_x(r)
    j2 = satflock.budget(500e3, 0.0, 1000.0, "radial", **PAIR)["J2"]
    assert j2["drift_per_orbit_m"] == pytest.approx(2 * delta_a * (2 * math.pi / n) / n, rel=1e-6)
    assert j2["drift_per_day_m"] == pytest.approx(2 * delta_a * DAY / n, rel=1e-6)


def test_identical_satellites_on_one_orbit_only_drift_from_the_hcw_error():
    b = satflock.budget(400e3, 51.6, mass_kg=100.0, drag_area_m2=1.0, drag_area_2_m2=1.0)
    for term in TERMS[:-1]:
        assert b[term]["drift_per_day_m"] < 1e-4, term
    # Straight-line along-track coordinates: the offset orbit is 2 d^2 / r higher, drifting 6 pi d^2 / r
    # per orbit.
    assert b["hcw-linearisation"]["drift_per_orbit_m"] == pytest.approx(6 * math.pi * 1e6 / (RE + 400e3), rel=1e-3)


@pytest.mark.parametrize(
    "kwargs, says",
    [
        (dict(altitude_m=99e3), "altitude_m = 99000"),
        (dict(altitude_m=2.5e6), "altitude_m = 2500000"),
        (dict(inclination_deg=-1.0), "inclination_deg = -1"),
        (dict(inclination_deg=float("nan")), "inclination_deg = NaN"),
        (dict(separation_m=0.0), "separation_m = 0"),
        (dict(separation_m=2e5), "separation_m = 200000"),
        (dict(direction="up"), "along-track, radial, cross-track"),
        (dict(mass_kg=0.0), "mass_kg = 0"),
        (dict(drag_area_m2=-1.0), "drag_area_m2 = -1"),
        (dict(drag_area_2_m2=-1.0), "drag_area_2_m2 = -1"),
        (dict(srp_area_2_m2=-1.0), "srp_area_2_m2 = -1"),
        (dict(drag_coefficient=11.0), "drag_coefficient = 11"),
        (dict(reflectivity_coefficient=3.0), "reflectivity_coefficient = 3"),
        (dict(atmosphere="msis"), "atmosphere = \"msis\""),
        (dict(epoch_utc="soon"), "epoch_utc"),
    ],
)
def test_bad_values_name_the_argument(kwargs, says):
    args = dict(altitude_m=400e3, inclination_deg=51.6, **PAIR)
    args.update(kwargs)
    with pytest.raises(ValueError) as info:
        satflock.budget(**args)
    assert says in str(info.value)
    assert "allowed" in str(info.value)


def test_same_numbers_as_the_command_line(satflock_bin):
    # The CLI's defaults are the function's: twice the drag area for satellite 2, SRP areas = drag areas.
    flags = "--altitude-km 450 --inclination-deg 63.4 --separation-m 250 --direction cross-track"
    flags += " --mass-kg 20 --drag-area-m2 0.2 --epoch-utc 2026-03-20T12:00:00Z --json"
    done = subprocess.run([satflock_bin, "budget", *flags.split()], check=True, capture_output=True)
    cli = {row["term"]: row for row in json.loads(done.stdout)["terms"]}
    py = satflock.budget(
        450e3, 63.4, 250.0, "cross-track", mass_kg=20.0, drag_area_m2=0.2, epoch_utc="2026-03-20T12:00:00Z"
    )
    for term in TERMS:
        for key, value in py[term].items():
            assert value == cli[term][key], (term, key)
