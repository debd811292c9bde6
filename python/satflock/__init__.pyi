"""Type stubs of the `satflock` package (the compiled `satflock._native` and its pure-Python parts).

Units are SI throughout: metres, seconds, kilograms, radians (degrees only where a name ends in `_deg`).
Frames:

* Hill LVLH: centred on the scenario's reference orbit (or origin member); x radial outward, y along-track,
  z along the orbit normal (right-handed). Relative positions [m] and velocities [m/s] in this rotating frame.
* EME2000: Earth-centred inertial (z on Earth's rotation axis for the J2 term; no precession or nutation).

Array shapes below use R = records (recording times), N = satellites, T = output times, M = neighbour pairs.
Arrays returned by satflock are float64 unless stated otherwise.
"""

import os
import pathlib
from typing import Any, Callable, Iterable, Literal, Mapping, Optional, Protocol, Sequence, Union, final

import numpy as np
import numpy.typing as npt
import pyarrow

__version__: str

__all__ = [
    "CampaignError",
    "LawContext",
    "RunResult",
    "Scenario",
    "ScenarioError",
    "Simulation",
    "SimulationError",
    "Trajectory",
    "__version__",
    "budget",
    "campaign",
    "characterize",
    "compare",
    "propagate",
    "run",
]

_FloatArray = npt.NDArray[np.float64]
_IntArray = npt.NDArray[np.int64]
_BoolArray = npt.NDArray[np.bool_]

# ---------------------------------------------------------------------------------------------- errors

class ScenarioError(ValueError):
    """A scenario that cannot be read or is invalid.

    The message is the one `satflock run` prints: the file, the dotted key and the allowed range.
    """

    file: Optional[str]
    """The scenario's source (a path, `builtin:NAME`, `<toml>` or `<dict>`), or None."""
    key: Optional[str]
    """The dotted key at fault (`"law.k_f_kg_per_m_s2"`), or None when the whole file is at fault."""

class SimulationError(RuntimeError):
    """A run that could not finish: divergence (naming the satellite and time), a law that failed (a
    Python law's exception or a command of the wrong shape or with NaN), or an output that could not be
    written."""

class CampaignError(ValueError):
    """A campaign file, dict or output directory that cannot be used (naming the file and the key)."""

# -------------------------------------------------------------------------------------------- scenario

@final
class Scenario:
    """A scenario: what `satflock run` reads, held as its TOML table.

    Keys carry their unit in their name (`duration_s`, `law.k_f_kg_per_m_s2`, `reference.altitude_m`);
    the full reference is docs/scenarios.md. Every change is validated at once: an invalid value raises
    `ScenarioError` naming the key and the allowed range, and is not kept.
    """

    @staticmethod
    def load(name_or_path: str) -> "Scenario":
        """Loads a scenario file (a path that exists) or a built-in scenario by name (`"gao-circle"`)."""
    @staticmethod
    def from_toml(text: str, source: str = "<toml>", base_dir: str = ".") -> "Scenario":
        """A scenario from TOML text; `source` names it in error messages, `base_dir` resolves the relative
        paths in it. Validated fully, as `satflock run` does before it starts: a bad value (a NaN
        `duration_s`) raises `ScenarioError` here, naming the key."""
    @staticmethod
    def from_dict(d: Mapping[str, Any], source: str = "<dict>", base_dir: str = ".") -> "Scenario":
        """A scenario from a dict of the TOML file's tables and keys (as `to_dict()` returns them),
        validated as `from_toml`. A dict or list that contains itself, or nesting deeper than 64 levels,
        raises `ScenarioError`."""
    @staticmethod
    def builtins() -> list[str]:
        """The names of the built-in scenarios (`satflock scenarios` lists them with descriptions)."""
    def to_dict(self) -> dict[str, Any]:
        """The scenario as a dict of its tables and keys (a copy: change the scenario by item assignment)."""
    def to_toml(self) -> str:
        """The scenario as TOML text (what `satflock run` reads)."""
    def validate(self) -> None:
        """Checks every value (ranges, consistency, initial states) as `satflock run` does before it
        starts; raises `ScenarioError`."""
    def update(self, values: Mapping[str, Any]) -> None:
        """Sets several dotted keys at once, with one validation for all (for values that must change
        together, e.g. `{"duration_s": 100.0, "events": []}`)."""
    def __getitem__(self, key: str, /) -> Any:
        """The value at a dotted key (`"law.name"`, `"threats.0.speed_mps"`); `KeyError` if it is not set."""
    def __setitem__(self, key: str, value: Any, /) -> None:
        """Sets the value at a dotted key and validates the scenario (`ScenarioError` leaves it unchanged)."""
    def __contains__(self, key: object, /) -> bool:
        """Whether a dotted key is set."""
    @property
    def name(self) -> str:
        """The scenario's `name` key."""
    @property
    def source(self) -> str:
        """Where the scenario came from: a path, `builtin:NAME`, `<toml>` or `<dict>`."""
    def with_controller(self, spec: str) -> "Scenario":
        """This scenario (the case) steered by a controller file or `builtin:NAME`, as `satflock run CASE
        --law SPEC` takes it: the controller's law and law events replace the case's; validated
        (`ScenarioError` names both files)."""
    def copy(self) -> "Scenario":
        """An independent copy."""
    def __copy__(self) -> "Scenario": ...
    def __deepcopy__(self, memo: Any, /) -> "Scenario": ...

