"""Shared by the peers: the problem's constants, the states CSV, the JSON line every peer prints."""
import csv
import json

MU = 3.986004418e14  # m^3/s^2, WGS 84 (satflock's EarthModel::WGS84_EGM96)
R_EQ = 6378137.0  # m
J2 = 1.08262668e-3
HEADER = ["sat", "x", "y", "z", "vx", "vy", "vz"]


def read_states(path):
    """(ids, rows) from a sat,x,y,z,vx,vy,vz CSV (m, m/s, EME2000)."""
    with open(path) as f:
        reader = csv.reader(f)
        assert next(reader) == HEADER
        rows = [r for r in reader]
    return [int(r[0]) for r in rows], [[float(v) for v in r[1:]] for r in rows]


def write_states(path, ids, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(HEADER)
        for i, r in zip(ids, rows):
            w.writerow([i] + [repr(float(v)) for v in r])


def report(peer, n, steps, wall_s, threads, first):
    print(json.dumps({
        "peer": peer, "n": n, "steps": steps, "wall_s": wall_s,
        "sat_steps_per_s": n * steps / wall_s, "threads": threads,
        "final_state_first_sat": [float(v) for v in first],
    }))


def steps_of(duration_s, step_s):
    """Whole steps only: the driver picks durations that are multiples of the step."""
    steps = round(duration_s / step_s)
    assert abs(steps * step_s - duration_s) < 1e-9 * duration_s, "duration must be a multiple of the step"
    return steps
