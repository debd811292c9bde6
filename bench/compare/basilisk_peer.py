"""Basilisk (bsk from PyPI): N `spacecraft.Spacecraft` objects in one task at the step rate (Basilisk's
default RK4 state integrator), Earth point-mass gravity only: the spherical-harmonics (J2) model needs a
gravity-coefficient file that the bsk wheel does not ship and fetches at run time, which this machine
cannot. The final-state difference to satflock's J2 run therefore measures J2 (kilometres), not error.

usage: basilisk_peer.py STATES.csv DURATION_S STEP_S FINAL.csv
"""
import sys
import time

from common import MU, read_states, report, steps_of, write_states


def main():
    states, duration_s, step_s, final = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
    from Basilisk.simulation import spacecraft
    from Basilisk.utilities import SimulationBaseClass, macros, simIncludeGravBody

    ids, rows = read_states(states)
    steps = steps_of(duration_s, step_s)
    sim = SimulationBaseClass.SimBaseClass()
    process = sim.CreateNewProcess("dyn")
    process.addTask(sim.CreateNewTask("task", macros.sec2nano(step_s)))
    grav = simIncludeGravBody.gravBodyFactory()
    earth = grav.createEarth()
    earth.isCentralBody = True
    earth.mu = MU
    crafts = []
    for i, r in zip(ids, rows):
        sc = spacecraft.Spacecraft()
        sc.ModelTag = f"sat{i}"
        sc.hub.r_CN_NInit = [[r[0]], [r[1]], [r[2]]]
        sc.hub.v_CN_NInit = [[r[3]], [r[4]], [r[5]]]
        grav.addBodiesTo(sc)
        sim.AddModelToTask("task", sc)
        crafts.append(sc)
    sim.InitializeSimulation()
    sim.ConfigureStopTime(macros.sec2nano(duration_s))
    start = time.perf_counter()
    sim.ExecuteSimulation()
    wall = time.perf_counter() - start
    out = []
    for sc in crafts:
        msg = sc.scStateOutMsg.read()
        out.append(list(msg.r_BN_N) + list(msg.v_BN_N))
    write_states(final, ids, out)
    report("basilisk", len(ids), steps, wall, 1, out[0])


if __name__ == "__main__":
    main()
