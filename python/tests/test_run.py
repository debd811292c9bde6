"""satflock.run: the files of `satflock run`, read back into numpy arrays and tables; errors, Ctrl-C,
progress, removed satellites, thread counts."""

import json
import os
import signal
import sys
import threading

import numpy as np
import pyarrow.csv
import pytest

import satflock

TRAJECTORY_STATE = ["x_lvlh_m", "y_lvlh_m", "z_lvlh_m", "vx_lvlh_mps", "vy_lvlh_mps", "vz_lvlh_mps"]


def test_result_is_the_run_directory_read_back(short_hold, tmp_path):
    out = tmp_path / "run"
    result = satflock.run(short_hold, out=out, progress=False)
    assert result.out == out and result.status == "completed"
    assert result.summary == json.loads((out / "summary.json").read_text())
    # The metrics table is metrics.csv, column for column (read by pyarrow's own CSV reader).
    text = pyarrow.csv.ConvertOptions(column_types={"time_utc": pyarrow.string()})
    csv = pyarrow.csv.read_csv(out / "metrics.csv", convert_options=text)
    table = result.metrics_table()
    assert table.column_names == csv.column_names
    assert table["time_utc"].to_pylist() == csv["time_utc"].to_pylist()
    for name in csv.column_names[2:] + ["t_s"]:
        ours, theirs = table[name].to_numpy(), csv[name].to_numpy(zero_copy_only=False)
        assert np.array_equal(ours, theirs.astype(ours.dtype), equal_nan=True), name
    # The trajectory rows of trajectory.csv, one per live satellite and record, on the (R, N) grid.
    rows = pyarrow.csv.read_csv(out / "trajectory.csv")
    t, ids = rows["t_s"].to_numpy(), rows["id"].to_numpy()
    traj = result.trajectory
    assert traj.hill.shape == (31, 20, 6) and traj.eci.shape == (31, 20, 6)
    assert np.array_equal(traj.t_s, np.arange(0.0, 301.0, 10.0))
    assert np.array_equal(traj.ids, np.arange(20))
    record = np.searchsorted(traj.t_s, t)
    for k, name in enumerate(TRAJECTORY_STATE):
        assert np.array_equal(traj.hill[record, ids, k], rows[name].to_numpy()), name
    assert np.array_equal(traj.eci[record, ids, 0], rows["x_eme2000_m"].to_numpy())
    assert np.array_equal(traj.delta_v_mps[record, ids], rows["delta_v_mps"].to_numpy())
    assert traj.law_outputs == {}
    assert not traj.hill.flags.writeable


def test_out_none_uses_a_temporary_folder_and_a_name_or_path_loads(tmp_path):
    path = tmp_path / "hold.toml"
    scenario = satflock.Scenario.load("hold")
    scenario.update({"duration_s": 60.0, "events": []})
    path.write_text(scenario.to_toml())
    by_path = satflock.run(str(path), progress=False)
    assert by_path.out is None and by_path.summary["source"] == str(path)
    assert np.array_equal(by_path.trajectory.hill, satflock.run(scenario, progress=False).trajectory.hill)
    without_trajectory = satflock.Scenario.load("free-drift")
    without_trajectory.update({"output.trajectory": False})
    result = satflock.run(without_trajectory, progress=False)
    assert result.trajectory is None and len(result.metrics["t_s"]) > 1


def test_threads_1_and_2_give_bitwise_identical_trajectories(short_hold):
    one = satflock.run(short_hold, threads=1, progress=False)
    two = satflock.run(short_hold, threads=2, progress=False)
    assert one.summary["threads"] == 1 and two.summary["threads"] == 2
    assert np.array_equal(one.trajectory.hill, two.trajectory.hill)
    assert np.array_equal(one.trajectory.eci, two.trajectory.eci)
    assert np.array_equal(one.trajectory.delta_v_mps, two.trajectory.delta_v_mps)
    with pytest.raises(ValueError, match="threads = 0"):
        satflock.run(short_hold, threads=0, progress=False)


def test_removed_satellites_are_nan_rows(short_hold):
    short_hold["events"] = [{"time_s": 100.0, "action": "remove-satellite", "satellite": 2}]
    result = satflock.run(short_hold, progress=False)
    traj, t = result.trajectory, result.trajectory.t_s
    # Events apply before the record of their time.
    gone = t >= 100.0
    assert np.isnan(traj.hill[gone, 2]).all() and np.isnan(traj.eci[gone, 2]).all()
    assert np.isnan(traj.delta_v_mps[gone, 2]).all()
    assert np.isfinite(traj.hill[~gone]).all()
    assert np.isfinite(np.delete(traj.hill, 2, axis=1)).all()
    assert list(result.metrics["n"]) == [20 if s < 100.0 else 19 for s in t]


