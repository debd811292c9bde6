"""Runs, step-by-step simulation and their results as numpy arrays.

Frames: Hill LVLH (x radial out, y along-track, z orbit normal) relative to the LVLH origin, and EME2000
inertial. SI units: m, m/s, s, kg.

A guidance law written in Python is any object with a method ``command(ctx)`` returning the commanded
accelerations of every satellite, an (N, 3) array [m/s^2] in the Hill frame (rows of removed satellites
are ignored), and optionally an attribute ``name`` (str). It is called once per control tick (sampled
control only: a scenario with ``[control] mode = "continuous"`` is refused) with a ``LawContext``
(``time_s``, ``tick``, ``period_s``, ``positions_hill`` (N, 3), ``velocities_hill`` (N, 3), ``active``
(N,), ``mass_kg`` (N,), ``sensing_range_m``, the CSR neighbour lists ``neighbour_offsets`` (N + 1,) and
``neighbour_indices`` (M,), ``mean_motion_rad_per_s``). It is a whole-swarm (centralised) law: it sees
the truth states, without navigation noise or link outages. The actuator limits, thruster failures and
events of the scenario apply to its commands as to any law's; the scenario's own law events
(``set-law-parameters``, ``switch-law``) are refused. It is slower than a law written in Rust: every
tick takes the GIL, copies the states into arrays and runs Python. Measured on the ``hold`` scenario
(J2 truth, RK4 at 1 s, one thread) with a numpy PD law: 20 satellites 7.8e5 satellite-steps/s against
2.4e6 for the built-in law (about 18 us more per tick); 200 and 2000 satellites within 10 % of the
built-in law's 1.2e6 to 1.3e6 (the propagation dominates); reading the neighbour lists (about 8
neighbours each) costs 1.3 times (200) to 1.9 times (2000 satellites) the built-in law's time.
"""

from __future__ import annotations

import json
import os
import pathlib
import sys
import tempfile
from typing import Any, Callable, Optional, Union

import numpy as np

from . import _native
from ._native import Scenario

__all__ = ["RunResult", "Simulation", "Trajectory", "run"]


class Trajectory:
    """The states of every satellite at every recording time, as read-only numpy arrays.

    Attributes:
        t_s: (R,) recording times, seconds since the scenario start [s].
        ids: (N,) int64 satellite indices (0 .. N - 1); axis 1 of the arrays below.
        hill: (R, N, 6) Hill LVLH states relative to the LVLH origin: x, y, z [m] then vx, vy, vz [m/s]
            (velocities relative to the rotating frame).
        eci: (R, N, 6) EME2000 inertial states: x, y, z [m] then vx, vy, vz [m/s].
        delta_v_mps: (R, N) delta-v spent so far by each satellite [m/s].
        law_outputs: dict name -> (R, N) per-satellite law outputs (the unit or meaning is in the name).

    A satellite not alive at a record (removed by an event) is a row of NaN at that record: the rows of
    the run's ``trajectory`` table (one per live satellite) placed on a (records, satellites) grid.
    """

    __slots__ = ("t_s", "ids", "hill", "eci", "delta_v_mps", "law_outputs")

    def __init__(self, arrays: dict) -> None:
        self.t_s: np.ndarray = arrays["t_s"]
        self.ids: np.ndarray = arrays["ids"]
        self.hill: np.ndarray = arrays["hill"]
        self.eci: np.ndarray = arrays["eci"]
        self.delta_v_mps: np.ndarray = arrays["delta_v_mps"]
        self.law_outputs: dict = dict(arrays["law_outputs"])

    def __repr__(self) -> str:
        records, satellites = self.delta_v_mps.shape
        return f"Trajectory(records={records}, satellites={satellites})"


def _metrics(columns: dict) -> dict:
    """The metrics columns as a dict of numpy arrays (the same with or without pyarrow)."""
    columns = dict(columns)
    columns["time_utc"] = np.array(columns["time_utc"], dtype=str)
    return columns


def _metrics_table(columns: dict) -> Any:
    """The metrics columns (``_metrics``) as a ``pyarrow.Table``."""
    try:
        import pyarrow
    except ImportError as e:
        raise ImportError(
            "metrics_table() returns a pyarrow.Table and needs pyarrow: pip install pyarrow (from the "
            'source tree: pip install "./python[arrow]"); the metrics attribute is a dict of numpy '
            "arrays without it"
        ) from e
    return pyarrow.table(columns)


class RunResult:
    """What ``satflock.run`` returns.

    Attributes:
        summary: dict, ``summary.json`` of the run.
        status: str, the summary's status (``completed``).
        out: ``pathlib.Path`` of the output folder, or None when the run went to a temporary folder
            (removed afterwards).
        metrics: the metrics table, one row per recording time, always a dict of numpy arrays (R,) by
            column, whatever is installed: ``t_s`` [s], ``time_utc`` (ISO 8601 UTC strings), then the
            columns of ``metrics.csv`` (counts as int64, NaN where a value does not exist).
            ``metrics_table()`` gives it as a ``pyarrow.Table`` (needs pyarrow; its ``to_pandas()``
            needs pandas too).
        trajectory: a ``Trajectory``, or None when the scenario writes none
            (``[output] trajectory = false``).
    """

    __slots__ = ("summary", "status", "out", "metrics", "trajectory")

    def __init__(self, raw: dict, out: Optional[pathlib.Path]) -> None:
        self.summary: dict = json.loads(raw["summary"])
        self.status: str = self.summary["status"]
        self.out = out
        self.metrics = _metrics(raw["metrics"])
        self.trajectory: Optional[Trajectory] = (
            None if raw["trajectory"] is None else Trajectory(raw["trajectory"])
        )

    def metrics_table(self) -> Any:
        """The metrics as a ``pyarrow.Table`` (same columns and values as ``metrics``); raises
        ``ImportError`` without pyarrow."""
        return _metrics_table(self.metrics)

    def __repr__(self) -> str:
        return (
            f"RunResult(scenario={self.summary['scenario']!r}, status={self.status!r}, "
            f"out={self.out!r})"
        )


