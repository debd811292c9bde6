"""satflock.propagate against independent physics (two-body invariants, the J2 nodal regression) and
against `satflock propagate`'s CSV output."""

import math
import subprocess

import numpy as np
import pytest

import satflock

MU = 3.986004418e14  # WGS 84, m^3/s^2
RE = 6378137.0  # m
J2 = 1.08262668e-3  # EGM96


def elements_to_state(a_m, e, i_rad, raan_rad, argp_rad, nu_rad, mu=MU):
    """EME2000 state from classical elements (perifocal frame rotated by R3(-raan) R1(-i) R3(-argp))."""
    p = a_m * (1 - e * e)
    r = p / (1 + e * math.cos(nu_rad))
    r_pf = np.array([r * math.cos(nu_rad), r * math.sin(nu_rad), 0.0])
    v_pf = math.sqrt(mu / p) * np.array([-math.sin(nu_rad), e + math.cos(nu_rad), 0.0])

    def rot3(t):
        c, s = math.cos(t), math.sin(t)
        return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])

    def rot1(t):
        c, s = math.cos(t), math.sin(t)
        return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])

    q = rot3(raan_rad) @ rot1(i_rad) @ rot3(argp_rad)
    return np.concatenate([q @ r_pf, q @ v_pf])


def test_shapes_single_and_several():
    s0 = elements_to_state(7000e3, 0.001, math.radians(50), 0.3, 0.2, 0.1)
    t, x = satflock.propagate(s0, 600.0, 10.0, 60.0)
    np.testing.assert_array_equal(t, np.arange(0.0, 601.0, 60.0))
    assert x.shape == (11, 6)
    np.testing.assert_array_equal(x[0], s0)
    # A duration that is not a multiple of the output step ends on the duration; output_step_s=None
    # means step_s.
    t, x = satflock.propagate(np.stack([s0, s0]), 25.0, 10.0, threads=2)
    np.testing.assert_array_equal(t, [0.0, 10.0, 20.0, 25.0])
    assert x.shape == (4, 2, 6)
    np.testing.assert_array_equal(x[:, 0], x[:, 1])


def test_two_body_energy_and_angular_momentum_are_conserved_over_an_orbit():
    a, e = 7200e3, 0.05
    s0 = elements_to_state(a, e, math.radians(63.4), 1.0, 2.0, 0.5)
    period = 2 * math.pi * math.sqrt(a**3 / MU)
    t, x = satflock.propagate(s0, period, 30.0, period / 50, gravity="point-mass")
    r, v = x[:, :3], x[:, 3:]
    energy = 0.5 * np.sum(v * v, axis=1) - MU / np.linalg.norm(r, axis=1)
    h = np.cross(r, v)
    assert np.max(np.abs(energy / (-MU / (2 * a)) - 1)) < 1e-9
    assert np.max(np.linalg.norm(h - h[0], axis=1)) / np.linalg.norm(h[0]) < 1e-9
    # After one period the orbit closes (Kepler's third law), to the integrator's accuracy.
    assert np.linalg.norm(r[-1] - r[0]) < 1e-3
    # "two-body" is the command line's name of the same model.
    _, x2 = satflock.propagate(s0, period, 30.0, period / 50, gravity="two-body")
    np.testing.assert_array_equal(x, x2)


def test_j2_nodal_regression_matches_the_first_order_rate():
    a, e, i = 7000e3, 0.001, math.radians(50.0)
    s0 = elements_to_state(a, e, i, 0.5, 0.0, 0.0)
    duration = 3 * 86400.0
    t, x = satflock.propagate(s0, duration, 60.0, 60.0, gravity="j2")
    h = np.cross(x[:, :3], x[:, 3:])
    raan = np.unwrap(np.arctan2(h[:, 0], -h[:, 1]))
    # Least-squares slope: the short-period terms average out over ~45 orbits.
    slope = np.polyfit(t, raan, 1)[0]
    n = math.sqrt(MU / a**3)
    p = a * (1 - e * e)
    expected = -1.5 * n * J2 * (RE / p) ** 2 * math.cos(i)
    assert slope == pytest.approx(expected, rel=1e-2)
    # Two-body: no regression.
    _, x = satflock.propagate(s0, duration, 60.0, 3600.0, gravity="two-body")
    h = np.cross(x[:, :3], x[:, 3:])
    np.testing.assert_allclose(np.arctan2(h[:, 0], -h[:, 1]), 0.5, atol=1e-9)


