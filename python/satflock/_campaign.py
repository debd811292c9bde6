"""Campaigns from Python: ``satflock.campaign``, on this machine or on Ray.

Both backends run every run with the library's own run function (``satflock::campaign::runner::execute``,
what ``satflock campaign`` runs) and write the same ``manifest.jsonl``, ``campaign.parquet`` and
``summary.md`` through the same Rust code; the returned table is ``campaign.parquet`` read with pyarrow.
"""

from __future__ import annotations

import copy
import functools
import importlib
import os
import shutil
import sys
import tempfile
from typing import Any, Mapping, Optional, Union

from . import _native

__all__ = ["campaign"]

_BACKENDS = ("local", "ray")


def _pyarrow_parquet():
    try:
        import pyarrow.parquet as pq
    except ImportError as e:
        raise ImportError(
            "satflock.campaign returns a pyarrow.Table: pip install pyarrow (from the source tree: "
            'pip install "./python[arrow]")'
        ) from e
    return pq


def _ray():
    try:
        import ray
    except ImportError as e:
        raise ImportError(
            'backend="ray" needs Ray: pip install "ray[default]" (from the source tree: pip install '
            '"./python[ray]")'
        ) from e
    return ray


def _plan(spec: Union[str, os.PathLike, Mapping[str, Any]]) -> "_native.CampaignPlan":
    """The validated campaign of ``spec``: a file path, TOML text or a dict of the file's keys."""
    if isinstance(spec, Mapping):
        return _native.CampaignPlan.from_dict(dict(spec), "<dict>", os.getcwd())
    if isinstance(spec, os.PathLike):
        return _native.CampaignPlan.from_file(os.fspath(spec))
    if isinstance(spec, str):
        # TOML text has a key = value; a path has neither "=" nor a line break.
        if "=" in spec or "\n" in spec:
            return _native.CampaignPlan.from_toml(spec, "<toml>", os.getcwd())
        return _native.CampaignPlan.from_file(spec)
    raise TypeError(
        f"spec is a {type(spec).__name__} (allowed: a campaign file path, TOML text, or a dict of "
        "the campaign file's keys)"
    )


class _Progress:
    """One line on stderr, rewritten as runs start and finish."""

    def __init__(self, enabled: bool, total: int):
        self.enabled = enabled
        self.total = total
        self.done = 0
        self.not_completed = 0
        self.running = 0

    def event(self, kind: str, a: int, b: Optional[str]) -> None:
        if kind == "planned":
            self.total = a
        elif kind == "started":
            self.running += 1
        elif kind == "finished":
            self.running = max(self.running - 1, 0)
            self.done += 1
            if b != "completed":
                self.not_completed += 1
        if self.enabled:
            sys.stderr.write(
                f"\rcampaign: {self.done}/{self.total} runs done, {self.not_completed} not completed, "
                f"{self.running} in progress "
            )
            sys.stderr.flush()

    def close(self) -> None:
        if self.enabled:
            sys.stderr.write("\n")
            sys.stderr.flush()


def _check_count(name: str, value: Optional[int], allow_none: bool) -> None:
    if value is None and allow_none:
        return
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        allowed = "an integer >= 1" + (", or None" if allow_none else "")
        raise ValueError(f"{name} = {value!r} (allowed: {allowed})")


