"""satflock.campaign: the local backend against the command line's campaign.parquet and hand-known
facts, the Ray backend against the local backend, and bad campaigns refused naming the key."""

import json
import os
import subprocess
import sys

import pytest

pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")

import satflock  # noqa: E402

# Columns that measure the machine (differ between any two executions of the same run).
TIMING = {"wall_time_s", "satellite_steps_per_s"}

SEEDS = [7, 11]
DAMPINGS = [0.01, 0.02]

# 4 satellites holding their slots for 30 s with navigation noise (so the seed matters): 2 dampings x 2
# seeds = 4 runs.
SPEC = {
    "scenario": "hold",
    "seeds": SEEDS,
    "set": {
        "duration_s": 30.0,
        "satellites.count": 4,
        "events": [],
        "sensing.position_noise_m": 0.5,
    },
    "vary": {"law.damping_per_s": DAMPINGS},
}

TOML = """
scenario = "hold"
seeds = [7, 11]
[set]
duration_s = 30.0
"satellites.count" = 4
events = []
"sensing.position_noise_m" = 0.5
[vary]
"law.damping_per_s" = [0.01, 0.02]
"""


def without_timing(table):
    return table.drop_columns([c for c in table.column_names if c in TIMING])


def assert_same_table(a, b):
    assert a.column_names == b.column_names
    assert set(TIMING) <= set(a.column_names)
    a, b = without_timing(a), without_timing(b)
    for name in a.column_names:
        assert a.column(name).equals(b.column(name)), name
    assert a.equals(b)


@pytest.fixture(scope="module")
def local_table():
    return satflock.campaign(SPEC, progress=False)


def test_local_table_holds_the_grid_and_seeds(local_table):
    t = local_table
    assert t.num_rows == len(DAMPINGS) * len(SEEDS)
    assert t.column("run").to_pylist() == [0.0, 1.0, 2.0, 3.0]
    assert t.column("point").to_pylist() == [0.0, 0.0, 1.0, 1.0]
    assert t.column("seed").to_pylist() == ["7", "11", "7", "11"]
    assert t.column("parameter.law.damping_per_s").to_pylist() == [0.01, 0.01, 0.02, 0.02]
    assert t.column("status").to_pylist() == ["completed"] * 4
    assert t.column("error").to_pylist() == [""] * 4
    # Every run flew 4 satellites; the seeds differ, so their outcomes do.
    d = t.column("delta_v_mps.mean").to_pylist()
    assert all(v > 0 for v in d) and d[0] != d[1]


def test_spec_forms_give_the_same_table(local_table, tmp_path, monkeypatch):
    path = tmp_path / "c.toml"
    path.write_text(TOML)
    for spec in (TOML, str(path), path):
        assert_same_table(satflock.campaign(spec, progress=False, jobs=1), local_table)


def test_local_equals_the_command_line(satflock_bin, local_table, tmp_path):
    path = tmp_path / "c.toml"
    path.write_text(TOML)
    cli_out = tmp_path / "cli"
    subprocess.run(
        [satflock_bin, "campaign", str(path), "--out", str(cli_out), "--quiet"],
        check=True,
        capture_output=True,
    )
    cli = pq.read_table(cli_out / "campaign.parquet")
    assert_same_table(local_table, cli)
    # The same campaign file from Python writes the same folder (the table also in the file).
    out = tmp_path / "py"
    table = satflock.campaign(path, out=out, progress=False)
    assert_same_table(table, pq.read_table(out / "campaign.parquet"))
    assert sorted(os.listdir(out)) == sorted(p for p in os.listdir(cli_out) if p != "plots")
    assert sorted(os.listdir(out / "runs")) == ["00000", "00001", "00002", "00003"]


def test_bad_key_raises_campaign_error_naming_it():
    bad = dict(SPEC, vary={"law.no_such_gain": [1.0]})
    with pytest.raises(satflock.CampaignError) as info:
        satflock.campaign(bad, progress=False)
    assert info.value.key == "vary.law.no_such_gain"
    assert "vary.law.no_such_gain" in str(info.value)
    bad = dict(SPEC, set=dict(SPEC["set"], duration_s=-1.0))
    with pytest.raises(satflock.CampaignError) as info:
        satflock.campaign(bad, progress=False)
    assert info.value.key == "set.duration_s"
    with pytest.raises(satflock.CampaignError) as info:
        satflock.campaign(dict(SPEC, seedz=[1]), progress=False)
    assert "seedz" in str(info.value)


