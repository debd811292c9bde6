"""Orekit (orekit-jpype, without orekitdata): one NumericalPropagator per satellite, classical RK4 at the step,
point mass + J2 (J2OnlyPerturbation about the EME2000 z axis, satflock's constants), Cartesian
propagation, one thread.

usage: orekit_peer.py STATES.csv DURATION_S STEP_S FINAL.csv
"""
import sys
import time

from common import J2, MU, R_EQ, read_states, report, steps_of, write_states


def main():
    states, duration_s, step_s, final = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
    import orekit_jpype
    orekit_jpype.initVM()
    # No orekit-data: `orekitdata` is not on the package index here, and EME2000, the J2000 epoch and
    # the force models used need none.
    from org.hipparchus.geometry.euclidean.threed import Vector3D
    from org.hipparchus.ode.nonstiff import ClassicalRungeKuttaIntegrator
    from org.orekit.forces.gravity import J2OnlyPerturbation
    from org.orekit.frames import FramesFactory
    from org.orekit.orbits import CartesianOrbit, OrbitType
    from org.orekit.propagation import SpacecraftState
    from org.orekit.propagation.numerical import NumericalPropagator
    from org.orekit.time import AbsoluteDate
    from org.orekit.utils import PVCoordinates

    ids, rows = read_states(states)
    steps = steps_of(duration_s, step_s)
    frame = FramesFactory.getEME2000()
    epoch = AbsoluteDate.J2000_EPOCH
    j2 = J2OnlyPerturbation(MU, R_EQ, J2, frame)
    out = []
    start = time.perf_counter()
    for r in rows:
        pv = PVCoordinates(Vector3D(r[0], r[1], r[2]), Vector3D(r[3], r[4], r[5]))
        orbit = CartesianOrbit(pv, frame, epoch, MU)
        prop = NumericalPropagator(ClassicalRungeKuttaIntegrator(step_s))
        prop.setOrbitType(OrbitType.CARTESIAN)
        prop.setMu(MU)
        prop.addForceModel(j2)
        prop.setInitialState(SpacecraftState(orbit))
        s = prop.propagate(epoch.shiftedBy(duration_s)).getPVCoordinates(frame)
        p, v = s.getPosition(), s.getVelocity()
        out.append([p.getX(), p.getY(), p.getZ(), v.getX(), v.getY(), v.getZ()])
    wall = time.perf_counter() - start
    write_states(final, ids, out)
    report("orekit", len(ids), steps, wall, 1, out[0])


if __name__ == "__main__":
    main()
