"""campaign.parquet read by pyarrow: one row per run, its text and number columns, and every outcome equal
bit for bit to the run's summary.json and to its manifest line, both read by Python's json module."""

import json
import struct

import pyarrow as pa
import pyarrow.parquet as pq

from conftest import run_satflock

# 4 satellites drifting from a 200 m ball for 1200 s: max_distance 205 m makes the run fail (diverged).
CAMPAIGN = """
scenario = "free-drift"
seeds = [3, 8]
[set]
duration_s = 1200.0
"satellites.count" = 4
"satellites.initial.radius_m" = 200.0
[vary]
"dynamics.max_distance_m" = [1e6, 205.0]
"""


def _bits(value: float) -> int:
    return struct.unpack("<Q", struct.pack("<d", value))[0]


def test_campaign_table_matches_the_runs_and_the_manifest(satflock_bin, tmp_path):
    path = tmp_path / "drift.toml"
    path.write_text(CAMPAIGN)
    out = tmp_path / "out"
    run_satflock(satflock_bin, "campaign", str(path), "--out", str(out), "--quiet", "--jobs", "2")

    table = pq.read_table(out / "campaign.parquet")
    assert table.num_rows == 4
    file_metadata = pq.ParquetFile(out / "campaign.parquet").metadata.metadata
    metadata = {k.decode(): v.decode() for k, v in file_metadata.items()}
    assert metadata["scenario"] == "builtin:free-drift"
    assert len(metadata["campaign_sha256"]) == 64
    for name in ("status", "error", "seed"):
        assert table.schema.field(name).type == pa.string()
    for name in ("run", "point", "parameter.dynamics.max_distance_m", "delta_v_mps.mean"):
        assert table.schema.field(name).type == pa.float64()
    rows = table.to_pylist()
    assert [r["run"] for r in rows] == [0.0, 1.0, 2.0, 3.0]
    assert [r["seed"] for r in rows] == ["3", "8", "3", "8"]
    assert [r["status"] for r in rows] == ["completed", "completed", "failed", "failed"]
    assert [r["parameter.dynamics.max_distance_m"] for r in rows] == [1e6, 1e6, 205.0, 205.0]
    assert rows[0]["error"] == "" and "diverged" in rows[2]["error"]

    lines = (out / "manifest.jsonl").read_text().splitlines()
    header = json.loads(lines[0])
    assert header["runs"] == 4 and header["seeds"] == [3, 8]
    manifest = {r["run"]: r for r in map(json.loads, lines[1:])}
    assert sorted(manifest) == [0, 1, 2, 3]

    for row in rows:
        k = int(row["run"])
        summary = json.loads((out / "runs" / f"{k:05d}" / "summary.json").read_text())
        assert summary["seed"] == int(row["seed"])
        assert summary["status"] == row["status"]
        # Scalars of the summary by dotted name, as the table names them.
        scalars = {}

        def walk(prefix, value):
            if isinstance(value, bool):
                scalars[prefix] = float(value)
            elif isinstance(value, (int, float)):
                scalars[prefix] = float(value)
            elif isinstance(value, dict):
                for key, item in value.items():
                    walk(f"{prefix}.{key}" if prefix else key, item)
            elif isinstance(value, list) and len(value) <= 6 and all(
                isinstance(v, (int, float)) and not isinstance(v, bool) for v in value
            ):
                for i, item in enumerate(value):
                    walk(f"{prefix}.{i}", item)

        for key, value in summary.items():
            if key not in ("metadata", "seed", "threads", "timing"):
                walk(key, value)
        assert len(scalars) > 15
        for name, value in scalars.items():
            assert _bits(row[name]) == _bits(value), f"run {k} {name}"
            assert _bits(manifest[k]["outcomes"][name]) == _bits(value), f"manifest run {k} {name}"