# ------------------------------------------------------------------------------------------------ runs

class Trajectory:
    """Every recorded state of a run: one record every `record_interval_s` of the scenario, at the times
    of the CLI's `trajectory` table. A satellite not alive at a record (removed by an event) has NaN in
    its row of `hill`, `eci`, `delta_v_mps` and the law outputs. The arrays are read-only. Made by
    satflock (`RunResult.trajectory`, `Simulation.trajectory`), not by users."""

    t_s: _FloatArray
    """Record times since the scenario start [s], shape (R,)."""
    ids: _IntArray
    """Satellite indices 0 .. N - 1 (the `id` column of the CLI's trajectory), shape (N,) int64."""
    hill: _FloatArray
    """States in the Hill LVLH frame, shape (R, N, 6): x, y, z [m] then vx, vy, vz [m/s] (relative to the
    rotating frame)."""
    eci: _FloatArray
    """States in EME2000, shape (R, N, 6): x, y, z [m] then vx, vy, vz [m/s]."""
    delta_v_mps: _FloatArray
    """Delta-v each satellite has spent since the start [m/s], shape (R, N)."""
    law_outputs: dict[str, _FloatArray]
    """The law's per-satellite outputs by column name (the unit in the name), each (R, N)."""

class RunResult:
    """What `satflock.run` returns (made by it, not by users): the numbers the CLI writes into a run
    directory."""

    summary: dict[str, Any]
    """The run's `summary.json` as a dict: `status`, `delta_v_mps` (`per_satellite`, `mean`, `max` [m/s]),
    `min_separation_m`, `final.five_elements` (`d_max_m`, `d_min_m`, `uniformity_l` …), `law` (the law's
    own results), `wall_time_s` … (docs/outputs.md lists every key). A value that does not exist is None."""
    status: str
    """The summary's status: `"completed"` (a run that fails raises `SimulationError`)."""
    out: Optional[pathlib.Path]
    """The run directory written (as `satflock run --out`), or None when `out` was not given."""
    metrics: dict[str, npt.NDArray[Any]]
    """The metrics table (the CLI's `metrics.csv`: one row per record, units in the column names, e.g.
    `t_s` [s], `time_utc`, `d_max_m`, `min_separation_m`, `delta_v_mean_mps`): always a dict of numpy
    arrays of shape (R,) by column, whatever is installed. NaN where a value does not exist."""
    trajectory: Optional[Trajectory]
    """Every recorded state as numpy arrays; None when the scenario writes no trajectory
    (`[output] trajectory = false`)."""
    def metrics_table(self) -> pyarrow.Table:
        """`metrics` as a `pyarrow.Table` (its `to_pandas()` needs pandas); `ImportError` without
        pyarrow."""

