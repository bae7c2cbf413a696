#!/usr/bin/env python3
"""An extended-precision reference for the OpenSees anchor problem.

The same discrete problem as scripts/opensees_anchor.py and examples/opensees_check.rs (200
Euler-Bernoulli elements of the 730 x 50 x 5 mm steel beam, consistent mass, clamped ends,
C = a0 M + a1 K, a unit 60 Hz sine force on the node x = 41 L / 200, Newmark average
acceleration, dt = 1e-4 s, from rest), assembled and stepped in numpy's longdouble (the x87
80-bit format: 64-bit significand, eps = 1.1e-19) with K_eff inverted once by Gauss-Jordan.
Its own round-off is ~1e-14 of the peak over 20,000 steps, far below the double-precision
codes it checks. Needs numpy (pip install numpy); about a minute for 20,000 steps.

    python scripts/newmark_reference.py OUT [steps] [increment]

writes w at the load, one value per step, to OUT. With `increment`, the same stepping in
float64 in the increment form (K_eff du = F + M(c0 dt v + a) + C v - K u), to compare forms.
"""
import sys

import numpy as np


def run(steps, dtype, increment=False):
    f = dtype
    length, width, thick = f("0.730"), f("0.050"), f("0.005")
    young, rho = f("210e9"), f("7850")
    ne = 200
    dt, a0, a1 = f("1e-4"), f("5.29"), f("9.96e-6")
    h = length / ne
    ei, ra = young * width * thick**3 / 12, rho * width * thick
    ke = ei / h**3 * np.array([[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                               [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]], dtype=dtype)
    me = ra * h / 420 * np.array([[156, 22 * h, 54, -13 * h], [22 * h, 4 * h * h, 13 * h, -3 * h * h],
                                  [54, 13 * h, 156, -22 * h], [-13 * h, -3 * h * h, -22 * h, 4 * h * h]], dtype=dtype)
    n_all = 2 * (ne + 1)
    k_mat = np.zeros((n_all, n_all), dtype=dtype)
    m_mat = np.zeros((n_all, n_all), dtype=dtype)
    for e in range(ne):
        idx = [2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3]
        k_mat[np.ix_(idx, idx)] += ke
        m_mat[np.ix_(idx, idx)] += me
    free = list(range(2, n_all - 2))  # both ends clamped
    k_mat, m_mat = k_mat[np.ix_(free, free)], m_mat[np.ix_(free, free)]
    c_mat = a0 * m_mat + a1 * k_mat
    n = len(free)
    beta, gamma = f("0.25"), f("0.5")
    c0, c1 = 1 / (beta * dt * dt), gamma / (beta * dt)
    k_eff = k_mat + c1 * c_mat + c0 * m_mat
    aug = np.concatenate([k_eff, np.eye(n, dtype=dtype)], axis=1)
    for i in range(n):  # Gauss-Jordan; K_eff is symmetric positive definite, no pivoting
        aug[i] /= aug[i, i]
        col = aug[:, i].copy()
        col[i] = 0
        aug -= np.outer(col, aug[i])
    k_inv = aug[:, n:]
    d = 2 * 41 - 2  # w of node 41 among the free DOFs
    u, v, a = (np.zeros(n, dtype=dtype) for _ in range(3))
    two_pi_f = 2 * dtype(np.pi) * 60
    w = []
    for k in range(1, steps + 1):
        load = np.zeros(n, dtype=dtype)
        load[d] = np.sin(two_pi_f * (k * dt))
        if increment:
            du = k_inv @ (load + m_mat @ (c0 * dt * v + a) + c_mat @ v - k_mat @ u)
            un = u + du
        else:
            un = k_inv @ (load + m_mat @ (c0 * (u + dt * v) + a) + c_mat @ (c1 * u + v))
        an = c0 * (un - u - dt * v) - a
        v = v + dt * (f("0.5") * a + f("0.5") * an)
        u, a = un, an
        w.append(u[d])
    return np.array(w, dtype=np.float64)


def main():
    out = sys.argv[1]
    steps = int(sys.argv[2]) if len(sys.argv) > 2 else 20_000
    increment = len(sys.argv) > 3 and sys.argv[3] == "increment"
    w = run(steps, np.float64 if increment else np.longdouble, increment)
    np.savetxt(out, w, fmt="%.17e")


if __name__ == "__main__":
    main()
