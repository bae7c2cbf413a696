#!/usr/bin/env python3
"""Imported models against the code they came from: OpenSees builds the paper beam of 2-D
elastic beam-column elements (axial DOFs kept: no actuator touches them), exports its M, K
and DOF map, and beamflow imports them.

Checks, each against an independent reference:
  1. the imported model's eigenfrequencies against OpenSees' own eigen (<= 1e-8);
  2. the point powers of a frame actuator on the imported beam against beamflow's native beam
     on the same mesh (<= 1e-8), the stack on the transverse component uy;
  3. the same actuator standing on the other side (component -uy, the stack pushing the
     other way) puts in the same power;
  4. a plane portal frame (two fixed columns, a beam across) of the same elements: its
     modes against OpenSees' eigen (<= 1e-8) and a frame actuator on its beam whose run
     balances its energy;
  5. a simply supported plate of ShellMITC4 elements, whose lumped mass has no rotary
     inertia (a singular M): its modes against OpenSees' eigen (<= 1e-8) and against Navier's
     closed form (the MITC4 discretisation's difference: 0.3–3.3 % on 20 x 16, bounded by 5 %), and an
     inertial actuator on it whose run balances its energy.

    python3 scripts/opensees_import.py <beamflow binary> <work folder>
    python3 scripts/opensees_import.py --portal cases/portal-frame   # the portal's files alone

Needs openseespy (and the system BLAS/LAPACK its wheel links), numpy and scipy
(scripts/test-opensees-import.sh installs them in a virtualenv).
"""
import math
import sys
from pathlib import Path

import numpy as np
import openseespy.opensees as ops
import scipy.io
import scipy.sparse

sys.path.insert(0, str(Path(__file__).resolve().parent / "lib"))
from import_checks import PE, PH, PNU, PRHO, PX, PY, Checks, navier_hz, run  # noqa: E402

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


# The shell plate: the example plate (import_checks), 20 x 16 MITC4 elements, simply supported.
NX, NY = 20, 16
PLATE_MODES = 6


def build_shell():
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    tag = lambda i, j: j * (NX + 1) + i + 1
    for j in range(NY + 1):
        for i in range(NX + 1):
            ops.node(tag(i, j), i * PX / NX, j * PY / NY, 0.0)
            if i in (0, NX) or j in (0, NY):
                ops.fix(tag(i, j), 1, 1, 1, 0, 0, 0)  # w = 0 and the membrane held: simply supported
    ops.section("ElasticMembranePlateSection", 1, PE, PNU, PH, PRHO)
    for j in range(NY):
        for i in range(NX):
            ops.element("ShellMITC4", j * NX + i + 1, tag(i, j), tag(i + 1, j), tag(i + 1, j + 1), tag(i, j + 1), 1)
    return tag


# The portal: 1.0 m steel columns, a 1.5 m beam, 40 x 10 mm sections; 20 elements per member.
PORTAL_H, PORTAL_W, PORTAL_N = 1.0, 1.5, 20


def build_portal():
    """Returns the node tag at a fraction of the beam's span."""
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    area, inertia = 0.040 * 0.010, 0.040 * 0.010**3 / 12.0
    ops.geomTransf("Linear", 1)
    tags = {}

    def node(x, y):
        key = (round(x, 12), round(y, 12))
        if key not in tags:
            tags[key] = len(tags) + 1
            ops.node(tags[key], x, y)
        return tags[key]

    members = [((0, 0), (0, PORTAL_H)), ((0, PORTAL_H), (PORTAL_W, PORTAL_H)), ((PORTAL_W, PORTAL_H), (PORTAL_W, 0))]
    e = 0
    for (x0, y0), (x1, y1) in members:
        for i in range(PORTAL_N):
            a = node(x0 + (x1 - x0) * i / PORTAL_N, y0 + (y1 - y0) * i / PORTAL_N)
            b = node(x0 + (x1 - x0) * (i + 1) / PORTAL_N, y0 + (y1 - y0) * (i + 1) / PORTAL_N)
            e += 1
            ops.element("elasticBeamColumn", e, a, b, area, E, inertia, 1, "-mass", RHO * area, "-cMass")
    ops.fix(node(0, 0), 1, 1, 1)
    ops.fix(node(PORTAL_W, 0), 1, 1, 1)
    return lambda frac: node(PORTAL_W * frac, PORTAL_H)


def matrix(m, c, k):
    """The assembled m·M + c·C + k·K over OpenSees' equations. analyze(1) also tries to
    solve with it, and OpenSees warns when that matrix is singular (a mass matrix without
    rotary inertia); printA returns the matrix as assembled all the same."""
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


def export(folder, stem, components, modes):
    """Writes the built model's M, K and DOF map as `stem`_M.mtx, _K.mtx, _dofs.csv; returns
    OpenSees' own lowest `modes` eigenfrequencies (Hz)."""
    mass, stiffness = matrix(1.0, 0.0, 0.0), matrix(0.0, 0.0, 1.0)
    for name, a in (("M", mass), ("K", stiffness)):
        a = 0.5 * (a + a.T)  # FullGeneral prints the symmetric matrix; average its round-off
        scipy.io.mmwrite(str(folder / f"{stem}_{name}.mtx"), scipy.sparse.coo_matrix(a), symmetry="symmetric", precision=17)
    lines = ["row,node,x_m,y_m,z_m,component"]
    for tag in ops.getNodeTags():
        xyz = list(ops.nodeCoord(tag)) + [0.0] * (3 - len(ops.nodeCoord(tag)))
        for eq, comp in zip(ops.nodeDOFs(tag), components):
            if eq >= 0:
                lines.append(f"{eq + 1},{tag},{xyz[0]!r},{xyz[1]!r},{xyz[2]!r},{comp}")
    (folder / f"{stem}_dofs.csv").write_text("\n".join(lines) + "\n")
    ops.wipeAnalysis()
    ops.system("FullGeneral")
    lam = ops.eigen("-fullGenLapack", modes)
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