def run(
    scenario: Union[Scenario, str, os.PathLike[str]],
    out: Optional[Union[str, os.PathLike[str]]] = None,
    threads: Optional[int] = None,
    progress: Union[bool, Callable[[float], Any]] = True,
    law: Optional["PythonLaw"] = None,
) -> RunResult:
    """Runs a scenario to its end, as `satflock run` does (the same numbers, bit for bit).

    Args:
        scenario: a `Scenario`, a built-in name or a path to a scenario file.
        out: a run directory (new, empty or a previous run's) that gets the CLI's files (`summary.json`,
            metrics and trajectory tables, `scene.json`, `scenario.toml`); None: nothing is kept on disk.
        threads: worker threads, an int from 1 to 1024; None: one per core. The results do not depend on
            it.
        progress: True shows the percentage done on stderr (when it is a terminal); False nothing; or a
            callable receiving the simulated time [s] at each whole percent of the run. Nothing else.
        law: a guidance law written in Python run instead of the scenario's law (see `PythonLaw`);
            sampled control only.

    Raises:
        ScenarioError: the scenario is invalid, or cannot take `law`.
        SimulationError: the run failed (divergence, a Python law that raised or returned a bad array),
            with the message `satflock run` prints; with `out`, the files so far stay, marked `failed`.
        KeyboardInterrupt: Ctrl-C (the GIL is released while Rust runs): the run stops cleanly first
            (with `out`, its files are valid up to that time and `summary.json` says `interrupted`); a
            `KeyboardInterrupt` raised by a Python law's `command` is raised as it is.
        ValueError: `out` holds files that are not a previous run's, or `threads` is out of 1 to 1024.
        TypeError: `threads` is not an int or None, or `progress` not a bool or a callable.
    """

class Simulation:
    """A scenario stepped from Python: the simulation `satflock.run` builds, with the same scheduler,
    events and records, so advancing it in any number of calls gives the CLI's results bit for bit.

    State arrays are read-only copies of the current time (the engine stores each satellite as one
    struct, so a zero-copy view is not possible); removed satellites have NaN rows.
    """

    def __new__(
        cls,
        scenario: Union[Scenario, str, os.PathLike[str]],
        law: Optional["PythonLaw"] = None,
        threads: Optional[int] = None,
    ) -> "Simulation":
        """Builds the simulation at t = 0 and takes the first record (`ScenarioError` or `SimulationError`
        if the scenario or the engine refuses it). `scenario`, `law` and `threads` as in `satflock.run`."""
    def advance_to(self, t_s: float) -> None:
        """Advances to `t_s` [s] since the start (from `time_s` to `duration_s`), with the ticks, events and
        records of a whole run. The GIL is released; Ctrl-C raises `KeyboardInterrupt` and leaves the
        simulation usable at the time reached; a failure (divergence, a Python law) raises
        `SimulationError`."""
    def step(self) -> None:
        """Advances to the next control tick (the next integration step in continuous mode); nothing at the
        end."""
    def run(self) -> None:
        """Advances to `duration_s`."""
    @property
    def time_s(self) -> float:
        """Current time since the start [s]."""
    @property
    def duration_s(self) -> float:
        """The scenario's end time [s]."""
    @property
    def n_satellites(self) -> int:
        """N, the number of satellites (removed ones included)."""
    @property
    def positions_hill(self) -> _FloatArray:
        """Positions in the Hill LVLH frame [m], shape (N, 3)."""
    @property
    def velocities_hill(self) -> _FloatArray:
        """Velocities in the Hill LVLH frame (relative to the rotating frame) [m/s], shape (N, 3)."""
    @property
    def positions_eci(self) -> _FloatArray:
        """Positions in EME2000 [m], shape (N, 3)."""
    @property
    def velocities_eci(self) -> _FloatArray:
        """Velocities in EME2000 [m/s], shape (N, 3)."""
    @property
    def active(self) -> _BoolArray:
        """Whether each satellite is still in the swarm, shape (N,) bool."""
    @property
    def law_outputs(self) -> dict[str, _FloatArray]:
        """The law's per-satellite outputs now, by column name (the unit in the name), each (N,)."""
    @property
    def trajectory(self) -> Optional[Trajectory]:
        """The records so far (as `RunResult.trajectory`)."""
    @property
    def metrics(self) -> dict[str, npt.NDArray[Any]]:
        """The metrics rows recorded so far (as `RunResult.metrics`: a dict of numpy arrays)."""
    def metrics_table(self) -> pyarrow.Table:
        """The metrics rows recorded so far as a `pyarrow.Table` (`ImportError` without pyarrow)."""

# ------------------------------------------------------------------------------------------ Python law