def test_lvlh_frames_of_the_reference_itself_are_zero_and_gao_is_hill_relabelled():
    ref = elements_to_state(6900e3, 0.0, math.radians(97.8), 0.0, 0.0, 0.0)
    other = ref + np.array([0.0, 0.0, 100.0, 0.0, 0.1, 0.0])
    t, hill = satflock.propagate(np.stack([ref, other]), 600.0, 10.0, 60.0, frame="lvlh-hill", reference=ref)
    np.testing.assert_array_equal(hill[:, 0], 0.0)
    _, gao = satflock.propagate(other, 600.0, 10.0, 60.0, frame="lvlh-gao", reference=ref)
    # Gao o-xyz: x = y_hill, y = -z_hill, z = -x_hill (positions and velocities alike).
    h = hill[:, 1]
    np.testing.assert_array_equal(gao, np.stack([h[:, 1], -h[:, 2], -h[:, 0], h[:, 4], -h[:, 5], -h[:, 3]], axis=1))


@pytest.mark.parametrize(
    "kwargs, error, says",
    [
        (dict(states_eci=np.zeros(5)), ValueError, "states_eci has shape (5,)"),
        (dict(states_eci=np.zeros((0, 6))), ValueError, "states_eci has shape (0, 6)"),
        (dict(states_eci=[[7e6, 0, 0, 0, 7.5e3, 0], [7e3, 0, 0, 0, 7.5, 0]]), ValueError, "states_eci[1]"),
        (dict(duration_s=-1.0), ValueError, "duration_s = -1"),
        (dict(step_s=0.0), ValueError, "step_s = 0"),
        (dict(gravity="j4"), ValueError, "gravity = \"j4\""),
        (dict(frame="lvlh"), ValueError, "frame = \"lvlh\""),
        (dict(frame="lvlh-hill"), ValueError, "needs a reference"),
        (dict(reference=[7e6, 0, 0, 0, 7.5e3, 0]), ValueError, "reference is used only"),
        (dict(frame="lvlh-hill", reference=[1.0, 2.0]), ValueError, "reference has shape (2,)"),
        (dict(integrator="euler"), ValueError, "\"rk4\", \"rk78\", \"dop853\""),
        (dict(mu_m3_s2=-1.0), ValueError, "mu_m3_s2 = -1"),
        (dict(j2=float("nan")), ValueError, "j2 = NaN"),
        (dict(threads=0), ValueError, "threads = 0"),
    ],
)
def test_bad_input_names_the_argument(kwargs, error, says):
    args = dict(states_eci=[7e6, 0, 0, 0, 7.5e3, 0], duration_s=60.0, step_s=10.0)
    args.update(kwargs)
    with pytest.raises(error) as info:
        satflock.propagate(**args)
    assert says in str(info.value)


def cli_propagate(binary, tmp_path, state, *extra):
    out = tmp_path / "orbit.csv"
    subprocess.run(
        [binary, "propagate", "--state", ",".join(repr(float(v)) for v in state), "--out", str(out), *extra],
        check=True,
        capture_output=True,
    )
    data = np.loadtxt(out, delimiter=",", skiprows=1, ndmin=2)
    return data[:, 0], data[:, 1:]


