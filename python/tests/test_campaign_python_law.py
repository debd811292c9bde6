"""`satflock.campaign(law=...)`: a guidance law written in Python in every run of a campaign. The numpy
PD law of test_python_law.py against the campaign of the built-in `hold` it mirrors: the same table to
the last bit (timing columns aside), given as an object or as a "module:name" path, locally and on Ray."""

import os
import pathlib

import pytest

pa = pytest.importorskip("pyarrow")

import satflock  # noqa: E402

from test_python_law import PDHold  # noqa: E402

TIMING = {"wall_time_s", "satellite_steps_per_s"}

# 4 satellites holding their slots for 60 s, 3 seeds, no navigation noise (the Python law reads the
# truth, which `hold` then senses too).
SPEC = {
    "scenario": "hold",
    "seeds": [7, 11, 13],
    "set": {"duration_s": 60.0, "satellites.count": 4, "events": []},
}


def pd_hold():
    """The factory the "module:name" path names: the PD law with `hold`'s gains."""
    return PDHold(1e-4, 2e-2)


def assert_same_runs(table, reference):
    names = [n for n in reference.column_names if n not in TIMING]
    assert [n for n in table.column_names if n not in TIMING] == names
    for name in names:
        assert table.column(name).to_pylist() == reference.column(name).to_pylist(), name


@pytest.fixture(scope="module")
def hold_table():
    return satflock.campaign(SPEC, progress=False)


def test_a_python_law_object_gives_the_table_of_hold(hold_table):
    table = satflock.campaign(SPEC, law=pd_hold(), progress=False)
    assert table.column("status").to_pylist() == ["completed"] * 3
    assert_same_runs(table, hold_table)


def test_a_module_path_law_gives_the_same_table(hold_table, tmp_path):
    table = satflock.campaign(SPEC, law="test_campaign_python_law:pd_hold", out=tmp_path / "c", progress=False)
    assert_same_runs(table, hold_table)
    # The runs' own summaries say which law ran.
    summary = (tmp_path / "c" / "runs" / "00000" / "summary.json").read_text()
    assert '"python:pd-hold"' in summary


def test_bad_law_arguments_are_refused_before_anything_runs(tmp_path):
    with pytest.raises(ValueError, match="jobs"):
        satflock.campaign(SPEC, law=pd_hold(), jobs=2, progress=False)
    with pytest.raises(ValueError, match="module:name"):
        satflock.campaign(SPEC, law="no_colon", progress=False)
    with pytest.raises(ValueError, match="importable"):
        satflock.campaign(SPEC, law="no_such_module_here:x", progress=False)
    with pytest.raises(TypeError, match="command"):
        satflock.campaign(SPEC, law=42, progress=False)
    with pytest.raises(ValueError, match="ray"):
        satflock.campaign(SPEC, backend="ray", law=pd_hold(), progress=False)
    assert not any(tmp_path.iterdir())


def test_ray_tasks_import_the_law_by_its_module_path(hold_table):
    ray = pytest.importorskip("ray")
    here = str(pathlib.Path(__file__).parent)
    path = os.pathsep.join(p for p in (here, os.environ.get("PYTHONPATH")) if p)
    ray.init(
        num_cpus=2,
        include_dashboard=False,
        log_to_driver=False,
        runtime_env={"env_vars": {"PYTHONPATH": path}},
    )
    try:
        table = satflock.campaign(
            SPEC, backend="ray", law="test_campaign_python_law:pd_hold", progress=False
        )
    finally:
        ray.shutdown()
    assert_same_runs(table, hold_table)