def test_bad_arguments(tmp_path):
    for kwargs, says in [
        (dict(backend="dask"), "backend = 'dask'"),
        (dict(jobs=0), "jobs = 0"),
        (dict(cpus_per_run=2), "cpus_per_run = 2 with backend='local'"),
        (dict(resume=True), "resume=True needs out"),
    ]:
        with pytest.raises(ValueError) as info:
            satflock.campaign(SPEC, progress=False, **kwargs)
        assert says in str(info.value)
    (tmp_path / "x").write_text("not a campaign")
    with pytest.raises(satflock.CampaignError) as info:
        satflock.campaign(SPEC, out=tmp_path, progress=False)
    assert "holds no campaign manifest.jsonl" in str(info.value)
    with pytest.raises(satflock.CampaignError) as info:
        satflock.campaign(str(tmp_path / "missing.toml"), progress=False)
    assert "cannot read the file" in str(info.value)


def test_missing_ray_or_pyarrow_says_how_to_install_what_exists(monkeypatch):
    # satflock is not on PyPI: the hints name packages that are, and the source tree's extras.
    monkeypatch.setitem(sys.modules, "ray", None)
    with pytest.raises(ImportError, match=r'pip install "ray\[default\]" .*pip install "./python\[ray\]"'):
        satflock.campaign(SPEC, backend="ray", progress=False)
    monkeypatch.setitem(sys.modules, "pyarrow.parquet", None)
    with pytest.raises(ImportError, match=r'pip install pyarrow .*pip install "./python\[arrow\]"'):
        satflock.campaign(SPEC, progress=False)


def test_progress_is_a_bool_and_written_only_to_a_terminal(capfd):
    with pytest.raises(TypeError, match=r"progress = 'yes' is a str \(allowed: True or False\)"):
        satflock.campaign(SPEC, progress="yes")
    # pytest's captured stderr is not a terminal: no progress line, no carriage return.
    satflock.campaign(SPEC, progress=True)
    assert "\r" not in capfd.readouterr().err


@pytest.fixture(scope="module")
def ray_session():
    ray = pytest.importorskip("ray")
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    yield ray
    ray.shutdown()


def test_ray_gives_the_local_table(ray_session, local_table, tmp_path):
    out = tmp_path / "ray"
    table = satflock.campaign(SPEC, backend="ray", out=out, cpus_per_run=1, progress=False)
    assert_same_table(table, local_table)
    # The driver wrote the same folder as the local runner: manifest, runs, table and summary.
    lines = (out / "manifest.jsonl").read_text().splitlines()
    assert json.loads(lines[0])["runs"] == 4
    assert sorted(json.loads(line)["run"] for line in lines[1:]) == [0, 1, 2, 3]
    assert (out / "summary.md").read_text().startswith("#")
    assert sorted(os.listdir(out / "runs")) == ["00000", "00001", "00002", "00003"]
    # Runs to temporary folders (out=None), two tasks at most in flight: the same table.
    assert_same_table(satflock.campaign(SPEC, backend="ray", jobs=2, progress=False), local_table)


def test_ray_resumes_a_local_campaign(ray_session, local_table, tmp_path):
    out = tmp_path / "c"
    satflock.campaign(SPEC, out=out, progress=False)
    lines = (out / "manifest.jsonl").read_text().splitlines()
    # Drop run 2's record: resuming on Ray runs it alone and gives the same table.
    kept = [lines[0]] + [line for line in lines[1:] if json.loads(line)["run"] != 2]
    (out / "manifest.jsonl").write_text("\n".join(kept) + "\n")
    table = satflock.campaign(SPEC, backend="ray", out=out, resume=True, progress=False)
    assert_same_table(table, local_table)
    lines = (out / "manifest.jsonl").read_text().splitlines()
    assert [json.loads(line)["run"] for line in lines[1:]][-1] == 2


def test_resume_says_which_manifest_lines_it_dropped(tmp_path, capfd, local_table):
    out = tmp_path / "c"
    satflock.campaign(SPEC, out=out, progress=False)
    manifest = out / "manifest.jsonl"
    lines = manifest.read_text().splitlines()
    forged = json.loads(lines[1])
    forged["seed"] = 999
    manifest.write_text("\n".join(lines + [json.dumps(forged), "garbage"]) + "\n")
    capfd.readouterr()
    table = satflock.campaign(SPEC, out=out, resume=True, progress=False)
    err = capfd.readouterr().err
    assert f"warning: resume dropped manifest.jsonl line {len(lines) + 1}: run {forged['run']}: seed 999" in err
    assert f"warning: resume dropped manifest.jsonl line {len(lines) + 2}: not a run record" in err
    assert_same_table(table, local_table)
