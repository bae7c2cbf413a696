"""SciPy's shift-invert Lanczos (ARPACK) on the plate bench's matrices, for comparison with
`cargo bench --bench plate -- modes`: modes 1-20 of the 100 x 80 simply supported plate.

    cargo run --release --example export_plate_matrices -- 100 80 /tmp/plate
    python3 benches/scipy_modes.py /tmp/plate [count] [repeats]

Times `scipy.sparse.linalg.eigsh(K, k=count, M=M, sigma=0)` (SuperLU factorisation of K
inside, ARPACK's implicitly restarted Lanczos) and reports the best and median of the
repeats, with the first and last frequency so the runs can be checked against beamflow's;
where SuperLU's factor does not fit in memory, how long it ran before it failed.
"""

import statistics
import sys
import time

import numpy as np
import scipy
import scipy.io
import scipy.sparse.linalg


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else "/tmp/plate"
    count = int(sys.argv[2]) if len(sys.argv) > 2 else 20
    repeats = int(sys.argv[3]) if len(sys.argv) > 3 else 5
    k = scipy.io.mmread(f"{folder}/plate_K.mtx").tocsc()
    m = scipy.io.mmread(f"{folder}/plate_M.mtx").tocsc()
    times = []
    print(f"scipy {scipy.__version__}, {k.shape[0]} DOFs, {count} modes")
    for _ in range(repeats):
        start = time.perf_counter()
        try:
            lam, _ = scipy.sparse.linalg.eigsh(k, k=count, M=m, sigma=0.0)
        except (MemoryError, SystemError) as e:
            # SuperLU's factor of K does not fit (it says "Can't expand MemType" and fails
            # with one of these): say so, with how long it took to find out.
            print(f"eigsh(sigma=0): the factorisation failed after {time.perf_counter() - start:.1f} s: {e!r}")
            sys.exit(1)
        times.append(time.perf_counter() - start)
    hz = np.sqrt(np.sort(lam)) / (2.0 * np.pi)
    print(f"eigsh(sigma=0): best {min(times):.3f} s, median {statistics.median(times):.3f} s of {repeats}")
    print(f"f_1 = {hz[0]:.6f} Hz, f_{count} = {hz[-1]:.6f} Hz")


if __name__ == "__main__":
    main()