def export_portal(folder):
    """Writes the portal frame's M, K and DOF map alone (the files cases/portal-frame/ ships)."""
    folder.mkdir(parents=True, exist_ok=True)
    build_portal()
    export(folder, "portal", ("ux", "uy", "rz"), MODES)


def main():
    if sys.argv[1] == "--portal":
        export_portal(Path(sys.argv[2]))
        return
    beamflow, folder = sys.argv[1], Path(sys.argv[2])
    folder.mkdir(parents=True, exist_ok=True)
    build()
    f_os = export(folder, "os", ("ux", "uy", "rz"), MODES)
    beam_node = build_portal()
    f_portal = export(folder, "portal", ("ux", "uy", "rz"), MODES)
    portal_nodes = [beam_node(f) for f in (0.3, 0.25, 0.35)]
    tag = build_shell()
    f_shell = export(folder, "shell", ("ux", "uy", "uz", "rx", "ry", "rz"), PLATE_MODES)
    damping = f'[damping]\nkind = "rayleigh"\na0 = {A0}\na1 = {A1}\n'
    frame = f'[[actuator]]\ntype = "frame"\nname = "frame"\na = {HALF_SPAN!r}\ne = 0.0\n'
    drive = DRIVE.format(modes=MODES)
    cases = {
        "native": f"[beam]\n[beam.mesh]\nelements = {NE}\n{damping}{frame}x_e = {20 * L / NE!r}\n{drive}",
    }
    imported = f'[imported]\nmass = "os_M.mtx"\nstiffness = "os_K.mtx"\ndofs = "os_dofs.csv"\n{damping}'
    for name, comp in (("imported", "uy"), ("imported_below", "-uy")):
        cases[name] = f'{imported}{frame}node = {STACK}\ncomponent = "{comp}"\nlegs = [{LEFT}, {RIGHT}]\n{drive}'
    s_node, l_node, r_node = portal_nodes
    cases["portal"] = (
        f'[imported]\nmass = "portal_M.mtx"\nstiffness = "portal_K.mtx"\ndofs = "portal_dofs.csv"\n{damping}'
        f'[[actuator]]\ntype = "frame"\nname = "frame"\na = {0.05 * PORTAL_W!r}\ne = 0.0\n'
        f'node = {s_node}\ncomponent = "uy"\nlegs = [{l_node}, {r_node}]\n{drive}'
    )
    cases["shell"] = (
        f'[imported]\nmass = "shell_M.mtx"\nstiffness = "shell_K.mtx"\ndofs = "shell_dofs.csv"\n'
        f'[damping]\nkind = "rayleigh_ratio"\nzeta = 0.01\nmodes = [1, 3]\n'
        f'[[actuator]]\ntype = "inertial"\nname = "shaker"\nnode = {tag(6, 9)}\ncomponent = "uz"\n'
        + DRIVE.format(modes=PLATE_MODES).replace("60.0", "83.0")
    )
    res = {}
    for name, text in cases.items():
        p = folder / f"{name}.toml"
        p.write_text(text)
        res[name] = run(beamflow, p, folder / f"out_{name}")
    checks = Checks(44)
    close = checks.close

    modes = next(a for a in res["imported"]["analyses"] if a["type"] == "modes")
    # The imported model also has axial modes; OpenSees' lowest eight are all bending.
    for i, (f, g) in enumerate(zip(modes["frequencies_hz"], f_os)):
        close(f"mode {i + 1} (Hz): imported vs OpenSees eigen", f, g, 1e-8)
    steady = {k: next(a for a in v["analyses"] if a["type"] == "steady_state") for k, v in res.items()}
    for point, p in steady["native"]["mean_power_w"].items():
        close(f"{point} (W): imported vs native", steady["imported"]["mean_power_w"][point], p, 1e-8)
        close(f"{point} (W): -uy side vs uy side", steady["imported_below"]["mean_power_w"][point], steady["imported"]["mean_power_w"][point], 1e-10)
    portal = next(a for a in res["portal"]["analyses"] if a["type"] == "modes")["frequencies_hz"]
    for i, (f, g) in enumerate(zip(portal, f_portal)):
        close(f"portal mode {i + 1} (Hz): imported vs OpenSees eigen", f, g, 1e-8)
    for name in ("portal",):
        balance = steady[name]["energy_balance_rel_error"]
        print(f"{name + ' steady state: energy balance':<44} {balance:.1e}")
        if not balance <= 1e-8:
            checks.fail(f"{name} steady state: energy balance {balance}")
    shell = next(a for a in res["shell"]["analyses"] if a["type"] == "modes")["frequencies_hz"]
    for i, (f, g, n) in enumerate(zip(shell, f_shell, navier_hz(PLATE_MODES))):
        close(f"shell mode {i + 1} (Hz): imported vs OpenSees eigen", f, g, 1e-8)
        close(f"shell mode {i + 1} (Hz): MITC4 vs Navier", f, n, 5e-2)
    balance = steady["shell"]["energy_balance_rel_error"]
    print(f"{'shell steady state: energy balance':<44} {balance:.1e}")
    if not balance <= 1e-8:
        checks.fail(f"shell steady state: energy balance {balance}")
    checks.finish("imported OpenSees beam")


if __name__ == "__main__":
    main()
