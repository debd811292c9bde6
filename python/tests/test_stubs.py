"""The type stubs (`satflock/__init__.pyi`, installed with the package beside `py.typed`): they match the
compiled module's names and signatures (mypy's stubtest), and every public item has its docstring."""

import ast
import subprocess
import sys
from pathlib import Path

import satflock

PACKAGE = Path(satflock.__file__).parent

# Not checked against the module: a name the stubs declare for type checkers only (its docstring says
# so), the constructors of results that satflock makes and users do not (the stubs leave them out), and
# the package's private modules (regular expressions).
ALLOWLIST = [
    "satflock.PythonLaw",
    "satflock.RunResult.__init__",
    "satflock.Trajectory.__init__",
    "satflock\\._[a-z]+\\..*",
]

# The package's own Python modules are mypy's to type-check elsewhere, not stubtest's: their errors, and
# the compiled module they import (which has no stub of its own), must not stop the check of the stubs.
MYPY_CONFIG = """[mypy]
ignore_missing_imports = True

[mypy-satflock.*]
ignore_errors = True
"""


def test_stubs_and_marker_are_installed():
    assert (PACKAGE / "__init__.pyi").is_file()
    assert (PACKAGE / "py.typed").is_file()


def test_stubs_match_the_module(tmp_path):
    (tmp_path / "allowlist.txt").write_text("\n".join(ALLOWLIST) + "\n", encoding="utf-8")
    (tmp_path / "mypy.ini").write_text(MYPY_CONFIG, encoding="utf-8")
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "mypy.stubtest",
            "satflock",
            "--allowlist",
            "allowlist.txt",
            "--ignore-unused-allowlist",
            "--mypy-config-file",
            "mypy.ini",
        ],
        cwd=tmp_path,  # mypy's cache stays in the test's folder
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stdout + done.stderr


def test_every_public_item_of_the_stubs_has_a_docstring():
    tree = ast.parse((PACKAGE / "__init__.pyi").read_text(encoding="utf-8"))
    missing = []

    def visit(nodes, prefix):
        for node in nodes:
            if isinstance(node, (ast.FunctionDef, ast.ClassDef)) and not node.name.startswith("_"):
                if ast.get_docstring(node) is None:
                    missing.append(prefix + node.name)
                if isinstance(node, ast.ClassDef):
                    visit(node.body, prefix + node.name + ".")

    visit(tree.body, "satflock.")
    assert not missing, f"without a docstring: {missing}"