@final
class LawContext:
    """What a Python law's `command(ctx)` receives at a control tick: the whole swarm's truth states (no
    navigation noise) and its neighbour lists. Arrays are read-only copies; row i is satellite i. A
    removed satellite keeps its row (its last state) with `active[i] == False` and no neighbours.

    Satellite i's neighbours (the live satellites within `sensing_range_m`, i excluded) are
    `neighbour_indices[neighbour_offsets[i]:neighbour_offsets[i + 1]]` (CSR).
    """

    @property
    def time_s(self) -> float:
        """Time of the tick since the start [s]."""
    @property
    def tick(self) -> int:
        """Index of the control tick, from 0."""
    @property
    def period_s(self) -> float:
        """Control period [s]: the commands are held until the next tick."""
    @property
    def n_satellites(self) -> int:
        """N, the number of satellites (removed ones included)."""
    @property
    def positions_hill(self) -> _FloatArray:
        """Positions in the Hill LVLH frame [m], shape (N, 3)."""
    @property
    def velocities_hill(self) -> _FloatArray:
        """Velocities in the Hill LVLH frame (relative to the rotating frame) [m/s], shape (N, 3)."""
    @property
    def active(self) -> _BoolArray:
        """Whether each satellite is still in the swarm, shape (N,) bool (the others' commands are ignored)."""
    @property
    def mass_kg(self) -> _FloatArray:
        """Masses [kg], shape (N,)."""
    @property
    def sensing_range_m(self) -> float:
        """Range of the sensors and links [m]."""
    @property
    def neighbour_offsets(self) -> _IntArray:
        """CSR offsets into `neighbour_indices`, shape (N + 1,) int64."""
    @property
    def neighbour_indices(self) -> _IntArray:
        """CSR neighbour indices, shape (M,) int64, ascending per satellite."""
    @property
    def mean_motion_rad_per_s(self) -> float:
        """Mean motion n of the reference orbit [rad/s] (for HCW feed-forward terms)."""

class PythonLaw(Protocol):
    """A guidance law written in Python (for type checkers only, not importable: any object with this
    method works).

    Sampled control only: `command` is called once per control tick (`[control] period_s`) for the whole
    swarm and its output held over the period. It runs under the GIL and is slower than a Rust law.
    """

    def command(self, ctx: LawContext) -> npt.ArrayLike:
        """Commanded accelerations in the Hill LVLH frame [m/s^2], shape (N, 3), finite (rows of removed
        satellites are ignored). The actuator model (saturation, failures) applies after it, and the
        delta-v ledger counts what is applied."""

# -------------------------------------------------------------------------------- metrics, propagation

def characterize(
    positions: npt.ArrayLike,
    radii: Optional[npt.ArrayLike] = None,
    velocities: Optional[npt.ArrayLike] = None,
) -> dict[str, Any]:
    """Gao et al.'s five elements of a set of points, as `satflock characterize` prints them.

    Args:
        positions: shape (N, 3), N >= 2 [m], any common Cartesian frame.
        radii: physical radii [m] (finite, >= 0), a scalar or shape (N,), for the minimum distance;
            None: points.
        velocities: shape (N, 3) [m/s], same frame; None: `v_o_mps` is left out of the result.

    Returns:
        `{"n", "r_o_m" (3,), "v_o_mps" (3,, only with velocities), "d_max_m", "diameter_m", "d_min_m",
        "uniformity_l"}`, as in `summary.json`'s `final.five_elements`. A bad input raises `ValueError`
        naming the argument.
    """

