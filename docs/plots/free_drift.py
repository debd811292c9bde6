"""Plot the README picture from a `satflock run free-drift` output directory.

Usage: python3 docs/plots/free_drift.py OUT_DIR docs/free-drift.png
Reads OUT_DIR/trajectory.csv (Hill LVLH: x radial, y along-track, z orbit normal).
"""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(out_dir, png):
    tracks = defaultdict(lambda: ([], [], []))
    with open(f"{out_dir}/trajectory.csv") as f:
        for row in csv.DictReader(f):
            x, y, z = tracks[int(row["id"])]
            x.append(float(row["x_lvlh_m"]))
            y.append(float(row["y_lvlh_m"]))
            z.append(float(row["z_lvlh_m"]))
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    for x, y, z in tracks.values():
        ax1.plot(y, x, lw=0.7)
        ax1.plot(y[0], x[0], "k.", ms=3)
        ax2.plot(y, z, lw=0.7)
        ax2.plot(y[0], z[0], "k.", ms=3)
    ax1.set_xlabel("along-track y [m]")
    ax1.set_ylabel("radial x [m]")
    ax1.set_title("in-plane: released at rest, the cluster shears")
    ax2.set_xlabel("along-track y [m]")
    ax2.set_ylabel("cross-track z [m]")
    ax2.set_title("out-of-plane: bounded oscillation")
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3)
    fig.suptitle("satflock run free-drift: 50 satellites, 600 km SSO, point mass + J2, one orbit (dots: t = 0)")
    fig.tight_layout()
    fig.savefig(png, dpi=110)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
