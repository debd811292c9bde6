"""A guidance law written in Python: a PD hold law against the built-in `hold`, what it sees (its
context), what is done with its commands (actuator limits, failures), and how it fails."""

import json
import math

import numpy as np
import pytest

import satflock


class PDHold:
    """u = -k_p (r - r_slot) - k_d v - a_HCW(r, v), slots = the positions at the first tick: the
    built-in `hold` law with `feedforward = "hcw"` (src/guidance/hold.rs), written with numpy."""

    name = "pd-hold"

    def __init__(self, k_p, k_d):
        self.k_p, self.k_d, self.slots = k_p, k_d, None

    def command(self, ctx):
        r, v, n = ctx.positions_hill, ctx.velocities_hill, ctx.mean_motion_rad_per_s
        if self.slots is None:
            self.slots = r.copy()
        # The HCW natural acceleration, term by term in the order of Hcw::natural_acceleration_m_s2.
        a_hcw = np.stack(
            [3.0 * n * n * r[:, 0] + 2.0 * n * v[:, 1], -2.0 * n * v[:, 0], -n * n * r[:, 2]], axis=1
        )
        return -self.k_p * (r - self.slots) - self.k_d * v - a_hcw


class Constant:
    """The same command for every satellite."""

    def __init__(self, command):
        self.value = np.asarray(command, dtype=float)

    def command(self, ctx):
        return np.tile(self.value, (len(ctx.active), 1))


def test_pd_law_in_python_equals_the_built_in_hold(short_hold):
    # Exactly equal, not only to rounding: the Python law computes the same IEEE operations in the same
    # order as hold.rs (no fused multiply-add on either side) from the same states (the scenario has no
    # navigation noise, so the truth the Python law sees is what `hold` senses), and its commands go
    # through the same actuators (2 mm/s^2 norm limit, the y thruster of satellite 3 failing at 150 s).
    rust = satflock.run(short_hold, progress=False)
    python = satflock.run(short_hold, law=PDHold(1e-4, 2e-2), progress=False)
    assert python.summary["controller"] == "python:pd-hold"
    assert np.array_equal(python.trajectory.hill, rust.trajectory.hill)
    assert np.array_equal(python.trajectory.eci, rust.trajectory.eci)
    assert np.array_equal(python.trajectory.delta_v_mps, rust.trajectory.delta_v_mps)
    # Stepped, the same law gives the same run.
    sim = satflock.Simulation(short_hold, law=PDHold(1e-4, 2e-2))
    sim.run()
    assert np.array_equal(sim.trajectory.hill, rust.trajectory.hill)


def test_context_holds_the_swarm_and_its_neighbours(short_hold):
    short_hold.update(
        {
            "sensing.range_m": 150.0,
            "events": [{"time_s": 3.0, "action": "remove-satellite", "satellite": 5}],
        }
    )
    seen = []

    class Recorder:
        def command(self, ctx):
            seen.append(ctx)
            return np.zeros((ctx.n_satellites, 3))

    sim = satflock.Simulation(short_hold, law=Recorder())
    states = []
    for t in range(1, 6):
        states.append((sim.positions_hill.copy(), sim.velocities_hill.copy(), sim.active.copy()))
        sim.advance_to(float(t))
    assert [c.tick for c in seen] == [0, 1, 2, 3, 4]
    assert [c.time_s for c in seen] == [0.0, 1.0, 2.0, 3.0, 4.0]
    # Reference orbit: 600 km altitude on the WGS-84 / EGM96 Earth (mu, equatorial radius).
    a = 6378137.0 + 600e3
    assert math.isclose(seen[0].mean_motion_rad_per_s, math.sqrt(3.986004418e14 / a**3), rel_tol=1e-12)
    for ctx, (r, v, active) in zip(seen, states):
        assert ctx.period_s == 1.0 and ctx.sensing_range_m == 150.0
        assert np.array_equal(ctx.active, active)
        live = active
        assert np.array_equal(ctx.positions_hill[live], r[live])
        assert np.array_equal(ctx.velocities_hill[live], v[live])
        assert np.array_equal(ctx.mass_kg, np.full(20, 10.0))
        assert np.isnan(ctx.positions_hill[~live]).all() and np.isnan(ctx.velocities_hill[~live]).all()
        assert not ctx.positions_hill.flags.writeable
        offsets, indices = ctx.neighbour_offsets, ctx.neighbour_indices
        assert offsets.dtype == np.int64 and indices.dtype == np.int64
        assert offsets.shape == (21,) and offsets[-1] == len(indices)
        # All pairs, by brute force: live satellites within the sensing range, self excluded.
        distance = np.linalg.norm(r[:, None, :] - r[None, :, :], axis=2)
        for i in range(20):
            expected = [
                j for j in range(20) if j != i and live[i] and live[j] and distance[i, j] <= 150.0
            ]
            assert indices[offsets[i] : offsets[i + 1]].tolist() == expected, (ctx.tick, i)
    # The removal at 3 s applies before the tick of 3 s.
    assert seen[2].active[5] and not seen[3].active[5]
    assert 0 < len(seen[0].neighbour_indices) < 20 * 19


