"""One placement evaluation on the 20 x 16 plate: SciPy's sparse direct solve per harmonic
beside beamflow's evaluation on the study's shared modal reduction, in one run.

    cargo build --release --examples
    python3 benches/scipy_placement.py [repeats]

SciPy's side is the least an evaluation on the full model must do: the plate's dynamic
stiffness K - w^2 M + i w C (Rayleigh C = a0 M + a1 K, the shipped cases' calibration)
factorised and solved by SuperLU (`scipy.sparse.linalg.spsolve`) at the five odd harmonics
of 83 Hz that a 9-harmonic steady state solves, for one unit point force. It leaves out
the actuator's own equations, the stack force and the powers, so the ratio printed
understates what a full-model evaluation in SciPy would cost. beamflow's side is
`examples/placement_evaluation.rs`: whole candidates of an optimisation (case built,
coupled actuator with hysteresis, steady state, powers, constraints) on the reduction.
"""

import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
import scipy
import scipy.io
import scipy.sparse.linalg

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXAMPLES = os.path.join(ROOT, "target", "release", "examples")
A0, A1 = 6.983, 11.05e-6
F0, HARMONICS = 83.0, (1, 3, 5, 7, 9)


def scipy_evaluation_ms(folder, repeats):
    k = scipy.io.mmread(os.path.join(folder, "plate_K.mtx")).tocsc()
    m = scipy.io.mmread(os.path.join(folder, "plate_M.mtx")).tocsc()
    c = A0 * m + A1 * k
    f = np.zeros(k.shape[0], dtype=complex)
    f[k.shape[0] // 2 - (k.shape[0] // 2) % 4] = 1.0  # a w DOF near the middle
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        for h in HARMONICS:
            w = 2 * np.pi * F0 * h
            scipy.sparse.linalg.spsolve((k - w * w * m + 1j * w * c).tocsc(), f)
        times.append((time.perf_counter() - start) * 1e3)
    return statistics.median(times), k.shape[0]


def main():
    repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 50
    with tempfile.TemporaryDirectory() as folder:
        subprocess.run([os.path.join(EXAMPLES, "export_plate_matrices"), "20", "16", folder], check=True,
                       stdout=subprocess.DEVNULL)
        ms, n = scipy_evaluation_ms(folder, repeats)
    out = subprocess.run([os.path.join(EXAMPLES, "placement_evaluation"), str(4 * repeats)], check=True,
                         capture_output=True, text=True).stdout
    ours = [float(x) for x in re.findall(r"([0-9.]+) ms per evaluation", out)]
    print(f"SciPy {scipy.__version__}, {n} DOFs: {ms:.2f} ms per evaluation (5 complex sparse solves, median)")
    print(out.strip())
    for label, t in zip(("two frames", "one inertial actuator"), ours):
        print(f"{label}: {ms / t:.1f}x faster than SciPy's full-model solve")


if __name__ == "__main__":
    main()
