"""satflock.Simulation: a scenario stepped from Python gives the CLI's numbers bit for bit; its state
arrays, steps, ranges and Ctrl-C."""

import os
import signal
import subprocess
import threading

import numpy as np
import pyarrow
import pyarrow.csv
import pytest

import satflock

HILL = ["x_lvlh_m", "y_lvlh_m", "z_lvlh_m", "vx_lvlh_mps", "vy_lvlh_mps", "vz_lvlh_mps"]
ECI = ["x_eme2000_m", "y_eme2000_m", "z_eme2000_m", "vx_eme2000_mps", "vy_eme2000_mps", "vz_eme2000_mps"]


@pytest.fixture
def hold_with_events():
    """`hold` cut to 1200 s: its set-law-parameters event (1000 s) and thruster failure (moved to 500 s)
    both happen."""
    scenario = satflock.Scenario.load("hold")
    scenario.update({"duration_s": 1200.0, "events.1.time_s": 500.0})
    return scenario


def grid_of_csv(path, n):
    """trajectory.csv (pyarrow's CSV reader) as (R, N, 6) Hill and EME2000 arrays, NaN where a
    satellite has no row."""
    rows = pyarrow.csv.read_csv(path)
    t = rows["t_s"].to_numpy()
    times = np.unique(t)
    record = np.searchsorted(times, t)
    ids = rows["id"].to_numpy()
    hill = np.full((len(times), n, 6), np.nan)
    eci = np.full((len(times), n, 6), np.nan)
    for k in range(6):
        hill[record, ids, k] = rows[HILL[k]].to_numpy()
        eci[record, ids, k] = rows[ECI[k]].to_numpy()
    return times, hill, eci


def stepped(scenario, times, **kwargs):
    """The simulation advanced to each of `times` in turn."""
    sim = satflock.Simulation(scenario, **kwargs)
    for t in times:
        sim.advance_to(float(t))
    return sim


def test_stepped_from_python_equals_the_cli_bit_for_bit(hold_with_events, satflock_bin, tmp_path):
    path = tmp_path / "hold.toml"
    path.write_text(hold_with_events.to_toml())
    out = tmp_path / "cli"
    subprocess.run(
        [satflock_bin, "run", str(path), "--out", str(out), "--quiet", "--no-plots"],
        check=True,
        capture_output=True,
    )
    times, hill, eci = grid_of_csv(out / "trajectory.csv", 20)
    # Several calls at record times, in uneven chunks.
    sim = stepped(hold_with_events, [10.0, 200.0, 210.0, 990.0, 1000.0, 1200.0], threads=2)
    traj = sim.trajectory
    assert np.array_equal(traj.t_s, times)
    assert np.array_equal(traj.hill, hill)
    assert np.array_equal(traj.eci, eci)
    metrics = pyarrow.csv.read_csv(
        out / "metrics.csv", convert_options=pyarrow.csv.ConvertOptions(column_types={"time_utc": pyarrow.string()})
    )
    ours = sim.metrics_table()
    assert ours.column_names == metrics.column_names
    assert ours["time_utc"].to_pylist() == metrics["time_utc"].to_pylist()
    for name in metrics.column_names[2:] + ["t_s"]:
        # An empty cell (a value that does not exist) is NaN in ours, null in pyarrow's reading.
        theirs = np.array(metrics[name].to_pylist(), dtype=float)
        assert np.array_equal(ours[name].to_numpy().astype(float), theirs, equal_nan=True), name
    # satflock.run is the same run.
    result = satflock.run(hold_with_events, threads=1, progress=False)
    assert np.array_equal(result.trajectory.hill, traj.hill)
    assert np.array_equal(result.trajectory.delta_v_mps, traj.delta_v_mps)
    assert result.metrics_table().equals(ours)