def propagate(
    states_eci: npt.ArrayLike,
    duration_s: float,
    step_s: float,
    output_step_s: Optional[float] = None,
    gravity: Literal["j2", "two-body", "point-mass"] = "j2",
    frame: Literal["eme2000", "inertial", "lvlh-hill", "lvlh-gao"] = "eme2000",
    reference: Optional[npt.ArrayLike] = None,
    threads: Optional[int] = None,
    *,
    integrator: Literal["rk78", "dop853", "rk4"] = "rk78",
    rtol: float = 1e-12,
    atol: float = 1e-6,
    mu_m3_s2: Optional[float] = None,
    earth_radius_m: Optional[float] = None,
    j2: Optional[float] = None,
    forces: Optional[Mapping[str, Any]] = None,
    epoch_utc: str = "2000-01-01T12:00:00Z",
) -> tuple[_FloatArray, _FloatArray]:
    """Propagates free orbits (no control), as `satflock propagate` does: each row alone (with the
    reference, for the LVLH frames), rows in parallel.

    Args:
        states_eci: initial EME2000 states, shape (6,) or (N, 6): x, y, z [m], vx, vy, vz [m/s].
        duration_s: length [s] (> 0).
        step_s: integration step [s] (> 0; the largest step of the adaptive integrators).
        output_step_s: output spacing [s]; outputs at k * output_step_s up to `duration_s`, and
            `duration_s` itself. None: `step_s`.
        gravity: `"j2"` (point mass + J2) or `"two-body"` (point mass; also spelled `"point-mass"`).
        frame: `"eme2000"` (also `"inertial"`), `"lvlh-hill"` (Hill LVLH of `reference`: x radial out,
            y along-track, z orbit normal) or `"lvlh-gao"` (Gao's o-xyz: x along-track, y minus orbit
            normal, z nadir). LVLH velocities are seen in the rotating frame.
        reference: EME2000 state (6,) of the reference orbit [m, m/s], propagated with the same settings;
            required by the LVLH frames, refused with `"eme2000"`.
        threads: rows propagated at once; None: one per core.
        integrator: `"rk78"` (adaptive RKF 7(8)), `"dop853"` (adaptive Dormand-Prince 8(5,3)) or `"rk4"`.
        rtol: relative tolerance of the adaptive integrators, in (0, 1).
        atol: absolute tolerance of the adaptive integrators [m, m/s] (> 0).
        mu_m3_s2: gravitational parameter [m^3/s^2]; None: WGS 84.
        earth_radius_m: equatorial radius [m]; None: WGS 84.
        j2: J2 coefficient; None: EGM96.
        forces: the force set as a dict shaped like a scenario's `[dynamics.forces]` table (or a
            `satflock propagate --forces` file): `gravity`, `drag`, `srp`, `third_body`, and the
            satellite's `satellite` properties (`mass_kg`, `drag_area_m2`, ...), e.g.
            `{"drag": {"atmosphere": "harris-priester"}, "satellite": {"mass_kg": 4.0,
            "drag_area_m2": 0.03}}`. None: `gravity` alone. Every row has the same properties.
        epoch_utc: the instant of t = 0 (ISO 8601 UTC), read by the Sun, the Moon and the
            atmosphere's diurnal bulge.

    Returns:
        `(t_s, states)`: t_s shape (R,) [s]; states shape (R, N, 6) (or (R, 6) for a (6,) input) in `frame`.

    Raises:
        ValueError: a wrong shape or a value out of range, naming the argument (and the row).
        SimulationError: the integrator failed, or an orbit fell below the atmosphere's floor.
    """

def budget(
    altitude_m: float,
    inclination_deg: float,
    separation_m: float = 1000.0,
    direction: Literal["along-track", "radial", "cross-track"] = "along-track",
    *,
    mass_kg: float,
    drag_area_m2: float,
    drag_area_2_m2: Optional[float] = None,
    drag_coefficient: float = 2.2,
    srp_area_m2: Optional[float] = None,
    srp_area_2_m2: Optional[float] = None,
    reflectivity_coefficient: float = 1.5,
    atmosphere: Literal["harris-priester", "exponential-table"] = "harris-priester",
    epoch_utc: str = "2000-01-01T12:00:00Z",
) -> dict[str, dict[str, Optional[float]]]:
    """The perturbation budget of a satellite pair on a circular orbit, as `satflock budget` prints it:
    for each term the acceleration on satellite 1, the differential acceleration between the two and the
    along-track drift it causes. Orders of magnitude for deciding which forces to neglect (method and what
    is left out: docs/dynamics.md).

    Satellite 1 is on the circular orbit (ascending node on the EME2000 x axis);
    satellite 2 on its own circular orbit `separation_m` away along the arc: the same orbit ahead
    (along-track), a coplanar orbit higher (radial), or an orbit inclined `separation_m / r` more about the
    same nodes (cross-track). Every quantity is the mean over 36 points of the orbit, the Sun and the Moon
    held at their epoch positions.

    Args:
        altitude_m: altitude of the orbit above the equatorial radius [m] (100e3 to 2000e3).
        inclination_deg: inclination [deg] (0 to 180).
        separation_m: distance between the two satellites along the arc [m] (> 0, at most 100e3).
        direction: the axis of satellite 1's Hill frame the separation is along.
        mass_kg: each satellite's mass [kg] (> 0).
        drag_area_m2: satellite 1's drag area [m^2] (>= 0).
        drag_area_2_m2: satellite 2's drag area [m^2] (>= 0); None: twice `drag_area_m2`, so that the
            differential drag (from different ballistic coefficients) shows.
        drag_coefficient: C_d of both satellites (0 to 10).
        srp_area_m2: satellite 1's area facing the Sun [m^2] (>= 0); None: its drag area.
        srp_area_2_m2: satellite 2's area facing the Sun [m^2] (>= 0); None: its drag area.
        reflectivity_coefficient: C_r of both satellites (0 to 2; SRP without shadow, always lit).
        atmosphere: `"harris-priester"` (no drag above 1000 km) or `"exponential-table"` (Vallado's static
            table).
        epoch_utc: the instant of the budget (ISO 8601 UTC): the Sun's and the Moon's positions, the
            atmosphere's diurnal bulge.

    Returns:
        term -> row, for the terms `"J2"`, `"J3"`, `"J4"`, `"J5"`, `"J6"` (each zonal harmonic alone,
        EGM96), `"drag"`, `"srp"`, `"sun"`, `"moon"` and `"hcw-linearisation"` (the exact two-body relative
        acceleration minus its HCW linearisation, for the straight-line offset). Each row:
        `"acceleration_mps2"`: orbit mean of |a| on satellite 1 [m/s^2] (None for `"hcw-linearisation"`);
        `"differential_acceleration_mps2"`: orbit mean of |a_2 - a_1| (inertial) [m/s^2];
        `"drift_per_orbit_m"`, `"drift_per_day_m"`: the secular along-track drift [m] after one orbit and
        after 86400 s, |(3/2) a_y t^2 + 2 a_x t / n| for the orbit mean of the differential acceleration
        (each satellite's own Hill frame: x radial, y along-track).

    Raises:
        ValueError: a value out of range, naming the argument and the allowed range.
    """

