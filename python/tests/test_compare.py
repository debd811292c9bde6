"""`satflock.compare`: laws side by side on one case from Python, a Python law among them. The numpy PD
law of test_python_law.py against the built-in `hold` on the same case gives the same row to rounding,
and the table has compare.parquet's columns."""

import math

import pytest

import satflock

from test_python_law import PDHold


def _controller_of_the_case(case, folder):
    """A controller file with the case's own law (so that `hold` runs with the case's gains and no law
    event)."""
    law = case["law"]
    lines = ["[law]"]
    for key, value in law.items():
        if isinstance(value, bool):
            text = "true" if value else "false"
        elif isinstance(value, str):
            text = f'"{value}"'
        else:
            text = repr(value)
        lines.append(f"{key} = {text}")
    path = folder / "hold-case.toml"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def test_a_python_law_in_compare_equals_the_built_in_hold(short_hold, tmp_path):
    pytest.importorskip("pyarrow")
    controller = _controller_of_the_case(short_hold, tmp_path)
    table = satflock.compare(
        short_hold, laws=[PDHold(1e-4, 2e-2), str(controller)], seeds=[1, 2], threads=1
    )
    rows = table.to_pylist()
    assert table.column_names[:6] == ["law", "controller", "law_name", "status", "error", "seed"]
    assert [(r["law"], r["seed"]) for r in rows] == [
        ("pd-hold", 1),
        ("pd-hold", 2),
        ("hold-case", 1),
        ("hold-case", 2),
    ]
    assert [r["controller"] for r in rows] == ["python:pd-hold"] * 2 + [str(controller)] * 2
    assert [r["law_name"] for r in rows] == ["python", "python", "hold", "hold"]
    assert all(r["status"] == "completed" and r["error"] == "" for r in rows)
    outcomes = [c for c in table.column_names[6:] if c not in ("wall_time_s", "satellite_steps_per_s")]
    assert "delta_v_mps.mean" in outcomes and "min_separation_m" in outcomes
    for python_row, rust_row in ((rows[0], rows[2]), (rows[1], rows[3])):
        for name in outcomes:
            a, b = python_row[name], rust_row[name]
            if a is None or b is None:
                assert a is None and b is None, name
            else:
                assert math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-12), (name, a, b)
    # Different seeds are different draws of the case's initial states.
    assert rows[0]["final.five_elements.d_max_m"] != rows[1]["final.five_elements.d_max_m"]


def test_compare_refuses_bad_laws_before_running(short_hold, tmp_path):
    pytest.importorskip("pyarrow")
    controller = str(_controller_of_the_case(short_hold, tmp_path))
    with pytest.raises(TypeError, match="laws"):
        satflock.compare(short_hold, laws=controller)
    with pytest.raises(TypeError, match=r"laws\[1\]"):
        satflock.compare(short_hold, laws=[controller, 42])
    with pytest.raises(ValueError, match="label"):
        satflock.compare(short_hold, laws=[controller, controller])
    with pytest.raises(satflock.ScenarioError, match="no-such"):
        satflock.compare(short_hold, laws=["builtin:no-such"])
    # A controller whose law event falls outside the case: refused naming both, nothing run.
    with pytest.raises(satflock.ScenarioError, match="events"):
        satflock.compare(short_hold, laws=["builtin:hold"])
    with pytest.raises(ValueError, match="seeds"):
        satflock.compare(short_hold, laws=[controller], seeds=[-1])
