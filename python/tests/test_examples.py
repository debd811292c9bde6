"""python/examples/: each example runs as a script, with small settings."""

import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def run_example(name, *args, cwd):
    done = subprocess.run(
        [sys.executable, str(EXAMPLES / name), *args], cwd=cwd, capture_output=True, text=True
    )
    assert done.returncode == 0, f"{name} {' '.join(args)} exited {done.returncode}:\n{done.stderr}"
    return done.stdout


def test_gao_circle_tour_draws_its_figures(tmp_path):
    pytest.importorskip("matplotlib")
    out = run_example(
        "gao_circle_tour.py", "--seeds", "3", "--duration-s", "60", "--plots", "figures", cwd=tmp_path
    )
    # gao-circle records every 10 s: 60 s hold 60 / 10 + 1 = 7 records of its 50 satellites.
    assert "hill (7, 50, 6)" in out
    assert "campaign (local): 3 of 3 runs completed" in out
    for name in ("five_elements.png", "formation.png"):
        assert (tmp_path / "figures" / name).read_bytes().startswith(PNG_MAGIC)


def test_gao_circle_tour_on_ray_without_figures(tmp_path):
    pytest.importorskip("ray")
    out = run_example(
        "gao_circle_tour.py", "--seeds", "3", "--duration-s", "60", "--no-plots", "--ray", cwd=tmp_path
    )
    assert "figures: not drawn (--no-plots)" in out
    assert "campaign (ray): 3 of 3 runs completed" in out
    assert not (tmp_path / "gao-circle-tour").exists()
