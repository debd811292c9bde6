"""Side-by-side propagation benchmark: satflock (`satflock bench propagate`), NumPy, and where they are
installed, Orekit (orekit-jpype) and Basilisk (bsk), on the same initial states (point mass + J2, RK4).

usage: run.py [--satflock PATH] [--n 1000 10000 100000] [--duration-s 600] [--step-s 1] [--repeat 3]
              [--threads 2] [--peers numpy orekit basilisk] [--orekit-max-n 1000] [--basilisk-max-n 1000]

Generates the initial states (a seeded spread of LEO orbits, `generate` below) into one CSV that every
peer reads, runs each peer `--repeat` times (best wall time), compares every satellite's final state
with satflock's (max position difference, m) and prints a Markdown table of sat-steps/s and the ratio
to NumPy. The peers other than satflock run on one thread.
"""
import argparse
import json
import math
import os
import random
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from common import HEADER, MU, R_EQ, read_states, write_states  # noqa: E402


def generate(path, n, seed=16):
    """A seeded spread of LEO orbits (a = R + 400..1200 km, e < 0.01, any inclination, node, anomaly)."""
    rng = random.Random(seed)
    rows = []
    for _ in range(n):
        a = R_EQ + 400e3 + 800e3 * rng.random()
        e = 0.01 * rng.random()
        i, raan, argp, nu = math.pi * rng.random(), *(2 * math.pi * rng.random() for _ in range(3))
        p = a * (1 - e * e)
        rn = p / (1 + e * math.cos(nu))
        pq = [rn * math.cos(nu), rn * math.sin(nu)]
        vq = [-math.sqrt(MU / p) * math.sin(nu), math.sqrt(MU / p) * (e + math.cos(nu))]
        cO, sO, ci, si, cw, sw = math.cos(raan), math.sin(raan), math.cos(i), math.sin(i), math.cos(argp), math.sin(argp)
        rot = [[cO * cw - sO * sw * ci, -cO * sw - sO * cw * ci],
               [sO * cw + cO * sw * ci, -sO * sw + cO * cw * ci],
               [sw * si, cw * si]]
        r = [rot[k][0] * pq[0] + rot[k][1] * pq[1] for k in range(3)]
        v = [rot[k][0] * vq[0] + rot[k][1] * vq[1] for k in range(3)]
        rows.append(r + v)
    write_states(path, range(n), rows)


def run_peer(cmd, env=None):
    out = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if out.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed: {out.stderr.strip()[-2000:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def best_of(repeat, cmd, env=None):
    runs = [run_peer(cmd, env) for _ in range(repeat)]
    return min(runs, key=lambda r: r["wall_s"])


def max_position_difference(a, b):
    _, ra = read_states(a)
    _, rb = read_states(b)
    return max(math.dist(x[:3], y[:3]) for x, y in zip(ra, rb))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--satflock", default="satflock")
    ap.add_argument("--n", type=int, nargs="+", default=[1000, 10000, 100000])
    ap.add_argument("--duration-s", type=float, default=600.0)
    ap.add_argument("--step-s", type=float, default=1.0)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--peers", nargs="+", default=["numpy", "orekit", "basilisk"])
    ap.add_argument("--orekit-max-n", type=int, default=1000)
    ap.add_argument("--basilisk-max-n", type=int, default=1000)
    args = ap.parse_args()
    one_thread = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1")
    tmp = tempfile.mkdtemp(prefix="satflock-compare-")
    lines = []
    for n in args.n:
        states = os.path.join(tmp, f"states-{n}.csv")
        generate(states, n)
        common = ["--duration-s", str(args.duration_s), "--step-s", str(args.step_s)]
        results = {}
        ref = os.path.join(tmp, f"satflock-{n}.csv")
        for threads in sorted({1, args.threads}):
            results[f"satflock ({threads} thr)"] = (best_of(args.repeat, [
                args.satflock, "bench", "propagate", "--initial-states", states, "--threads", str(threads),
                "--write-final", ref, *common]), 0.0)
        for peer in args.peers:
            if peer == "orekit" and n > args.orekit_max_n or peer == "basilisk" and n > args.basilisk_max_n:
                continue
            script = {"numpy": "numpy_rk4.py", "orekit": "orekit_peer.py", "basilisk": "basilisk_peer.py"}[peer]
            final = os.path.join(tmp, f"{peer}-{n}.csv")
            cmd = [sys.executable, os.path.join(HERE, script), states, str(args.duration_s), str(args.step_s), final]
            try:
                r = best_of(args.repeat, cmd, one_thread)
            except RuntimeError as e:
                print(f"{peer} at n={n}: {e}", file=sys.stderr)
                continue
            results[peer] = (r, max_position_difference(ref, final))
        for name, (r, diff) in results.items():
            print(json.dumps({**r, "label": name, "max_diff_m": diff}), file=sys.stderr)
        numpy_rate = results.get("numpy", (None,))[0]
        for name, (r, diff) in results.items():
            ratio = r["sat_steps_per_s"] / numpy_rate["sat_steps_per_s"] if numpy_rate else float("nan")
            lines.append(f"| {n} | {name} | {r['threads']} | {r['steps']} | {r['wall_s']:.3f} | "
                         f"{r['sat_steps_per_s'] / 1e6:.2f} M | {ratio:.2f}× | {diff:.1e} |")
    print("| N | peer | threads | steps | wall (s) | sat-steps/s | vs NumPy | max final-position diff vs satflock (m) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