def campaign(
    spec: Union[str, os.PathLike, Mapping[str, Any]],
    backend: str = "local",
    out: Optional[Union[str, os.PathLike]] = None,
    jobs: Optional[int] = None,
    resume: bool = False,
    keep_runs: bool = False,
    cpus_per_run: int = 1,
    progress: bool = True,
    law: Any = None,
):
    """Runs a campaign (docs/campaigns.md) and returns its table: ``campaign.parquet`` as a
    ``pyarrow.Table``, one row per finished run in run order.

    Arguments:
        spec: the campaign: a campaign file path (str or os.PathLike; a scenario path in it is
            relative to the file's folder), TOML text (a str holding ``=``), or a dict of the file's
            keys (``scenario``, ``seeds``, ``set``, ``vary``, ``sampling``, ``outcomes``, ``keep_runs``,
            ``description``; dotted keys as in the file, e.g. ``{"vary": {"law.k_f_kg_per_m_s2":
            [0.002, 0.004]}}``). For text and dicts a scenario path is relative to the current folder.
            Every key is validated before anything runs: a bad one raises ``CampaignError`` naming the
            key (attributes ``file`` and ``key``).
        backend: ``"local"``: the library's runner (``satflock campaign``) on this machine, ``jobs``
            runs at once, each on one thread. ``"ray"``: each run is one Ray task
            (``ray.remote(num_cpus=cpus_per_run)``) running the same Rust run function on
            ``cpus_per_run`` threads; the records come back to this process, which writes the
            manifest (as runs finish), the table and the summary with the same Rust code.
        out: output folder: a new path or an empty folder (with ``resume``, the campaign's folder).
            It receives ``manifest.jsonl``, ``runs/NNNNN/`` (each run's ``summary.json`` and
            ``scenario.toml``; everything with ``keep_runs``), ``campaign.parquet`` and ``summary.md``.
            None: a temporary folder, removed once the table is read (Ray tasks then write their run
            folders to their own temporary folders).
        jobs: runs at once, >= 1. Local: None means one per core. Ray: None submits every run and lets
            Ray schedule them by their CPUs; a number caps the tasks in flight.
        resume: continue the campaign in ``out``: keep the runs its manifest records as completed, run
            the others. Refused if the campaign or its scenario changed (needs ``out``).
        keep_runs: keep every run's full outputs (also the campaign key ``keep_runs = true``).
        cpus_per_run: CPUs (Ray's ``num_cpus``) and rayon threads of each Ray task, >= 1. The local
            backend runs each run on one thread (only 1 is accepted there). A run's result does not
            depend on its thread count.
        progress: a bool: a progress line on stderr (runs done, not completed, in progress), rewritten
            in place, only when stderr is a terminal.
        law: a guidance law written in Python, run in place of the scenario's law in every run (as
            ``satflock.run(law=...)`` takes it): an object with ``command(ctx)`` (local backend; each
            run gets its own ``copy.deepcopy``), or a ``"module:name"`` string naming a class or a
            zero-argument factory that makes one (either backend; on Ray each task imports the module,
            so it must be importable on every node, e.g. installed or on ``PYTHONPATH``). The runs of
            a Python law hold the GIL while it computes: locally they run one at a time (``jobs`` must
            be None or 1). None: the scenario's law.

    Returns a ``pyarrow.Table`` (see docs/campaigns.md, ``campaign.parquet``): ``status``, ``error``,
    ``seed`` (text), ``run``, ``point``, ``parameter.KEY`` for each varied key, then every scalar
    outcome of the runs' ``summary.json`` by dotted name (SI units, named in the name). The columns
    ``wall_time_s`` and ``satellite_steps_per_s`` measure the machine and differ between any two
    executions; every other column is the same bit for bit whatever the backend, ``jobs`` or
    ``cpus_per_run``.

    Ray: an existing Ray session is used if ``ray.is_initialized()``; otherwise ``ray.init()`` is
    called, which joins the cluster named by the ``RAY_ADDRESS`` environment variable (e.g.
    ``RAY_ADDRESS=ray://head:10001`` or ``auto``) or starts a local one. To point it at a cluster
    yourself, call ``ray.init(address=...)`` before ``campaign``. On several machines, satflock must be
    installed on every node, a scenario file must be readable at the same path on every node, and
    ``out`` must be on a shared filesystem for the runs' own folders to end up in it; the table comes
    back through Ray either way.

    Raises ``CampaignError`` for a bad campaign, an output folder that cannot hold it or a manifest
    that cannot be resumed; ``ValueError`` for a bad argument; ``ImportError`` without pyarrow (or
    without Ray for ``backend="ray"``: ``pip install "ray[default]"``). A run that fails is not an
    error: its row says ``status`` and ``error``. Ctrl-C stops the campaign (running runs are
    recorded as interrupted locally, cancelled on Ray), writes the table and summary of what
    finished, and raises ``KeyboardInterrupt``; ``resume=True`` runs the rest.
    """
    if backend not in _BACKENDS:
        raise ValueError(f"backend = {backend!r} (allowed: 'local' or 'ray')")
    if not isinstance(progress, bool):
        raise TypeError(f"progress = {progress!r} is a {type(progress).__name__} (allowed: True or False)")
    _check_count("jobs", jobs, allow_none=True)
    _check_count("cpus_per_run", cpus_per_run, allow_none=False)
    if backend == "local" and cpus_per_run != 1:
        raise ValueError(
            f"cpus_per_run = {cpus_per_run} with backend='local' (allowed: 1; the local backend runs "
            "each run on one thread, `jobs` at once; cpus_per_run is for backend='ray')"
        )
    if resume and out is None:
        raise ValueError("resume=True needs out: the folder of the campaign to continue")
    fresh_law, law_path = _law_argument(law, backend, jobs)
    pq = _pyarrow_parquet()
    plan = _plan(spec)
    if backend == "ray":
        ray = _ray()
    temporary = tempfile.mkdtemp(prefix="satflock-campaign-") if out is None else None
    folder = temporary if temporary is not None else os.fspath(out)
    bar = _Progress(progress and sys.stderr is not None and sys.stderr.isatty(), plan.run_count)
    try:
        try:
            if backend == "local" and fresh_law is None:
                dropped = plan.run_local(folder, jobs, resume, keep_runs, bar.event)
            elif backend == "local":
                dropped = _run_local_with_law(plan, folder, resume, keep_runs, fresh_law, bar)
            else:
                dropped = _run_on_ray(ray, plan, folder, temporary is not None, jobs, resume,
                                      keep_runs, cpus_per_run, bar, law_path)
        finally:
            bar.close()
        for line in dropped:
            sys.stderr.write(f"warning: resume dropped {line}\n")
        table_path = os.path.join(folder, "campaign.parquet")
        if not os.path.exists(table_path):
            # No run finished (possible only when every run was stopped).
            import pyarrow as pa

            return pa.table({})
        return pq.read_table(table_path, memory_map=False)
    finally:
        if temporary is not None:
            shutil.rmtree(temporary, ignore_errors=True)


