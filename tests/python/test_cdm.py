"""satflock's CCSDS CDMs (508.0-B-1, KVN) read back by the `ccsds-ndm` package (an independent NDM
reader), each one's TCA, miss distance, relative state and both objects' states compared with the run's
conjunction table (conjunctions.csv), to the printed precision."""

import csv
import datetime
import json
import random

import pytest
from ccsds_ndm.ndm_io import NdmIo

from conftest import run_satflock


def scenario_text():
    """Sixteen satellites drifting in a 120 m ball, navigation noise, one threat crossing it."""
    rng = random.Random(7)
    states = []
    for k in range(16):
        p = [rng.uniform(-120.0, 120.0) for _ in range(3)]
        if k == 0:
            p = [0.0, 0.0, 0.0]
        v = [rng.uniform(-0.15, 0.15) for _ in range(3)]
        states.append("[" + ", ".join(repr(x) for x in p + v) + "]")
    return f"""name = "conjunctions"
seed = 1
duration_s = 1200.0
record_interval_s = 60.0
[dynamics]
model = "j2"
integrator = "rk4"
step_s = 1.0
[reference]
altitude_m = 600e3
inclination_deg = 98.0
[control]
mode = "sampled"
period_s = 10.0
[satellites]
count = 16
mass_kg = 5.0
radius_m = 0.1
initial = {{ distribution = "list", frame = "hill", states = [{", ".join(states)}] }}
[sensing]
range_m = 100.0
position_noise_m = 0.5
velocity_noise_mps = 0.001
[law]
name = "none"
[[threats]]
name = "crossing"
danger_radius_m = 1.0
position_hill_m = [0.0, -60.0, 20.0]
velocity_hill_mps = [0.0, 0.6, 0.0]
at_time_s = 0.0
[conjunctions]
threshold_m = 60.0
"""


@pytest.fixture(scope="module")
def run_dir(satflock_bin, tmp_path_factory):
    base = tmp_path_factory.mktemp("cdm")
    (base / "conjunctions.toml").write_text(scenario_text())
    out = base / "run"
    run_satflock(satflock_bin, "run", str(base / "conjunctions.toml"), "--out", str(out), "--quiet")
    return out


def table(run_dir):
    with open(run_dir / "conjunctions.csv", newline="") as f:
        return list(csv.DictReader(f))


def test_every_cdm_matches_the_conjunction_table(satflock_bin, run_dir):
    run_satflock(satflock_bin, "export", "cdm", str(run_dir))
    rows = table(run_dir)
    summary = json.loads((run_dir / "summary.json").read_text())
    assert summary["conjunctions"]["count"] == len(rows) >= 4
    assert any(r["secondary_threat"] for r in rows)
    epoch = datetime.datetime.fromisoformat(summary["epoch_utc"].removesuffix("Z"))
    files = sorted((run_dir / "cdm").glob("*.cdm"))
    assert len(files) == len(rows)
    for path, row in zip(files, rows):
        cdm = NdmIo().from_path(str(path))
        assert cdm.header.originator == "SATFLOCK"
        assert cdm.header.message_id
        rel = cdm.body.relative_metadata_data
        tca = datetime.datetime.fromisoformat(str(rel.tca))
        assert abs((tca - epoch).total_seconds() - float(row["tca_s"])) < 1e-6
        assert abs(rel.miss_distance.value - float(row["miss_distance_m"])) <= 0.5e-6
        assert abs(rel.relative_speed.value - float(row["relative_speed_mps"])) <= 0.5e-9
        relative = rel.relative_state_vector
        for axis in "rtn":
            position = getattr(relative, f"relative_position_{axis}").value
            assert abs(position - float(row[f"relative_{axis}_rtn_m"])) <= 0.5e-6
            velocity = getattr(relative, f"relative_velocity_{axis}").value
            assert abs(velocity - float(row[f"relative_v{axis}_rtn_mps"])) <= 0.5e-9
        first, second = cdm.body.segment
        assert first.metadata.object_value.value == "OBJECT1"
        assert first.metadata.object_name == f"SAT-{int(row['primary']):05d}"
        if row["secondary"]:
            assert second.metadata.object_name == f"SAT-{int(row['secondary']):05d}"
        else:
            assert second.metadata.object_name == f"THREAT-{int(row['secondary_threat']):05d}"
        for segment, who in ((first, "primary"), (second, "secondary")):
            assert segment.metadata.ref_frame.value == "EME2000"
            state = segment.data.state_vector
            for key, column in (("x", "x"), ("y", "y"), ("z", "z")):
                km = float(row[f"{who}_{column}_eme2000_m"]) / 1000.0
                assert abs(getattr(state, key).value - km) <= 0.5e-9 + 1e-15 * abs(km)
                kms = float(row[f"{who}_v{column}_eme2000_mps"]) / 1000.0
                assert abs(getattr(state, f"{key}_dot").value - kms) <= 0.5e-12 + 1e-15 * abs(kms)
        # A satellite's covariance is its navigation noise (0.5 m, 1 mm/s), diagonal.
        cov = first.data.covariance_matrix
        assert cov.cr_r.value == pytest.approx(0.25) and cov.ct_r.value == 0.0
        assert cov.cndot_ndot.value == pytest.approx(1e-6)


def test_top_and_below_select_the_closest(satflock_bin, run_dir, tmp_path):
    rows = table(run_dir)
    misses = sorted(float(r["miss_distance_m"]) for r in rows)
    run_satflock(satflock_bin, "export", "cdm", str(run_dir), "--top", "2", "--out", str(tmp_path / "top"))
    top = [NdmIo().from_path(str(p)).body.relative_metadata_data.miss_distance.value
           for p in sorted((tmp_path / "top").glob("*.cdm"))]
    assert sorted(top) == pytest.approx(misses[:2], abs=1e-6)
    limit = (misses[1] + misses[2]) / 2
    run_satflock(satflock_bin, "export", "cdm", str(run_dir), "--below", str(limit), "--out",
                 str(tmp_path / "below"))
    assert len(list((tmp_path / "below").glob("*.cdm"))) == 2
