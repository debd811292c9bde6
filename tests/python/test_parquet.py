"""trajectory.parquet and metrics.parquet read by pyarrow: column metadata (unit, frame), file metadata,
and every value equal to the CSV of the same run read by Python's csv module (an empty cell is a null)."""

import csv
import json
import math
import struct

import pyarrow.parquet as pq

from conftest import run_satflock

# A law with per-satellite outputs and a threat (es-e3a), shortened.
SCENARIO = "es-e3a"


def _shortened(tmp_path, satflock_bin):
    """es-e3a cut to 140 s, written beside the runs (the built-in's text comes from a run's scenario.toml)."""
    first = tmp_path / "first"
    run_satflock(satflock_bin, "run", SCENARIO, "--out", str(first), "--quiet", "--format", "csv")
    text = (first / "scenario.toml").read_text()
    assert "duration_s = 430.0" in text
    path = tmp_path / "short.toml"
    path.write_text(text.replace("duration_s = 430.0", "duration_s = 140.0"))
    return path


def _bits(value: float) -> int:
    return struct.unpack("<Q", struct.pack("<d", value))[0]


def _assert_same(csv_path, parquet_path):
    with open(csv_path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        rows = list(reader)
    table = pq.read_table(parquet_path)
    assert table.column_names == header
    assert table.num_rows == len(rows)
    for k, name in enumerate(header):
        values = table.column(name).to_pylist()
        for r, (cell, value) in enumerate(zip((row[k] for row in rows), values)):
            where = f"{parquet_path.name} row {r} column {name}"
            if name == "time_utc":
                assert value == cell, where
            elif cell == "":
                assert value is None, where
            elif isinstance(value, int):
                assert value == int(cell), where
            else:
                assert value is not None and _bits(value) == _bits(float(cell)), f"{where}: {value} vs {cell}"
    return len(rows)


def test_parquet_metadata_and_values_equal_the_csv(satflock_bin, tmp_path):
    scenario = _shortened(tmp_path, satflock_bin)
    csv_run, parquet_run = tmp_path / "csv", tmp_path / "parquet"
    run_satflock(satflock_bin, "run", str(scenario), "--out", str(csv_run), "--quiet", "--format", "csv")
    run_satflock(satflock_bin, "run", str(scenario), "--out", str(parquet_run), "--quiet", "--format", "parquet")

    schema = pq.read_schema(parquet_run / "trajectory.parquet")
    meta = {f.name: {k.decode(): v.decode() for k, v in (f.metadata or {}).items()} for f in schema}
    assert meta["x_lvlh_m"] == {"unit": "m", "frame": "Hill LVLH"}
    assert meta["vz_lvlh_mps"] == {"unit": "m/s", "frame": "Hill LVLH"}
    assert meta["x_eme2000_m"] == {"unit": "m", "frame": "EME2000"}
    assert meta["vx_eme2000_mps"] == {"unit": "m/s", "frame": "EME2000"}
    assert meta["t_s"] == {"unit": "s"}
    assert meta["delta_v_mps"] == {"unit": "m/s"}
    assert meta["id"] == {"unit": "1"}
    assert meta["es_mode"] == {"unit": "1"}
    assert meta["time_utc"] == {"unit": "UTC"}

    summary = json.loads((parquet_run / "summary.json").read_text())
    file_meta = pq.ParquetFile(parquet_run / "trajectory.parquet").metadata.metadata
    assert file_meta[b"scenario"].decode() == summary["scenario"] == SCENARIO
    assert int(file_meta[b"seed"]) == summary["seed"]
    assert file_meta[b"epoch_utc"].decode() == summary["epoch_utc"]
    assert file_meta[b"satflock_version"].decode() == summary["metadata"]["satflock_version"]
    assert schema.metadata[b"scenario"].decode() == SCENARIO

    rows = _assert_same(csv_run / "trajectory.csv", parquet_run / "trajectory.parquet")
    assert rows == 6 * 141
    assert _assert_same(csv_run / "metrics.csv", parquet_run / "metrics.parquet") == 141
    # The CSV's empty cell at t = 0 (no threat distance observed yet) is a null, not NaN.
    first = pq.read_table(parquet_run / "metrics.parquet").slice(0, 1).to_pylist()[0]
    assert first["min_threat_distance_m"] is None
    assert not any(isinstance(v, float) and math.isnan(v) for v in first.values())
