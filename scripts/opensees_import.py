#!/usr/bin/env python3
"""Imported models against the code they came from: OpenSees builds the paper beam of 2-D
elastic beam-column elements (axial DOFs kept: no actuator touches them), exports its M, K
and DOF map, and beamflow imports them.

Checks, each against an independent reference:
  1. the imported model's eigenfrequencies against OpenSees' own eigen (<= 1e-8);
  2. the point powers of a frame actuator on the imported beam against beamflow's native beam
     on the same mesh (<= 1e-8), the stack on the transverse component uy;
  3. the same actuator standing on the other side (component -uy, the stack pushing the
     other way) puts in the same power.

    python3 scripts/opensees_import.py <beamflow binary> <work folder>

Needs openseespy (and the system BLAS/LAPACK its wheel links), numpy and scipy
(scripts/test-opensees-import.sh installs them in a virtualenv).
"""
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import openseespy.opensees as ops
import scipy.io
import scipy.sparse

L, B, H, E, RHO = 0.730, 0.050, 0.005, 210e9, 7850.0
NE = 100
A0, A1 = 5.0, 1.0e-5
# Frame: stack at node 20 (x = 0.146 m), legs 5 elements either side, stack centred.
STACK, LEFT, RIGHT = 21, 16, 26  # OpenSees node tags (1-based)
HALF_SPAN = 5 * L / NE
MODES = 8


def build():
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    h = L / NE
    for i in range(NE + 1):
        ops.node(i + 1, i * h, 0.0)
    ops.fix(1, 1, 1, 1)
    ops.fix(NE + 1, 1, 1, 1)
    ops.geomTransf("Linear", 1)
    area, inertia = B * H, B * H**3 / 12.0
    for e in range(NE):
        ops.element("elasticBeamColumn", e + 1, e + 1, e + 2, area, E, inertia, 1, "-mass", RHO * area, "-cMass")


def matrix(m, c, k):
    """The assembled m·M + c·C + k·K over OpenSees' equations."""
    ops.wipeAnalysis()
    ops.system("FullGeneral")
    ops.numberer("Plain")
    ops.constraints("Plain")
    ops.algorithm("Linear")
    ops.integrator("GimmeMCK", m, c, k)
    ops.analysis("Transient")
    ops.analyze(1, 0.0)
    n = ops.systemSize()
    return np.array(ops.printA("-ret")).reshape(n, n)


def export(folder):
    build()
    mass, stiffness = matrix(1.0, 0.0, 0.0), matrix(0.0, 0.0, 1.0)
    for name, a in (("M", mass), ("K", stiffness)):
        a = 0.5 * (a + a.T)  # FullGeneral prints the symmetric matrix; average its round-off
        scipy.io.mmwrite(str(folder / f"os_{name}.mtx"), scipy.sparse.coo_matrix(np.where(np.abs(a) > 0, a, 0.0)), symmetry="symmetric", precision=17)
    lines = ["row,node,x_m,y_m,z_m,component"]
    for tag in ops.getNodeTags():
        x, y = ops.nodeCoord(tag)
        for eq, comp in zip(ops.nodeDOFs(tag), ("ux", "uy", "rz")):
            if eq >= 0:
                lines.append(f"{eq + 1},{tag},{x!r},{y!r},0.0,{comp}")
    (folder / "os_dofs.csv").write_text("\n".join(lines) + "\n")
    ops.wipeAnalysis()
    ops.system("FullGeneral")
    lam = ops.eigen("-fullGenLapack", MODES)
    return [math.sqrt(v) / (2 * math.pi) for v in lam]


DRIVE = """[actuator.voltage]
kind = "sine"
amplitude = 12.0
frequency = 60.0
[[analysis]]
type = "steady_state"
[[analysis]]
type = "modes"
count = {modes}
"""


def run(beamflow, case, out):
    subprocess.run([beamflow, "run", str(case), "--out", str(out), "--quiet"], check=True)
    return json.loads((out / f"{case.stem}.json").read_text())


def main():
    beamflow, folder = sys.argv[1], Path(sys.argv[2])
    folder.mkdir(parents=True, exist_ok=True)
    f_os = export(folder)
    damping = f'[damping]\nkind = "rayleigh"\na0 = {A0}\na1 = {A1}\n'
    frame = f'[[actuator]]\ntype = "frame"\nname = "frame"\na = {HALF_SPAN!r}\ne = 0.0\n'
    drive = DRIVE.format(modes=MODES)
    cases = {
        "native": f"[beam]\n[beam.mesh]\nelements = {NE}\n{damping}{frame}x_e = {20 * L / NE!r}\n{drive}",
    }
    imported = f'[imported]\nmass = "os_M.mtx"\nstiffness = "os_K.mtx"\ndofs = "os_dofs.csv"\n{damping}'
    for name, comp in (("imported", "uy"), ("imported_below", "-uy")):
        cases[name] = f'{imported}{frame}node = {STACK}\ncomponent = "{comp}"\nlegs = [{LEFT}, {RIGHT}]\n{drive}'
    res = {}
    for name, text in cases.items():
        p = folder / f"{name}.toml"
        p.write_text(text)
        res[name] = run(beamflow, p, folder / f"out_{name}")
    failures = []

    def close(what, a, b, tol):
        err = abs(a - b) / max(abs(a), abs(b))
        print(f"{what:<44} {a: .12e} {b: .12e} {err:.1e}")
        if not err <= tol:
            failures.append(f"{what}: {a} against {b} ({err:.1e} > {tol})")

    modes = next(a for a in res["imported"]["analyses"] if a["type"] == "modes")
    # The imported model also has axial modes; OpenSees' lowest eight are all bending.
    for i, (f, g) in enumerate(zip(modes["frequencies_hz"], f_os)):
        close(f"mode {i + 1} (Hz): imported vs OpenSees eigen", f, g, 1e-8)
    steady = {k: next(a for a in v["analyses"] if a["type"] == "steady_state") for k, v in res.items()}
    for point, p in steady["native"]["mean_power_w"].items():
        close(f"{point} (W): imported vs native", steady["imported"]["mean_power_w"][point], p, 1e-8)
        close(f"{point} (W): -uy side vs uy side", steady["imported_below"]["mean_power_w"][point], steady["imported"]["mean_power_w"][point], 1e-10)
    if failures:
        print("\n".join(["FAILED:"] + failures))
        sys.exit(1)
    print("imported OpenSees beam: all checks hold")


if __name__ == "__main__":
    main()