@functools.lru_cache(maxsize=8)
def _plan_in_worker(text: str, file: str, base_dir: str) -> "_native.CampaignPlan":
    """The campaign in a Ray worker, validated once per worker process."""
    return _native.CampaignPlan.from_toml(text, file, base_dir)


def _law_from_path(path: str) -> Any:
    """A fresh law from ``"module:name"``: the module imported, ``name`` called (a class or a
    zero-argument factory)."""
    module, sep, name = path.partition(":")
    if not sep or not module or not name:
        raise ValueError(f"law = {path!r} (allowed: 'module:name', e.g. 'my_laws:PDHold')")
    try:
        factory = getattr(importlib.import_module(module), name)
    except (ImportError, AttributeError) as e:
        raise ValueError(f"law = {path!r}: {e} (the module must be importable here)") from e
    law = factory()
    if not callable(getattr(law, "command", None)):
        raise TypeError(f"law = {path!r} made a {type(law).__name__} without a command(ctx) method")
    return law


def _law_argument(law: Any, backend: str, jobs: Optional[int]):
    """(a maker of a fresh law per run, or None; the module path for Ray tasks, or None), checked
    before anything runs."""
    if law is None:
        return None, None
    if backend == "local" and jobs not in (None, 1):
        raise ValueError(
            f"jobs = {jobs} with a Python law (allowed: None or 1: a law written in Python holds the "
            "GIL, so its runs go one at a time)"
        )
    if isinstance(law, str):
        _law_from_path(law)  # imported and made once here: a bad path fails before anything runs
        return (lambda: _law_from_path(law)), law
    if backend == "ray":
        raise ValueError(
            f"law = {law!r} with backend='ray' (allowed: a 'module:name' string that each Ray task "
            "imports; an object cannot be sent to the tasks)"
        )
    if not callable(getattr(law, "command", None)):
        raise TypeError(
            f"law = {law!r} is a {type(law).__name__} without a command(ctx) method (allowed: a "
            "guidance law object, a 'module:name' string, or None)"
        )
    return (lambda: copy.deepcopy(law)), None


def _run_local_with_law(plan, folder, resume, keep_runs, fresh_law, bar):
    """The runs left in ``folder``, one at a time in this process, each with a fresh Python law; the
    manifest, table and summary written by the same Rust code as the other backends. Returns the
    manifest lines ``resume`` dropped."""
    output = plan.prepare(folder, resume)
    to_run = list(output.to_run)
    bar.event("planned", len(to_run), str(output.already_complete))
    try:
        for index in to_run:
            bar.event("started", index, None)
            status = output.append(plan.run_one(index, folder, keep_runs, 1, fresh_law()))
            bar.event("finished", index, status)
    except BaseException:
        output.finish()
        raise
    output.finish()
    return list(output.dropped)


def _run_task(
    spec, index: int, out: Optional[str], keep_runs: bool, threads: int, law_path: Optional[str] = None
) -> str:
    """One run in a Ray task: the library's run function (with the law ``law_path`` names, imported
    in this worker, if any); its record as JSON text."""
    plan = _plan_in_worker(*spec)
    law = _law_from_path(law_path) if law_path is not None else None
    if out is None:
        with tempfile.TemporaryDirectory(prefix="satflock-run-") as private:
            return plan.run_one(index, private, keep_runs, threads, law)
    return plan.run_one(index, out, keep_runs, threads, law)


def _run_on_ray(ray, plan, folder, private_runs, jobs, resume, keep_runs, cpus_per_run, bar, law_path):
    """Runs the runs left in ``folder`` as Ray tasks; the driver appends each record to the
    manifest as it arrives and writes the table and summary at the end (also when stopped).
    Returns the manifest lines ``resume`` dropped."""
    if not ray.is_initialized():
        ray.init()
    output = plan.prepare(folder, resume)
    to_run = list(output.to_run)
    bar.event("planned", len(to_run), str(output.already_complete))
    task = ray.remote(num_cpus=cpus_per_run)(_run_task)
    spec = (plan.text, plan.file, os.fspath(plan.base_dir))
    runs_out = None if private_runs else folder
    limit = jobs if jobs is not None else max(len(to_run), 1)
    pending = {}
    queue = iter(to_run)
    try:
        while True:
            while len(pending) < limit:
                index = next(queue, None)
                if index is None:
                    break
                ref = task.remote(spec, index, runs_out, keep_runs, cpus_per_run, law_path)
                pending[ref] = index
                bar.event("started", index, None)
            if not pending:
                break
            done, _ = ray.wait(list(pending), num_returns=1)
            for ref in done:
                index = pending.pop(ref)
                status = output.append(ray.get(ref))
                bar.event("finished", index, status)
    except BaseException:
        for ref in pending:
            ray.cancel(ref)
        output.finish()
        raise
    output.finish()
    return list(output.dropped)
