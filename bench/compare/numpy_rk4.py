"""NumPy RK4 of N independent satellites under point mass + J2, vectorised over N as a user writes it
(one thread: run with OMP_NUM_THREADS=1 / OPENBLAS_NUM_THREADS=1; plain ufuncs use one thread anyway).

usage: numpy_rk4.py STATES.csv DURATION_S STEP_S FINAL.csv
"""
import sys
import time

import numpy as np

from common import J2, MU, R_EQ, read_states, report, steps_of, write_states


def acceleration(r):
    x, y, z = r
    r2 = x * x + y * y + z * z
    mu_over_r3 = MU / (r2 * np.sqrt(r2))
    k = 1.5 * J2 * R_EQ * R_EQ / r2
    f = 5.0 * z * z / r2
    horizontal = -mu_over_r3 * (1.0 + k * (1.0 - f))
    vertical = -mu_over_r3 * (1.0 + k * (3.0 - f))
    return np.stack([horizontal * x, horizontal * y, vertical * z])


def main():
    states, duration_s, step_s, final = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
    ids, rows = read_states(states)
    y = np.array(rows).T.copy()  # (6, N)
    r, v = y[:3].copy(), y[3:].copy()
    steps = steps_of(duration_s, step_s)
    h = step_s
    start = time.perf_counter()
    for _ in range(steps):
        a1 = acceleration(r)
        r2, v2 = r + 0.5 * h * v, v + 0.5 * h * a1
        a2 = acceleration(r2)
        r3, v3 = r + 0.5 * h * v2, v + 0.5 * h * a2
        a3 = acceleration(r3)
        r4, v4 = r + h * v3, v + h * a3
        a4 = acceleration(r4)
        r = r + h / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4)
        v = v + h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4)
    wall = time.perf_counter() - start
    out = np.vstack([r, v]).T
    write_states(final, ids, out)
    report("numpy", len(ids), steps, wall, 1, out[0])


if __name__ == "__main__":
    main()