def test_progress_callback_and_its_exception(short_hold):
    seen = []
    satflock.run(short_hold, progress=seen.append)
    assert seen == sorted(seen) and seen[-1] == 300.0
    # At most one call per whole percent.
    assert len(seen) <= 101 and len({int(100 * s / 300.0) for s in seen}) == len(seen)

    def fail(t_s):
        if t_s > 100.0:
            raise ZeroDivisionError("from the callback")

    with pytest.raises(ZeroDivisionError, match="from the callback"):
        satflock.run(short_hold, progress=fail)


def test_invalid_input_raises_scenario_error(tmp_path):
    with pytest.raises(satflock.ScenarioError, match="no-such-scenario"):
        satflock.run("no-such-scenario", progress=False)
    bad = tmp_path / "bad.toml"
    bad.write_text(satflock.Scenario.load("hold").to_toml().replace("duration_s = 4000.0", "duration_s = -1.0"))
    with pytest.raises(satflock.ScenarioError) as e:
        satflock.run(str(bad), progress=False)
    assert e.value.key == "duration_s" and e.value.file == str(bad)
    with pytest.raises(ValueError, match="scenario is a int"):
        satflock.Simulation(3)


def test_output_folder_of_someone_else_is_refused(short_hold, tmp_path):
    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(ValueError, match="notes.txt"):
        satflock.run(short_hold, out=tmp_path, progress=False)
    assert (tmp_path / "notes.txt").read_text() == "mine"


def test_a_failed_run_raises_simulation_error_and_keeps_its_files(tmp_path):
    # HCW no-drift orbits from a 200 m ball reach twice their radial amplitude along-track: with an
    # almost idle law, a satellite passes 250 m from the origin within the first quarter orbit.
    scenario = satflock.Scenario.load("hold")
    scenario.update(
        {
            "dynamics.max_distance_m": 250.0,
            "law.stiffness_per_s2": 1e-9,
            "law.damping_per_s": 0.0,
            "law.feedforward": "none",
            "events": [],
        }
    )
    out = tmp_path / "run"
    with pytest.raises(satflock.SimulationError, match=r"satellite \d+ diverged at t = ") as e:
        satflock.run(scenario, out=out, progress=False)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "failed" and summary["error"] == str(e.value)
    assert pyarrow.csv.read_csv(out / "trajectory.csv").num_rows > 20


def test_ctrl_c_stops_the_run_cleanly(tmp_path):
    scenario = satflock.Scenario.load("hold")
    # About 5 to 10 s of work on two cores: SIGINT comes long before the end.
    scenario.update(
        {
            "satellites.count": 1000,
            "satellites.initial.radius_m": 2000.0,
            "output.trajectory": False,
        }
    )
    out = tmp_path / "run"
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            satflock.run(scenario, out=out, progress=False)
    finally:
        timer.cancel()
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "interrupted"
    assert 0.0 < summary["simulated_s"] < 4000.0
    # The metrics file is whole up to the time reached.
    metrics = pyarrow.csv.read_csv(out / "metrics.csv")
    assert metrics["t_s"].to_numpy()[-1] <= summary["simulated_s"]


def test_metrics_are_a_dict_of_numpy_arrays_with_or_without_pyarrow(short_hold, monkeypatch):
    result = satflock.run(short_hold, progress=False)
    assert isinstance(result.metrics, dict)
    with_pyarrow = result.metrics_table()
    monkeypatch.setitem(sys.modules, "pyarrow", None)  # `import pyarrow` now fails
    result = satflock.run(short_hold, progress=False)
    metrics = result.metrics
    with pytest.raises(ImportError, match="pip install pyarrow"):
        result.metrics_table()
    assert isinstance(metrics, dict) and list(metrics) == with_pyarrow.column_names
    assert metrics["n"].dtype == np.int64 and metrics["d_max_m"].dtype == np.float64
    assert metrics["time_utc"].tolist() == with_pyarrow["time_utc"].to_pylist()
    for name in with_pyarrow.column_names[2:]:
        assert np.array_equal(metrics[name], with_pyarrow[name].to_numpy(), equal_nan=True), name


@pytest.mark.parametrize(
    "threads, error",
    [(-1, ValueError), (0, ValueError), (100_000, ValueError), (2**70, ValueError),
     (2.5, TypeError), ("2", TypeError), (True, TypeError)],
)
def test_a_bad_threads_names_threads_and_the_range(short_hold, threads, error):
    for call in (
        lambda: satflock.run(short_hold, threads=threads, progress=False),
        lambda: satflock.Simulation(short_hold, threads=threads),
    ):
        with pytest.raises(error, match=r"threads = .*allowed: an int from 1 to 1024, or None"):
            call()


def test_progress_is_a_bool_or_a_callable(short_hold):
    with pytest.raises(TypeError, match=r"progress = 'yes' is a str \(allowed: True, False"):
        satflock.run(short_hold, progress="yes")
