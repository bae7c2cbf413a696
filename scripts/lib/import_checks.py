"""What the imported-model checks share (scripts/opensees_import.py, scripts/skfem_import.py):
the example plate of cases/plate-inertial.toml and Navier's closed form for it, a run of
beamflow on a case, and the list of checks that ends the script."""
import json
import math
import subprocess
import sys

# The example plate of cases/plate-inertial.toml: 0.5 x 0.4 x 3 mm aluminium (m, Pa, kg/m³).
PX, PY, PH, PE, PNU, PRHO = 0.5, 0.4, 0.003, 70e9, 0.33, 2700.0


def rigidity():
    """The plate's bending rigidity D = E·h³ / (12·(1 − ν²)) (N·m)."""
    return PE * PH**3 / (12 * (1 - PNU**2))


def navier_hz(count):
    """The simply supported plate's lowest `count` natural frequencies (Hz), closed form."""
    w = sorted(
        math.pi**2 * ((m / PX) ** 2 + (n / PY) ** 2) * math.sqrt(rigidity() / (PRHO * PH))
        for m in range(1, 8)
        for n in range(1, 8)
    )
    return [x / (2 * math.pi) for x in w[:count]]


def run(beamflow, case, out):
    """`beamflow run` of the case file `case` into `out`: its JSON summary."""
    subprocess.run([beamflow, "run", str(case), "--out", str(out), "--quiet"], check=True)
    return json.loads((out / f"{case.stem}.json").read_text())


class Checks:
    """Checks printed as a table as they are made; `finish` exits 1 naming those that
    failed. `width` is the width of the table's first column."""

    def __init__(self, width):
        self.width = width
        self.failures = []

    def close(self, what, a, b, tol):
        """a and b agree to `tol`, relative to the larger."""
        err = abs(a - b) / max(abs(a), abs(b))
        print(f"{what:<{self.width}} {a: .12e} {b: .12e} {err:.1e}")
        if not err <= tol:
            self.failures.append(f"{what}: {a} against {b} ({err:.1e} > {tol})")

    def fail(self, reason):
        self.failures.append(reason)

    def finish(self, what):
        if self.failures:
            print("\n".join(["FAILED:"] + self.failures))
            sys.exit(1)
        print(f"{what}: all checks hold")
