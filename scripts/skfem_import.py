#!/usr/bin/env python3
"""Imported models from a second source: scikit-fem assembles a simply supported thin
Kirchhoff plate of Morley triangles, exports its M, K and DOF map, and beamflow imports them.

The plate is the example plate of cases/plate-inertial.toml (0.5 x 0.4 x 3 mm aluminium),
on a structured mesh of nx x ny rectangles, each cut into two triangles. Stiffness from the
plate bending form D·[(1-ν)·w_,ij v_,ij + ν·Δw Δv], consistent mass ρh·w·v. The Morley
element's DOFs are the deflection at each vertex (component `uz`) and the slope along each
edge's normal at the edge's midpoint (component `w_n`, a node of its own at the midpoint).
The simply supported edges' vertex deflections are removed with scikit-fem's `condense`,
as a scikit-fem user applies Dirichlet conditions: the exported matrices are the condensed
ones and the DOF map names their rows.

Checks, each against an independent reference:
  1. the imported plate's eigenfrequencies against scikit-fem's own (scipy's eigsh on the
     same M, K; <= 1e-8);
  2. against Navier's closed form: the Morley element converges as O(h²), so its difference
     on the mesh twice as fine must be about a quarter (SHRINK says how close, and why);
  3. the steady-state power of an inertial actuator (no hysteresis: a linear system) on an
     interior vertex against the native [plate] at the same point (Bogner–Fox–Schmit, whose
     own difference to Navier is 4.5e-7, far below Morley's). The difference is Morley's
     discretisation difference, so it must shrink on the finer mesh as the nearest
     eigenfrequency's difference does: the two factors within 1/8 of each other (the
     half-width of SHRINK about 4). Measured: -5.1 % and -1.3 % in power, -0.91 % and
     -0.23 % in the first eigenfrequency, 4.1x against 3.9x.

    python3 scripts/skfem_import.py <beamflow binary> <work folder>

Needs scikit-fem, numpy and scipy (scripts/test-skfem-import.sh installs them in a
virtualenv).
"""
import math
import sys
from pathlib import Path

import numpy as np
import scipy.io
import scipy.sparse.linalg
from skfem import Basis, BilinearForm, ElementTriMorley, MeshTri, asm, condense
from skfem.helpers import dd, ddot, trace

sys.path.insert(0, str(Path(__file__).resolve().parent / "lib"))
from import_checks import PE, PH, PNU, PRHO, PX, PY, Checks, navier_hz, rigidity, run  # noqa: E402

MESHES = ((20, 16), (40, 32))  # a mesh and the one twice as fine
# A difference that is O(h²) shrinks 4x on the mesh twice as fine; the convergence study of
# the first six eigenfrequencies (10 x 8 to 80 x 64) gives 3.0-3.8x from 10 x 8, 3.66-3.94x
# from 20 x 16 and 3.90-3.98x from 40 x 32. The band holds those from 20 x 16 on and refuses
# any other order (O(h) shrinks 2x, O(h⁴) 16x).
SHRINK = (3.5, 4.5)
MODES = 6
DRIVE_AT = (0.15, 0.25)  # a vertex of both meshes, off the nodal lines of modes 2 and 3
DRIVE_HZ = 83.0  # between the first (75.2 Hz) and second (163.3 Hz) modes


@BilinearForm
def bending(u, v, w):
    return rigidity() * ((1 - PNU) * ddot(dd(u), dd(v)) + PNU * trace(dd(u)) * trace(dd(v)))


@BilinearForm
def inertia(u, v, w):
    return PRHO * PH * u * v


def export(folder, stem, nx, ny):
    """Writes the plate's condensed M, K and DOF map as `stem`_M.mtx, _K.mtx, _dofs.csv;
    returns scikit-fem's lowest eigenfrequencies (Hz) and the node id of the vertex at DRIVE_AT."""
    mesh = MeshTri.init_tensor(np.linspace(0, PX, nx + 1), np.linspace(0, PY, ny + 1))
    basis = Basis(mesh, ElementTriMorley(), intorder=4)
    stiffness, mass = asm(bending, basis), asm(inertia, basis)
    held = basis.get_dofs().all("u")  # the boundary vertices' deflections: simply supported
    k, m, _, kept = condense(stiffness, mass, D=held)
    for name, a in (("M", m), ("K", k)):
        a = 0.5 * (a + a.T)  # symmetric to the last bit, as Matrix Market's symmetric storage keeps it
        scipy.io.mmwrite(str(folder / f"{stem}_{name}.mtx"), a.tocoo(), symmetry="symmetric", precision=17)
    # Each global DOF's node and component: vertex v is node v + 1 (`uz`), edge f the node
    # n_vertices + f + 1 at the edge's midpoint (`w_n`).
    node, xy, component = {}, {}, {}
    for v in range(mesh.nvertices):
        node[basis.nodal_dofs[0, v]], xy[basis.nodal_dofs[0, v]] = v + 1, mesh.p[:, v]
        component[basis.nodal_dofs[0, v]] = "uz"
    for f in range(mesh.nfacets):
        node[basis.facet_dofs[0, f]] = mesh.nvertices + f + 1
        xy[basis.facet_dofs[0, f]] = mesh.p[:, mesh.facets[:, f]].mean(axis=1)
        component[basis.facet_dofs[0, f]] = "w_n"
    lines = ["row,node,x_m,y_m,z_m,component"]
    for row, dof in enumerate(kept):
        x, y = xy[dof]
        lines.append(f"{row + 1},{node[dof]},{float(x)!r},{float(y)!r},0.0,{component[dof]}")
    (folder / f"{stem}_dofs.csv").write_text("\n".join(lines) + "\n")
    lam = scipy.sparse.linalg.eigsh(k, k=MODES, M=m, sigma=0.0, which="LM", return_eigenvectors=False)
    vertex = int(np.argmin(np.hypot(mesh.p[0] - DRIVE_AT[0], mesh.p[1] - DRIVE_AT[1])))
    assert np.allclose(mesh.p[:, vertex], DRIVE_AT), "the drive point is not a vertex"
    return [math.sqrt(v) / (2 * math.pi) for v in sorted(lam)], vertex + 1


