"""A tour of satflock from Python on `gao-circle` (Gao, Li & Wei 2022: 50 satellites at rest in a 100 m ball
form a 500 m ring under the bifurcating potential law): one run, its five elements over time, then the
spread of its outcomes over 20 seeds (each seed draws other initial positions).

Run it as a script:

    python python/examples/gao_circle_tour.py --plots out/tour          # figures as PNG in out/tour
    python python/examples/gao_circle_tour.py --no-plots --ray          # the campaign on Ray

or cell by cell (the `# %%` cells: VS Code, Spyder, or Jupyter through jupytext). It needs satflock
(`pip install ./python`) with numpy and pyarrow; matplotlib for the figures (without it they are skipped
with a message); ray for `--ray` (a local Ray, or the cluster that `RAY_ADDRESS` names, e.g.
`RAY_ADDRESS=ray://host:10001`). Units are SI; positions are in the Hill LVLH frame (x radial outward,
y along-track, z orbit normal) about the reference orbit, the ring's centre.
"""

# %% Settings (command-line flags; in a notebook, edit the defaults here)
import argparse
import sys
from pathlib import Path

import numpy as np

import satflock

parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
parser.add_argument("--plots", type=Path, default=Path("gao-circle-tour"), help="folder for the PNG figures")
parser.add_argument("--no-plots", action="store_true", help="draw no figures")
parser.add_argument("--seeds", type=int, default=20, help="seeds of the campaign (default 20)")
parser.add_argument(
    "--duration-s",
    type=float,
    default=None,
    help="simulated time of every run [s] (default: the built-in's 2000 s for the single run, 300 s for "
    "the campaign's runs)",
)
parser.add_argument("--ray", action="store_true", help="run the campaign on Ray instead of this machine's cores")
parser.add_argument("--jobs", type=int, default=None, help="campaign runs at once (local backend; default: one per core)")
# Known flags only: a notebook kernel passes its own arguments.
args, _ = parser.parse_known_args()

# %% One run of gao-circle
scenario = satflock.Scenario.load("gao-circle")
if args.duration_s is not None:
    scenario["duration_s"] = args.duration_s
ring_radius_m = scenario["law.radius_m"]
print(
    f"{scenario.name}: {scenario['satellites.count']} satellites, {scenario['duration_s']} s, "
    f"law {scenario['law.name']} (ring radius {ring_radius_m} m)"
)
result = satflock.run(scenario, progress=False)
summary = result.summary
trajectory = result.trajectory
print(f"status {result.status}, wall time {summary['wall_time_s']:.2f} s")
print(f"delta-v per satellite: mean {summary['delta_v_mps']['mean']:.3f} m/s, max {summary['delta_v_mps']['max']:.3f} m/s")
print(f"minimum separation: {summary['min_separation_m']:.2f} m")
final = summary["final"]["five_elements"]
print(f"final d_max {final['d_max_m']:.1f} m, d_min {final['d_min_m']:.2f} m, uniformity L {final['uniformity_l']:.4f}")
print(f"trajectory: t_s {trajectory.t_s.shape}, hill {trajectory.hill.shape} (records, satellites, x y z vx vy vz)")


# %% The five elements over time
def column(table, name):
    """A metrics column as a float array of shape (R,) (a pyarrow.Table, or a dict of numpy arrays)."""
    values = table[name]
    return np.asarray(values.to_numpy() if hasattr(values, "to_numpy") else values, dtype=float)


metrics = result.metrics
t_s = column(metrics, "t_s")
# Element 2, the centre r_o, in the Hill frame: the mean of the alive satellites' Hill positions (R, 3).
centre_hill_m = np.nanmean(trajectory.hill[:, :, :3], axis=1)

plt = None
if args.no_plots:
    print("figures: not drawn (--no-plots)")
else:
    try:
        import matplotlib

        if "ipykernel" not in sys.modules:
            matplotlib.use("Agg")  # a script draws into files only
        import matplotlib.pyplot as plt
    except ImportError:
        print("figures: matplotlib is not installed (pip install matplotlib); skipped")

