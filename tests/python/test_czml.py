"""satflock's CZML validated packet by packet by czml3's pydantic models (unknown keys are errors), the
document as a whole by czml3's `Document` (preamble first, with name and version), and its positions
compared with the run's trajectory.csv."""

import csv
import json

import pytest
from czml3.core import Document, Packet

from conftest import run_satflock


@pytest.fixture(scope="module")
def run_dir(satflock_bin, tmp_path_factory):
    out = tmp_path_factory.mktemp("czml") / "run"
    run_satflock(satflock_bin, "run", "free-drift", "--out", str(out), "--quiet")
    return out


def load(path):
    packets = json.loads(path.read_text())
    for packet in packets:
        Packet.model_validate(packet)
    Document.model_validate(packets)
    return packets


def test_decimated_document_keeps_evenly_spaced_satellites_and_every_kth_time(satflock_bin, run_dir):
    done = run_satflock(
        satflock_bin, "export", "czml", str(run_dir), "--max-satellites", "10", "--max-samples", "50"
    )
    packets = load(run_dir / "swarm.czml")
    with open(run_dir / "trajectory.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    times = sorted({float(r["t_s"]) for r in rows})
    every = -(-len(times) // 50)
    kept_times = times[::every]
    document = packets[0]
    assert document["id"] == "document" and document["version"] == "1.0"
    assert document["clock"]["range"] == "LOOP_STOP"
    assert document["clock"]["step"] == "SYSTEM_CLOCK_MULTIPLIER"
    # What was kept is said in the document and on stderr.
    for text in (document["description"], done.stderr):
        assert "10 of 50 satellites" in text
        assert f"{len(kept_times)} of {len(times)} recorded times" in text
    satellites = packets[1:]
    assert [p["id"] for p in satellites] == [f"sat-{i:05d}" for i in range(0, 50, 5)]
    for packet in satellites:
        sat = int(packet["id"].split("-")[1])
        position = packet["position"]
        assert position["referenceFrame"] == "INERTIAL"
        assert position["interpolationAlgorithm"] == "LAGRANGE"
        cartesian = position["cartesian"]
        expected = [
            value
            for r in rows
            if int(r["id"]) == sat and float(r["t_s"]) in kept_times
            for value in (float(r["t_s"]), float(r["x_eme2000_m"]), float(r["y_eme2000_m"]),
                          float(r["z_eme2000_m"]))
        ]
        assert len(cartesian) == 4 * len(kept_times)
        assert cartesian == expected  # metres, exactly (shortest round-trip numbers both ways)
        assert "path" in packet  # 10 satellites: paths drawn


def test_default_document_keeps_a_small_run_whole(satflock_bin, run_dir, tmp_path):
    out = tmp_path / "all.czml"
    run_satflock(satflock_bin, "export", "czml", str(run_dir), "--out", str(out))
    packets = load(out)
    assert len(packets) == 1 + 50
    assert "all 50 satellites" in packets[0]["description"]