def test_same_numbers_as_the_command_line(satflock_bin, tmp_path):
    states = np.stack(
        [
            elements_to_state(7000e3, 0.01, math.radians(50), 0.3, 0.2, 0.1),
            elements_to_state(7100e3, 0.002, math.radians(98), 1.3, 0.0, 2.0),
        ]
    )
    ref = elements_to_state(7050e3, 0.0, math.radians(60), 0.3, 0.0, 0.0)
    settings = ["--duration-s", "5400", "--step-s", "30", "--output-step-s", "300"]
    cases = [
        (dict(), []),
        (dict(gravity="two-body", integrator="dop853", rtol=1e-10), ["--gravity", "two-body", "--integrator", "dop853", "--rtol", "1e-10"]),
        (dict(integrator="rk4"), ["--integrator", "rk4"]),
        (dict(frame="lvlh-hill", reference=ref), ["--frame", "lvlh-hill", "--reference-state", ",".join(repr(float(v)) for v in ref)]),
        (dict(frame="lvlh-gao", reference=ref, j2=1.1e-3), ["--frame", "lvlh-gao", "--reference-state", ",".join(repr(float(v)) for v in ref), "--j2", "0.0011"]),
    ]
    for kwargs, flags in cases:
        t, x = satflock.propagate(states, 5400.0, 30.0, 300.0, **kwargs)
        for k in range(len(states)):
            t_cli, x_cli = cli_propagate(satflock_bin, tmp_path, states[k], *settings, *flags)
            # The CSV holds every value in its shortest round-trip form: equal bit for bit.
            np.testing.assert_array_equal(t, t_cli)
            np.testing.assert_array_equal(x[:, k], x_cli, err_msg=f"{kwargs} row {k}")


def test_forces_drag_lowers_a_circular_orbit_at_the_forced_hcw_rate():
    """forces=dict: point mass + exponential drag without co-rotation on a circular 400 km orbit. The
    radial offset from the drag-free orbit follows the forced HCW solution (Clohessy & Wiltshire 1960)
    x(t) = (da/dt)(t - sin(n t)/n) with da/dt = -rho (C_d A/m) sqrt(mu a), to the neglected second-order
    terms (x/a ~ 3e-6) and the density's change over 17 m of altitude (3e-4)."""
    a = RE + 400e3
    s0 = elements_to_state(a, 0.0, math.radians(51.6), 0.0, 0.0, 0.0)
    forces = {
        "gravity": {"model": "point-mass"},
        "drag": {
            "atmosphere": "exponential",
            "reference_density_kg_per_m3": 3.725e-12,
            "reference_altitude_m": 400e3,
            "scale_height_m": 58515.0,
            "corotation": False,
        },
        "satellite": {"mass_kg": 4.0, "drag_area_m2": 0.03, "drag_coefficient": 2.2},
    }
    t_end = 5400.0
    _, free = satflock.propagate(s0, t_end, 60.0, t_end, gravity="point-mass", integrator="dop853")
    _, dragged = satflock.propagate(
        s0, t_end, 60.0, t_end, integrator="dop853", forces=forces, epoch_utc="2026-03-20T12:00:00Z"
    )
    n = math.sqrt(MU / a**3)
    rate = -3.725e-12 * (2.2 * 0.03 / 4.0) * math.sqrt(MU * a)
    expected = rate * (t_end - math.sin(n * t_end) / n)
    got = np.linalg.norm(dragged[-1, :3]) - np.linalg.norm(free[-1, :3])
    assert abs(got / expected - 1) < 5e-3, (got, expected)
    # Gravity alone through forces= is the gravity= model, number for number.
    _, j2_flag = satflock.propagate(s0, 600.0, 10.0, 60.0)
    _, j2_forces = satflock.propagate(s0, 600.0, 10.0, 60.0, forces={"gravity": {"model": "j2"}})
    np.testing.assert_array_equal(j2_flag, j2_forces)


@pytest.mark.parametrize(
    "forces, says",
    [
        ({"drag": {"atmosphere": "exponential"}}, "reference_density_kg_per_m3"),
        ({"drag": {"atmosphere": "harris-priester"}, "satellite": {"mass_kg": 4.0}}, "drag_area_m2"),
        ({"gravity": {"model": "zonal", "degree": 99}}, "gravity.degree"),
        ({"drag": {"atmosphere": "fog"}}, "fog"),
    ],
)
def test_bad_forces_name_the_key(forces, says):
    s0 = elements_to_state(7000e3, 0.001, math.radians(50), 0.3, 0.2, 0.1)
    with pytest.raises(ValueError, match=says):
        satflock.propagate(s0, 60.0, 10.0, forces=forces)