# ------------------------------------------------------------------------------------------- campaigns

def compare(
    case: Union[Scenario, str, os.PathLike[str]],
    laws: Sequence[Any],
    seeds: Iterable[int] = (1,),
    threads: Optional[int] = None,
) -> pyarrow.Table:
    """Runs every law on one case for every seed, as `satflock compare` does, and returns the table of
    runs (compare.parquet's columns), one row per (law, seed).

    Args:
        case: a `Scenario`, a built-in name or a TOML file's path.
        laws: controller files or `"builtin:NAME"` strings, and guidance laws written in Python (objects
            with `command(ctx)`; each run gets its own `copy.deepcopy`), in any mix; each row's `law` is the file name without extension, the
            built-in's name, or the Python law's `name` (else its class name); labels must differ.
        seeds: scenario seeds (ints >= 0), each run with every law.
        threads: rayon threads per run; None: one per core. Results do not depend on it.

    Returns:
        Text columns `law`, `controller`, `law_name`, `status`, `error`; `seed` (uint64); then every scalar
        outcome of the runs' summary.json by dotted name (float64, null where a run lacks it).
    """

def campaign(
    spec: Union[str, os.PathLike[str], Mapping[str, Any]],
    backend: Literal["local", "ray"] = "local",
    out: Optional[Union[str, os.PathLike[str]]] = None,
    jobs: Optional[int] = None,
    resume: bool = False,
    keep_runs: bool = False,
    cpus_per_run: int = 1,
    progress: bool = True,
    law: Any = None,
) -> pyarrow.Table:
    """Runs a campaign, as `satflock campaign` does (the file format: docs/campaigns.md).

    Args:
        spec: a campaign file's path, or a dict of the same keys (`scenario`, `seeds`, `set`, `vary`,
            `sampling`, `outcomes`, `keep_runs`).
        backend: `"local"`: runs in parallel on this machine; `"ray"`: each run is a Ray task on the
            cluster `ray.init()` connected to (call it first, or set `RAY_ADDRESS`).
        out: campaign directory (`manifest.jsonl`, `campaign.parquet`, `summary.md`); with the Ray backend on
            several machines it must be on a filesystem they share. None: a temporary directory, removed.
        jobs: runs at once (local backend); None: one per core.
        resume: continue a campaign in `out` from its manifest.
        keep_runs: keep each run's full outputs under `out`.
        cpus_per_run: CPUs each Ray task requests, and the threads it runs on.
        progress: a bool: show a progress line on stderr, only when stderr is a terminal.
        law: a guidance law written in Python run in place of the scenario's: an object with
            `command(ctx)` (local backend; a `copy.deepcopy` per run, one run at a time), or a
            `"module:name"` string naming a class or zero-argument factory (either backend; each Ray
            task imports the module). None: the scenario's law.

    Returns:
        The campaign table (`campaign.parquet`): one row per run, in run order, the same for both backends.
    """

