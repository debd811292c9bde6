"""The README's "From Python" example, run as written: the example a reader copies is itself tested."""

import contextlib
import io
import json
import re
import subprocess
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[2] / "README.md"


def section(text, title):
    """The lines of the README section `## title`, up to the next heading of the same or a higher level."""
    lines = text.splitlines()
    for i, line in enumerate(lines):
        heading = re.match(r"^(#+)\s+(.*?)\s*$", line)
        if heading and heading.group(2) == title:
            level = len(heading.group(1))
            end = next(
                (
                    j
                    for j in range(i + 1, len(lines))
                    if re.match(r"^#{1,%d}\s" % level, lines[j])
                ),
                len(lines),
            )
            return lines[i + 1 : end]
    pytest.fail(f"README.md has no section {title!r}")


def fenced(lines, language):
    """The body of every ```language block among `lines`."""
    blocks, body = [], None
    for line in lines:
        if body is None and line.strip() == "```" + language:
            body = []
        elif body is not None and line.strip() == "```":
            blocks.append("\n".join(body) + "\n")
            body = None
        elif body is not None:
            body.append(line)
    return blocks


def test_readme_from_python_section_installs_with_one_command():
    sh = fenced(section(README.read_text(encoding="utf-8"), "From Python"), "sh")
    assert ["pip install ./python\n"] == sh


def test_readme_from_python_example_runs(tmp_path, monkeypatch, satflock_bin):
    blocks = fenced(section(README.read_text(encoding="utf-8"), "From Python"), "python")
    assert len(blocks) == 1, "the section holds one ```python example"
    lines = [line for line in blocks[0].splitlines() if line.strip()]
    assert len(lines) <= 10, f"the example is ten lines at most, not {len(lines)}"

    monkeypatch.chdir(tmp_path)  # anything the example writes stays in the test's folder
    stdout = io.StringIO()
    with contextlib.redirect_stdout(stdout):
        exec(compile(blocks[0], f"{README}:From Python", "exec"), {"__name__": "__readme__"})
    printed = stdout.getvalue().splitlines()

    # What the example prints, against the scenario it says it runs: gao-circle (50 satellites, a record
    # every 10 s) shortened to 200 s gives 200 / 10 + 1 = 21 records ...
    status, delta_v = printed[0].split()
    assert status == "completed"
    assert printed[1] == "(21,) (21, 50, 6)"
    # ... and the CLI's run of the same scenario (its built-in text, shortened here) the same delta-v.
    text = subprocess.run(
        [str(satflock_bin), "scenarios", "show", "gao-circle"], capture_output=True, text=True, check=True
    ).stdout
    text, replaced = re.subn(r"(?m)^duration_s = .*$", "duration_s = 200.0", text)
    assert replaced == 1
    (tmp_path / "short.toml").write_text(text, encoding="utf-8")
    subprocess.run(
        [str(satflock_bin), "run", "short.toml", "--out", "cli", "--no-plots"], capture_output=True, check=True
    )
    summary = json.loads((tmp_path / "cli" / "summary.json").read_text(encoding="utf-8"))
    assert float(delta_v) == summary["delta_v_mps"]["mean"]
