"""Plots of the bifurcating-potential law (README): the gao-circle ring and the Table 4 sequence of
gao-reconfiguration, in Gao's o-xyz orbital plane (x along-track, z nadir).

Usage: satflock run gao-circle --out OUT1; satflock run gao-reconfiguration --out OUT2;
       python3 docs/plots/gao.py OUT1 OUT2 docs/
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def snapshots(out_dir, times):
    """Gao (x, z) in km of every satellite at the given times [s], from trajectory.csv (Hill frame)."""
    want = {float(t): ([], []) for t in times}
    with open(f"{out_dir}/trajectory.csv") as f:
        for row in csv.DictReader(f):
            t = float(row["t_s"])
            if t in want:
                # Gao x = Hill y (along-track), Gao z = -Hill x (nadir).
                want[t][0].append(float(row["y_lvlh_m"]) / 1e3)
                want[t][1].append(-float(row["x_lvlh_m"]) / 1e3)
    return want


def main(circle_dir, sequence_dir, docs):
    fig, ax = plt.subplots(figsize=(5, 5))
    for t, style in ((0.0, "x"), (200.0, "."), (2000.0, "o")):
        x, z = snapshots(circle_dir, [t])[t]
        ax.plot(x, z, style, label=f"t = {t:.0f} s", ms=4)
    ax.set_aspect("equal")
    ax.set_xlabel("x, along-track [km]")
    ax.set_ylabel("z, nadir [km]")
    ax.set_title("gao-circle: 50 satellites, r = 0.5 km, mu = -5 km")
    ax.legend(loc="upper right")
    fig.tight_layout()
    fig.savefig(f"{docs}/gao-circle.png", dpi=110)

    stages = [(3000.0, "disk (Table 5 t = 1000 s)"), (4000.0, "circle"), (5000.0, "line"),
              (6000.0, "double line"), (7000.0, "ellipse"), (8000.0, "double circle")]
    snaps = snapshots(sequence_dir, [t for t, _ in stages])
    fig, axes = plt.subplots(2, 3, figsize=(11, 7), sharex=True, sharey=True)
    for ax, (t, label) in zip(axes.flat, stages):
        x, z = snaps[t]
        ax.plot(x, z, "o", ms=3)
        ax.set_title(f"{label}, t = {t:.0f} s", fontsize=9)
        ax.set_aspect("equal")
        ax.grid(alpha=0.3)
    for ax in axes[1]:
        ax.set_xlabel("x, along-track [km]")
    for ax in axes[:, 0]:
        ax.set_ylabel("z, nadir [km]")
    fig.suptitle("gao-reconfiguration (Table 4): end of each stage, seed 1")
    fig.tight_layout()
    fig.savefig(f"{docs}/gao-reconfiguration.png", dpi=110)


if __name__ == "__main__":
    main(*sys.argv[1:4])
