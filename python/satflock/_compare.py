"""``satflock.compare``: laws side by side on one case, from Python, with laws written in Python among
them: the table ``satflock compare`` writes as compare.parquet, as a ``pyarrow.Table``."""

from __future__ import annotations

import copy
import json
import math
import os
from typing import Any, Iterable, List, Optional, Sequence, Tuple, Union

from . import _native
from ._native import Scenario, SimulationError
from ._run import run


def _pyarrow():
    try:
        import pyarrow
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError(
            "satflock.compare returns a pyarrow.Table: install pyarrow (pip install pyarrow)"
        ) from e
    return pyarrow


def _entries(case: Scenario, laws: Sequence[Any]) -> List[Tuple[str, str, str, Scenario, Any]]:
    """(label, controller, law_name, scenario, python_law) per law, checked before anything runs."""
    if isinstance(laws, (str, bytes)) or not isinstance(laws, Sequence) or len(laws) == 0:
        raise TypeError(
            f"laws = {laws!r} (allowed: a non-empty list of controller files or 'builtin:NAME' "
            "strings, and guidance-law objects with a command(ctx) method)"
        )
    entries = []
    for k, law in enumerate(laws):
        if isinstance(law, (str, os.PathLike)):
            spec = os.fspath(law)
            scenario = case.with_controller(spec)
            label = _native.controller_label(spec)
            entries.append((label, spec, str(scenario["law.name"]), scenario, None))
        elif callable(getattr(law, "command", None)):
            name = str(getattr(law, "name", type(law).__name__))
            entries.append((name, f"python:{name}", "python", case.copy(), law))
        else:
            raise TypeError(
                f"laws[{k}] = {law!r} is a {type(law).__name__} (allowed: a controller file or "
                "'builtin:NAME' string, or a guidance-law object with a command(ctx) method)"
            )
    labels = [e[0] for e in entries]
    for k, label in enumerate(labels):
        if labels.index(label) != k:
            raise ValueError(
                f"laws[{k}] has the label {label!r}, as laws[{labels.index(label)}] has (labels are "
                "file names without extension, built-in names, or a Python law's `name`: give "
                "each law its own)"
            )
    return entries


def compare(
    case: Union[Scenario, str, os.PathLike],
    laws: Sequence[Any],
    seeds: Iterable[int] = (1,),
    threads: Optional[int] = None,
) -> Any:
    """Runs every law on one case for every seed and returns the table of runs, one row per (law, seed),
    as ``satflock compare`` writes it to compare.parquet.

    Args:
        case: the case: a ``Scenario``, a built-in name or a path to a TOML file.
        laws: the laws: controller files or ``"builtin:NAME"`` strings (as ``satflock compare --law``
            takes them: the controller's law and law events replace the case's), and guidance laws
            written in Python (objects with ``command(ctx)``, as ``satflock.run(law=...)`` takes them;
            each run gets its own ``copy.deepcopy`` of the object, so a law's state starts afresh),
            in any mix. Each row's ``law`` is the label: the file name without extension, the built-in's
            name, or the Python law's ``name`` attribute (else its class name); labels must differ.
        seeds: the scenario seeds (ints >= 0), each run with every law.
        threads: rayon threads per run (results do not depend on it); None: one per core.

    Returns:
        A ``pyarrow.Table`` with the text columns ``law``, ``controller`` (the file, ``builtin:NAME`` or
        ``python:NAME``), ``law_name`` (the registry name, or ``python``), ``status`` (``completed`` or
        ``failed``) and ``error``, then ``seed`` (uint64), then every scalar outcome of the runs'
        summary.json by dotted name (float64; null where a run lacks it).

    Raises:
        ScenarioError: the case or a controller is invalid (nothing runs).
        TypeError, ValueError: ``laws`` or ``seeds`` are not as allowed.
    """
    pa = _pyarrow()
    if not isinstance(case, Scenario):
        case = Scenario.load(os.fspath(case))
    seeds = list(seeds)
    if not seeds or not all(isinstance(s, int) and not isinstance(s, bool) and s >= 0 for s in seeds):
        raise ValueError(f"seeds = {seeds!r} (allowed: a non-empty list of ints >= 0)")
    entries = _entries(case, laws)
    text = {name: [] for name in ("law", "controller", "law_name", "status", "error")}
    seed_column: List[int] = []
    outcome_rows = []
    for label, controller, law_name, scenario, python_law in entries:
        for seed in seeds:
            steered = scenario.copy()
            steered["seed"] = seed
            try:
                # Each run steers with its own copy of a Python law: a law that keeps state (slots
                # taken at its first tick, say) starts every run afresh.
                law = copy.deepcopy(python_law)
                result = run(steered, threads=threads, progress=False, law=law)
                status, error = "completed", ""
                outcomes = dict(_native.scalar_outcomes(json.dumps(result.summary)))
            except SimulationError as e:
                status, error, outcomes = "failed", str(e), {}
            for name, value in (
                ("law", label),
                ("controller", controller),
                ("law_name", law_name),
                ("status", status),
                ("error", error),
            ):
                text[name].append(value)
            seed_column.append(seed)
            outcome_rows.append(outcomes)
    order: List[str] = []
    for row in outcome_rows:
        for name in row:
            if name not in order:
                order.append(name)
    columns = {name: pa.array(values, pa.string()) for name, values in text.items()}
    columns["seed"] = pa.array(seed_column, pa.uint64())
    for name in order:
        values = [row.get(name, math.nan) for row in outcome_rows]
        columns[name] = pa.array(
            [None if math.isnan(v) else v for v in values], pa.float64()
        )
    return pa.table(columns)