SHAKER = f"""[damping]
kind = "rayleigh_ratio"
zeta = 0.01
modes = [1, 3]
[[actuator]]
type = "inertial"
name = "shaker"
{{point}}
[actuator.stack]
hysteresis = false
[actuator.voltage]
kind = "sine"
amplitude = 12.0
frequency = {DRIVE_HZ}
[[analysis]]
type = "steady_state"
[[analysis]]
type = "modes"
count = {MODES}
"""


def native():
    return (
        f"[plate]\nlength_x = {PX}\nlength_y = {PY}\nthickness = {PH}\nyoungs_modulus = {PE!r}\n"
        f"poisson_ratio = {PNU}\ndensity = {PRHO}\n[plate.mesh]\nelements = [20, 16]\n"
        '[plate.edges]\nx0 = "simply_supported"\nx1 = "simply_supported"\n'
        'y0 = "simply_supported"\ny1 = "simply_supported"\n'
        + SHAKER.format(point=f"at = [{DRIVE_AT[0]}, {DRIVE_AT[1]}]")
    )


def run_shaker(beamflow, folder, name, text):
    case = folder / f"{name}.toml"
    case.write_text(text)
    res = run(beamflow, case, folder / f"out_{name}")
    get = lambda kind: next(a for a in res["analyses"] if a["type"] == kind)
    return get("modes")["frequencies_hz"], get("steady_state")["mean_power_w"]["shaker_stack"]


def main():
    beamflow, folder = sys.argv[1], Path(sys.argv[2])
    folder.mkdir(parents=True, exist_ok=True)
    checks = Checks(48)

    def shrinks(what, coarse, fine):
        ratio = coarse / fine
        print(f"{what:<72} shrinks {ratio:.2f}x")
        if not SHRINK[0] <= ratio <= SHRINK[1]:
            checks.fail(f"{what}: shrinks {ratio:.2f}x on the finer mesh, not ~4x")
        return ratio

    navier = navier_hz(MODES)
    f_native, p_native = run_shaker(beamflow, folder, "native", native())
    r = min(range(MODES), key=lambda i: abs(f_native[i] - DRIVE_HZ))  # the nearest mode
    freq, power = [], []
    for nx, ny in MESHES:
        stem = f"morley{nx}x{ny}"
        f_skfem, vertex = export(folder, stem, nx, ny)
        point = f'node = {vertex}\ncomponent = "uz"'
        imported = f'[imported]\nmass = "{stem}_M.mtx"\nstiffness = "{stem}_K.mtx"\ndofs = "{stem}_dofs.csv"\n'
        f, p = run_shaker(beamflow, folder, stem, imported + SHAKER.format(point=point))
        for i, (a, b) in enumerate(zip(f, f_skfem)):
            checks.close(f"{stem} mode {i + 1} (Hz): imported vs eigsh", a, b, 1e-8)
        freq.append(f)
        power.append(p)
    # Navier's closed form: Morley's difference is O(h²).
    for i, n in enumerate(navier):
        (a, b) = (freq[0][i], freq[1][i])
        shrinks(f"mode {i + 1}: Navier {n:8.3f} Hz, Morley {a:8.3f} ({a / n - 1:+.3%}) -> {b:8.3f} ({b / n - 1:+.3%})", a - n, b - n)
    print(f"native [plate] mode {r + 1}: {f_native[r]:.6f} Hz ({f_native[r] / navier[r] - 1:+.1e} from Navier's)")
    # The shaker's power against the native plate's: the difference is Morley's
    # discretisation difference, shrinking with the nearest eigenfrequency's difference.
    dp = [p / p_native - 1 for p in power]
    df = [f[r] / f_native[r] - 1 for f in freq]
    for (nx, ny), a, b in zip(MESHES, dp, df):
        print(f"shaker at {DRIVE_HZ} Hz on {nx}x{ny}: power {a:+.3%} from the native plate's, mode {r + 1} {b:+.3%} ({a / b:.2f} x)")
    ratio_p = shrinks(f"shaker's power difference to the native plate ({p_native:.6e} W)", dp[0], dp[1])
    ratio_f = df[0] / df[1]
    print(f"{'... against the nearest eigenfrequency difference':<72} shrinks {ratio_f:.2f}x")
    if not abs(ratio_p / ratio_f - 1) <= SHRINK[1] / 4 - 1:
        checks.fail(f"the power difference shrinks {ratio_p:.2f}x, the eigenfrequency difference {ratio_f:.2f}x")
    checks.finish("imported scikit-fem plate")


if __name__ == "__main__":
    main()
