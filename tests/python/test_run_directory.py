"""A run directory read by Python's own csv and json modules: the time columns agree with the epoch."""

import csv
import datetime
import json

from conftest import run_satflock


def test_time_utc_is_epoch_plus_elapsed_seconds(satflock_bin, tmp_path):
    out = tmp_path / "run"
    run_satflock(satflock_bin, "run", "free-drift", "--out", str(out), "--quiet")
    summary = json.loads((out / "summary.json").read_text())
    # Both carry the zone letter `Z`: parsed as aware UTC instants.
    assert summary["epoch_utc"].endswith("Z")
    epoch = datetime.datetime.fromisoformat(summary["epoch_utc"].replace("Z", "+00:00"))
    assert summary["time_system"] == "UTC"
    assert summary["frames"]["inertial"] == "EME2000"
    with open(out / "metrics.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) > 1
    for row in rows:
        assert row["time_utc"].endswith("Z")
        t = datetime.datetime.fromisoformat(row["time_utc"].replace("Z", "+00:00"))
        assert abs((t - epoch).total_seconds() - float(row["t_s"])) < 1e-6
