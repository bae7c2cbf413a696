#!/usr/bin/env python3
"""The OpenSees speed anchor, measured with OpenSeesPy on this machine.

The bare paper beam (730 x 50 x 5 mm steel, clamped at both ends) as 200 elastic beam-column
elements with consistent mass, Rayleigh damping a0 = 5.29 1/s, a1 = 9.96e-6 s, a sine point
force at the node nearest x = 0.15 m, Newmark average acceleration, the effective matrix
factorised once (Linear -factorOnce), 20,000 steps at dt = 1e-4 s, w at the load recorded
after every step. The axial DOFs are fixed, so the model has beamflow's 398 DOFs (w and
theta at the 199 free nodes).

    python3 -m venv /tmp/osp && /tmp/osp/bin/pip install openseespy==3.7.1.2
    apt-get install -y libblas3 liblapack3          # the wheel links them
    /tmp/osp/bin/python scripts/opensees_anchor.py [repeats] [w-file]

Prints the best wall time of `repeats` runs (default 5) for two ways of driving it: one
analyze(20000) call with a Node recorder (the fastest OpenSees offers), and a Python loop of
analyze(1) + nodeDisp (how a script usually reads a response). beamflow's
`cargo bench --bench scaling -- anchor` times the same work (docs/performance.md).

With a w-file, the recorded w(t) at the load (one value per step) is also written there, for
`cargo run --release --example opensees_check -- <w-file>`, which steps beamflow's model of
the same beam and compares the two responses.
"""
import math
import os
import sys
import tempfile
import time

import openseespy.opensees as ops

L, B, H = 0.730, 0.050, 0.005
E, RHO = 210e9, 7850.0
NE, DT, STEPS = 200, 1e-4, 20_000
A0, A1 = 5.29, 9.96e-6
X_LOAD, F_HZ = 0.15, 60.0


def build():
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    h = L / NE
    for i in range(NE + 1):
        ops.node(i + 1, i * h, 0.0)
        if i in (0, NE):
            ops.fix(i + 1, 1, 1, 1)
        else:
            ops.fix(i + 1, 1, 0, 0)
    ops.geomTransf("Linear", 1)
    area, inertia = B * H, B * H**3 / 12.0
    for e in range(NE):
        ops.element("elasticBeamColumn", e + 1, e + 1, e + 2, area, E, inertia, 1,
                    "-mass", RHO * area, "-cMass")
    ops.rayleigh(A0, 0.0, A1, 0.0)  # C = a0 M + a1 K_init: constant, as in beamflow
    load_node = round(X_LOAD / h) + 1
    ops.timeSeries("Trig", 1, 0.0, 1e9, 1.0 / F_HZ)
    ops.pattern("Plain", 1, 1)
    ops.load(load_node, 0.0, 1.0, 0.0)
    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system("BandSPD")
    ops.test("NormDispIncr", 1e-12, 10)
    ops.algorithm("Linear", "-factorOnce")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    return load_node


def one_call(path):
    node = build()
    ops.recorder("Node", "-file", path, "-precision", 17, "-node", node, "-dof", 2, "disp")
    t0 = time.perf_counter()
    assert ops.analyze(STEPS, DT) == 0
    t = time.perf_counter() - t0
    ops.wipe()  # closes the recorder
    return t


def python_loop():
    node = build()
    w = []
    t0 = time.perf_counter()
    for _ in range(STEPS):
        assert ops.analyze(1, DT) == 0
        w.append(ops.nodeDisp(node, 2))
    t = time.perf_counter() - t0
    return t, w


def main():
    repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 5
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "w.out")
        best_call = min(one_call(path) for _ in range(repeats))
        with open(path) as f:
            text = f.read()
        rows = len(text.splitlines())
        if len(sys.argv) > 2:
            with open(sys.argv[2], "w") as out:
                out.write(text)
    loops = [python_loop() for _ in range(repeats)]
    best_loop = min(t for t, _ in loops)
    w = loops[0][1]
    ndof = 2 * (NE - 1)
    print(f"OpenSeesPy {ops.version()}: {NE} elements, {ndof} DOFs, {STEPS} steps at dt = {DT}")
    print(f"  analyze({STEPS}) + recorder ({rows} rows): best {best_call:.3f} s "
          f"= {best_call / (STEPS * ndof) * 1e9:.0f} ns per DOF-step")
    print(f"  Python loop of analyze(1) + nodeDisp:    best {best_loop:.3f} s "
          f"= {best_loop / (STEPS * ndof) * 1e9:.0f} ns per DOF-step")
    print(f"  max |w| at the load: {max(abs(x) for x in w):.4e} m (a unit force)")


if __name__ == "__main__":
    main()