def test_step_and_run_mix_with_advance_to(short_hold):
    sim = satflock.Simulation(short_hold)
    assert sim.time_s == 0.0 and sim.duration_s == 300.0 and sim.n_satellites == 20
    assert sim.trajectory.t_s.tolist() == [0.0]
    for k in range(1, 26):
        sim.step()
        assert sim.time_s == float(k)
    sim.advance_to(120.0)
    sim.run()
    assert sim.time_s == 300.0
    sim.step()
    assert sim.time_s == 300.0
    whole = satflock.run(short_hold, progress=False)
    assert np.array_equal(sim.trajectory.hill, whole.trajectory.hill)
    assert sim.metrics_table().equals(whole.metrics_table())


def test_state_arrays_are_read_only_copies_of_the_records(short_hold):
    sim = stepped(short_hold, [100.0])
    traj = sim.trajectory
    for name, array, expected in [
        ("positions_hill", sim.positions_hill, traj.hill[-1, :, :3]),
        ("velocities_hill", sim.velocities_hill, traj.hill[-1, :, 3:]),
        ("positions_eci", sim.positions_eci, traj.eci[-1, :, :3]),
        ("velocities_eci", sim.velocities_eci, traj.eci[-1, :, 3:]),
    ]:
        assert array.shape == (20, 3), name
        assert np.array_equal(array, expected), name
        assert not array.flags.writeable, name
        with pytest.raises(ValueError):
            array[0, 0] = 1.0
    assert sim.active.dtype == bool and sim.active.all()
    assert sim.law_outputs == {}


def test_removed_satellite_is_a_nan_row(short_hold):
    short_hold["events"] = [{"time_s": 50.0, "action": "remove-satellite", "satellite": 4}]
    sim = stepped(short_hold, [60.0])
    assert not sim.active[4] and sim.active.sum() == 19
    assert np.isnan(sim.positions_hill[4]).all() and np.isnan(sim.velocities_eci[4]).all()
    assert np.isfinite(np.delete(sim.positions_hill, 4, axis=0)).all()
    assert np.isnan(sim.trajectory.hill[-2:, 4]).all()


def test_law_outputs_per_satellite():
    scenario = satflock.Scenario.load("pigeon-baseline")
    scenario.update({"duration_s": 5.0, "output.trajectory": True})
    sim = stepped(scenario, [5.0])
    outputs = sim.law_outputs
    assert list(outputs) == ["pigeon_pattern"] and outputs["pigeon_pattern"].shape == (10,)
    assert np.array_equal(outputs["pigeon_pattern"], sim.trajectory.law_outputs["pigeon_pattern"][-1])
    whole = satflock.run(scenario, progress=False)
    assert np.array_equal(whole.trajectory.law_outputs["pigeon_pattern"], sim.trajectory.law_outputs["pigeon_pattern"])


def test_advance_to_refuses_times_outside_the_run(short_hold):
    sim = stepped(short_hold, [50.0])
    for bad in [10.0, 300.5, float("nan")]:
        with pytest.raises(ValueError, match=r"t_s = .* is out of range \(allowed: \[50, 300\] s"):
            sim.advance_to(bad)
    assert sim.time_s == 50.0


def test_ctrl_c_leaves_the_simulation_usable():
    scenario = satflock.Scenario.load("hold")
    scenario.update(
        {
            "satellites.count": 600,
            "satellites.initial.radius_m": 1500.0,
            "record_interval_s": 100.0,
        }
    )
    sim = satflock.Simulation(scenario, threads=2)
    # About 2 to 4 s of work on two cores: SIGINT comes long before the end.
    timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            sim.run()
    finally:
        timer.cancel()
    reached = sim.time_s
    assert 0.0 < reached < 4000.0
    # Stopped at a tick: carrying on gives the uninterrupted run, bit for bit.
    sim.run()
    whole = satflock.run(scenario, threads=2, progress=False)
    assert np.array_equal(sim.trajectory.hill, whole.trajectory.hill)
