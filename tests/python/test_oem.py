"""satflock's CCSDS OEM read by the Python `oem` package (an independent KVN parser that checks the
standard's keywords, their constraints and its one-object-per-file rule), every state compared with the
run's trajectory.csv converted to km and km/s, to the printed precision (1e-9 km, 1e-12 km/s)."""

import csv
import datetime
import json

import pytest
from oem import OrbitEphemerisMessage

from conftest import run_satflock

# 1 700 000 000 s after 1970-01-01T00:00:00Z.
SOURCE_DATE_EPOCH = "1700000000"
CREATION_DATE = datetime.datetime(2023, 11, 14, 22, 13, 20)


def trajectory_by_satellite(run_dir):
    by_id = {}
    with open(run_dir / "trajectory.csv", newline="") as f:
        for row in csv.DictReader(f):
            by_id.setdefault(int(row["id"]), []).append(row)
    return by_id


@pytest.fixture(scope="module")
def run_dir(satflock_bin, tmp_path_factory):
    out = tmp_path_factory.mktemp("oem") / "run"
    run_satflock(satflock_bin, "run", "free-drift", "--out", str(out), "--quiet")
    return out


def test_every_state_matches_the_trajectory_in_km(satflock_bin, run_dir, monkeypatch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", SOURCE_DATE_EPOCH)
    run_satflock(satflock_bin, "export", "oem", str(run_dir))
    summary = json.loads((run_dir / "summary.json").read_text())
    # summary.json's epoch carries the zone letter (aware); the OEM's epochs are UTC without it (naive).
    assert summary["epoch_utc"].endswith("Z")
    epoch = datetime.datetime.fromisoformat(summary["epoch_utc"].removesuffix("Z"))
    rows = trajectory_by_satellite(run_dir)
    files = sorted((run_dir / "oem").glob("sat-*.oem"))
    assert len(files) == len(rows) == summary["n_satellites"]
    for path in files:
        sat = int(path.stem.split("-")[1])
        ephemeris = OrbitEphemerisMessage.open(str(path))
        assert ephemeris.header["CCSDS_OEM_VERS"] == "2.0"
        assert ephemeris.header["ORIGINATOR"] == "satflock"
        assert ephemeris.header["CREATION_DATE"].datetime == CREATION_DATE
        (segment,) = ephemeris.segments
        meta = segment.metadata
        assert meta["OBJECT_NAME"] == f"SAT-{sat:05d}"
        assert meta["CENTER_NAME"] == "EARTH"
        assert meta["REF_FRAME"] == "EME2000"
        assert meta["TIME_SYSTEM"] == "UTC"
        assert meta["INTERPOLATION"] == "LAGRANGE"
        states = list(segment.states)
        expected = rows[sat]
        assert len(states) == len(expected)
        for state, row in zip(states, expected):
            elapsed = (state.epoch.datetime - epoch).total_seconds()
            assert abs(elapsed - float(row["t_s"])) < 1e-6
            for axis, name in enumerate("xyz"):
                km = float(row[f"{name}_eme2000_m"]) / 1000.0
                assert abs(state.position[axis] - km) <= 0.5e-9 + 1e-15 * abs(km)
                kms = float(row[f"v{name}_eme2000_mps"]) / 1000.0
                assert abs(state.velocity[axis] - kms) <= 0.5e-12 + 1e-15 * abs(kms)


def test_the_swarm_file_holds_the_same_segments(satflock_bin, run_dir, monkeypatch):
    """`--single-file` (`swarm.oem`, named non-standard) puts every satellite in one file, a segment
    each: the per-satellite files' segments, byte for byte. The strict reader refuses such a file: CCSDS
    502.0-B-2 (5.1.3) defines an OEM for one object, which is why one file per satellite is the
    default (docs/outputs.md says so)."""
    monkeypatch.setenv("SOURCE_DATE_EPOCH", SOURCE_DATE_EPOCH)
    run_satflock(satflock_bin, "export", "oem", str(run_dir), "--single-file")
    run_satflock(satflock_bin, "export", "oem", str(run_dir))
    swarm = (run_dir / "swarm.oem").read_text()
    blocks = ["META_START" + b for b in swarm.split("META_START")[1:]]
    files = sorted((run_dir / "oem").glob("sat-*.oem"))
    assert len(blocks) == len(files)
    for block, path in zip(blocks, files):
        text = path.read_text()
        assert block.rstrip("\n") == text[text.index("META_START") :].rstrip("\n")
    with pytest.raises(ValueError, match="OBJECT_NAME not fixed"):
        OrbitEphemerisMessage.open(str(run_dir / "swarm.oem"))