def test_actuator_limits_and_failures_apply(short_hold):
    # 1 m/s^2 outward for everyone: saturated to the 2 mm/s^2 norm limit; satellite 3 loses its x
    # thruster at 150 s (every other axis is idle), after which it spends nothing.
    short_hold["events"] = [{"time_s": 150.0, "action": "fail-thruster", "satellite": 3, "axis": "x"}]
    short_hold["dynamics.max_distance_m"] = 1e6
    result = satflock.run(short_hold, law=Constant([1.0, 0.0, 0.0]), progress=False)
    t, dv = result.trajectory.t_s, result.trajectory.delta_v_mps
    others = np.delete(dv, 3, axis=1)
    assert np.allclose(others, 2e-3 * t[:, None], rtol=1e-12, atol=1e-15)
    assert np.allclose(dv[:, 3], 2e-3 * np.minimum(t, 150.0), rtol=1e-12, atol=1e-15)


def test_rows_of_removed_satellites_are_ignored(short_hold):
    short_hold["events"] = [{"time_s": 20.0, "action": "remove-satellite", "satellite": 0}]

    class NanForTheDead:
        def command(self, ctx):
            u = np.zeros((ctx.n_satellites, 3))
            u[~ctx.active] = np.nan
            return u

    assert satflock.run(short_hold, law=NanForTheDead(), progress=False).status == "completed"


def test_a_law_that_raises_fails_the_run_with_its_traceback(short_hold, tmp_path):
    class Raises:
        name = "raiser"

        def command(self, ctx):
            if ctx.time_s >= 5.0:
                raise RuntimeError("no more commands")
            return np.zeros((ctx.n_satellites, 3))

    out = tmp_path / "run"
    with pytest.raises(satflock.SimulationError) as e:
        satflock.run(short_hold, out=out, law=Raises(), progress=False)
    message = str(e.value)
    assert message.startswith("law `python:raiser` failed at t = 5 s: tick 5: command(ctx) raised")
    assert "Traceback (most recent call last)" in message
    assert "RuntimeError: no more commands" in message and "test_python_law.py" in message
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "failed" and summary["simulated_s"] == 5.0
    # The stepped simulation stops at the tick and stays there.
    sim = satflock.Simulation(short_hold, law=Raises())
    with pytest.raises(satflock.SimulationError, match="no more commands"):
        sim.advance_to(10.0)
    assert sim.time_s == 5.0


@pytest.mark.parametrize(
    "returned, expected",
    [
        (np.zeros((20, 2)), r"returned an array of shape \(20, 2\) \(expected an array of shape \(20, 3\)"),
        (np.zeros(60), r"returned an array of shape \(60,\)"),
        ("fast", r"returned a str, which is not an array of numbers"),
        (None, r"returned a NoneType \(as an array: shape \(\)\)"),
    ],
)
def test_a_bad_command_array_fails_the_run(short_hold, returned, expected):
    class Bad:
        def command(self, ctx):
            return returned

    prefix = r"law `python:Bad` failed at t = 0 s: tick 0: command\(ctx\) "
    with pytest.raises(satflock.SimulationError, match=prefix + expected):
        satflock.run(short_hold, law=Bad(), progress=False)


def test_a_non_finite_command_names_the_satellite(short_hold):
    class NotFinite:
        def command(self, ctx):
            u = np.zeros((ctx.n_satellites, 3))
            if ctx.tick == 2:
                u[7, 1] = np.inf
            return u

    with pytest.raises(satflock.SimulationError, match=r"t = 2 s: tick 2: .*non-finite command for satellite 7: \[0, inf, 0\]"):
        satflock.run(short_hold, law=NotFinite(), progress=False)


def test_laws_the_scenario_cannot_take_are_refused(short_hold):
    with pytest.raises(TypeError, match="law: an object of type `int` has no method command"):
        satflock.run(short_hold, law=3, progress=False)

    class BadName:
        name = 7

        def command(self, ctx):
            return np.zeros((ctx.n_satellites, 3))

    with pytest.raises(TypeError, match="law.name is a int"):
        satflock.Simulation(short_hold, law=BadName())
    continuous = satflock.Scenario.load("es-e0")
    with pytest.raises(satflock.ScenarioError, match="continuous") as e:
        satflock.run(continuous, law=Constant([0.0, 0.0, 0.0]), progress=False)
    assert e.value.key == "control"
    # The built-in hold's set-law-parameters event is written for its own law.
    with pytest.raises(satflock.ScenarioError, match="set-law-parameters") as e:
        satflock.Simulation("hold", law=PDHold(1e-4, 2e-2))
    assert e.value.key == "events[0]"


def test_a_keyboard_interrupt_in_a_law_is_raised_as_keyboard_interrupt(short_hold, tmp_path):
    class Interrupts:
        def command(self, ctx):
            if ctx.time_s >= 5.0:
                raise KeyboardInterrupt
            return np.zeros((ctx.n_satellites, 3))

    with pytest.raises(KeyboardInterrupt):
        satflock.run(short_hold, out=tmp_path / "run", law=Interrupts(), progress=False)
    sim = satflock.Simulation(short_hold, law=Interrupts())
    with pytest.raises(KeyboardInterrupt):
        sim.advance_to(10.0)