if plt is not None:
    args.plots.mkdir(parents=True, exist_ok=True)
    fig, axes = plt.subplots(5, 1, sharex=True, figsize=(8, 12), constrained_layout=True)
    axes[0].plot(t_s, column(metrics, "n"))
    axes[0].set_ylabel("N (alive)")
    for k, label in enumerate(["x radial", "y along-track", "z normal"]):
        axes[1].plot(t_s, centre_hill_m[:, k], label=label)
    axes[1].set_ylabel("centre r_o,\nHill [m]")
    axes[1].legend()
    axes[2].plot(t_s, column(metrics, "d_max_m"), label="d_max (farthest from centre)")
    axes[2].plot(t_s, column(metrics, "diameter_m"), label="diameter")
    axes[2].axhline(ring_radius_m, color="grey", linestyle="--", label="ring radius")
    axes[2].set_ylabel("extent [m]")
    axes[2].legend()
    axes[3].plot(t_s, column(metrics, "d_min_m"))
    axes[3].set_ylabel("d_min, closest\npair [m]")
    axes[4].plot(t_s, column(metrics, "uniformity_l"))
    axes[4].set_ylabel("uniformity L")
    axes[4].set_xlabel("t [s]")
    fig.suptitle(f"{scenario.name}: the five elements")
    fig.savefig(args.plots / "five_elements.png", dpi=100)

    fig, ax = plt.subplots(figsize=(6, 6), constrained_layout=True)
    ax.plot(trajectory.hill[0, :, 1], trajectory.hill[0, :, 0], ".", color="grey", label="t = 0")
    ax.plot(trajectory.hill[-1, :, 1], trajectory.hill[-1, :, 0], "o", label=f"t = {trajectory.t_s[-1]:.0f} s")
    angle = np.linspace(0.0, 2.0 * np.pi, 200)
    ax.plot(ring_radius_m * np.cos(angle), ring_radius_m * np.sin(angle), "--", color="grey", label="target ring")
    ax.set_xlabel("y along-track [m]")
    ax.set_ylabel("x radial [m]")
    ax.set_aspect("equal")
    ax.legend()
    ax.set_title(f"{scenario.name} in the orbital plane (Hill LVLH)")
    fig.savefig(args.plots / "formation.png", dpi=100)
    print(f"figures: {args.plots / 'five_elements.png'}, {args.plots / 'formation.png'}")

# %% A campaign: the same case over seeds (the campaign file's keys, as a dict)
spec = {
    "description": f"gao-circle over {args.seeds} seeds",
    "scenario": "gao-circle",
    "seeds": {"count": args.seeds, "first": 1},
    "set": {"duration_s": args.duration_s if args.duration_s is not None else 300.0},
}
started_ray = False
if args.ray:
    import ray

    if not ray.is_initialized():
        ray.init()  # the cluster RAY_ADDRESS names, or a local Ray on this machine's cores
        started_ray = True
table = satflock.campaign(spec, backend="ray" if args.ray else "local", jobs=args.jobs, progress=False)
if started_ray:
    ray.shutdown()

# %% The outcome spread (numpy percentiles over the completed runs)
status = np.asarray(table["status"].to_pylist())
completed = status == "completed"
print(f"campaign ({'ray' if args.ray else 'local'}): {completed.sum()} of {len(status)} runs completed")
outcomes = {
    "delta_v_mps.mean": "mean delta-v per satellite [m/s]",
    "min_separation_m": "minimum separation [m]",
    "final.five_elements.d_max_m": "final d_max [m]",
    "final.five_elements.d_min_m": "final d_min [m]",
    "final.five_elements.uniformity_l": "final uniformity L",
    "law.shape_max_residual_m": "largest distance from the ring [m]",
}
print(f"{'outcome':<36} {'5 %':>10} {'median':>10} {'95 %':>10}")
for name, label in outcomes.items():
    values = column(table, name)[completed]
    p5, p50, p95 = np.nanpercentile(values, [5.0, 50.0, 95.0])
    print(f"{label:<36} {p5:>10.4g} {p50:>10.4g} {p95:>10.4g}")