class _TerminalProgress:
    """Prints the run's progress to stderr as a percentage of its duration."""

    def __init__(self, duration_s: float) -> None:
        self.duration_s = duration_s

    def __call__(self, t_s: float) -> None:
        sys.stderr.write(f"\rsatflock: {100.0 * t_s / self.duration_s:3.0f} %")
        sys.stderr.flush()

    def close(self) -> None:
        sys.stderr.write("\n")
        sys.stderr.flush()


def run(
    scenario: Union[Scenario, str, os.PathLike],
    out: Union[str, os.PathLike, None] = None,
    threads: Optional[int] = None,
    progress: Union[bool, Callable[[float], Any]] = True,
    law: Any = None,
) -> RunResult:
    """Runs a scenario as ``satflock run`` does and returns its summary, metrics and trajectory.

    Args:
        scenario: a ``Scenario``, a built-in scenario name (``"gao-circle"``) or a path to a TOML file.
        out: the output folder (new, empty, or a previous run's, whose files are replaced); it gets the
            files of ``satflock run``: summary.json, metrics and trajectory tables, scene.json,
            scenario.toml. None: a temporary folder, removed before returning.
        threads: rayon threads for this run (>= 1); None: one per core. Results do not depend on it.
        progress: True prints the percentage done to stderr when stderr is a terminal; False nothing;
            or a callable receiving the simulated time [s] each time a whole percent of the run passes
            (an exception it raises stops the run and is raised).
        law: a guidance law written in Python (see the module documentation) run instead of the
            scenario's law; None: the scenario's law.

    Returns:
        A ``RunResult``; ``status`` is ``completed``.

    Raises:
        ScenarioError: the scenario is invalid (or cannot take ``law``: continuous control, law events).
        SimulationError: the run failed (divergence, a Python law that raised or returned a bad array;
            the message is the one ``satflock run`` prints). With ``out`` given, the files written so
            far stay there, with summary.json saying ``failed``.
        KeyboardInterrupt: Ctrl-C: the run stops cleanly (with ``out`` given, its files are valid up to
            that time and summary.json says ``interrupted``).
        ValueError: ``out`` holds files that are not a previous run's, or ``threads`` is an int out of
            1 to 1024.
        TypeError: ``threads`` is not an int or None, or ``progress`` not a bool or a callable.
    """
    if not (isinstance(progress, bool) or callable(progress)):
        raise TypeError(
            f"progress = {progress!r} is a {type(progress).__name__} (allowed: True, False, or a "
            "callable taking the simulated time [s])"
        )
    if not isinstance(scenario, Scenario):
        scenario = Scenario.load(os.fspath(scenario))
    printer = None
    if callable(progress):
        callback = progress
    elif progress and sys.stderr is not None and sys.stderr.isatty():
        callback = printer = _TerminalProgress(float(scenario["duration_s"]))
    else:
        callback = None
    try:
        if out is None:
            with tempfile.TemporaryDirectory(prefix="satflock-run-") as folder:
                raw = _native.run(scenario, folder, threads, callback, law)
            return RunResult(raw, None)
        folder = pathlib.Path(out)
        raw = _native.run(scenario, folder, threads, callback, law)
        return RunResult(raw, folder)
    finally:
        if printer is not None:
            printer.close()


class Simulation(_native.Simulation):
    """A scenario stepped from Python: ``Simulation(scenario, law=None, threads=None)``.

    ``scenario``: a ``Scenario``, a built-in name or a path; ``law``: a guidance law written in Python
    run instead of the scenario's (see the module documentation); ``threads``: rayon threads of every
    advance (None: one per core; results do not depend on it).

    It is the simulation ``satflock.run`` builds, with an in-memory recorder keeping the rows the CLI
    writes (same columns, same values): ``advance_to(t_s)`` at recording or tick times, in as many
    calls as wanted, gives bit-identical results to ``satflock run``. ``advance_to``, ``step`` and
    ``run`` release the GIL; Ctrl-C raises ``KeyboardInterrupt`` and leaves the simulation usable at
    the time reached.

    State arrays (``positions_hill``, ``velocities_hill``, ``positions_eci``, ``velocities_eci``, (N, 3);
    ``active`` (N,); ``law_outputs``) are read-only copies: the engine keeps each satellite's state as
    one struct (array of structures), so a zero-copy numpy view is not possible. Removed satellites are
    rows of NaN.
    """

    @property
    def trajectory(self) -> Optional[Trajectory]:
        """The records so far as a ``Trajectory`` (None when the scenario writes no trajectory)."""
        arrays = self._trajectory_arrays()
        return None if arrays is None else Trajectory(arrays)

    @property
    def metrics(self) -> dict:
        """The metrics rows so far, as ``RunResult.metrics`` (a dict of numpy arrays by column)."""
        return _metrics(self._metrics_columns())

    def metrics_table(self) -> Any:
        """The metrics rows so far as a ``pyarrow.Table`` (needs pyarrow)."""
        return _metrics_table(self.metrics)
