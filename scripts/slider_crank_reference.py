#!/usr/bin/env python3
"""Reference solution of the slider-crank of SUNDIALS' idaSlCrank_dns (Haug, Intermediate
Dynamics, 1992, example 6.1.8) at t = 1 s, by an independent formulation: the
minimal-coordinate ODE in the crank angle q alone, integrated by scipy's DOP853 at rtol 1e-12.

Coordinates of idaSlCrank_dns: crank angle q, slider position x, connecting-rod angle p with
the constraints x - cos p - a cos q = 0 and -sin p - a sin q = 0 (crank length a, rod length 1);
mass matrix diag(J1, m2, J2); generalised forces of a spring-damper (k, c, free length l0)
between the crank's and the rod's midpoints and a constant horizontal force f on the rod.
Here x(q) and p(q) follow from the constraints (p = asin(-a sin q), the branch of the initial
p0 = asin(-a)), and the equation of motion is (J^T M J) q'' = J^T (Q - M beta) with
J = d(q, x, p)/dq and beta the velocity terms of the dependent accelerations.

Run: python3 scripts/slider_crank_reference.py   (prints the state at t = 1 s)
"""
from math import asin, cos, sin, sqrt

from scipy.integrate import solve_ivp

A, J1, M2, J2, K, C, L0, F = 0.5, 1.0, 1.0, 2.0, 1.0, 1.0, 1.0, 1.0


def dependent(q, qd):
    """x, p, their rates, and the affine maps of their accelerations in q''."""
    p = asin(-A * sin(q))
    x = cos(p) + A * cos(q)
    alpha_p = -A * cos(q) / cos(p)
    pd = alpha_p * qd
    xd = -sin(p) * pd - A * sin(q) * qd
    beta_p = (A * sin(q) * qd**2 + sin(p) * pd**2) / cos(p)
    alpha_x = -sin(p) * alpha_p - A * sin(q)
    beta_x = -cos(p) * pd**2 - sin(p) * beta_p - A * cos(q) * qd**2
    return x, p, xd, pd, alpha_x, beta_x, alpha_p, beta_p


def forces(q, x, p, qd, xd, pd):
    """Generalised forces (Q_q, Q_x, Q_p) of idaSlCrank_dns."""
    s1, c1, s2, c2 = sin(q), cos(q), sin(p), cos(p)
    s21 = s2 * c1 - c2 * s1
    c21 = c2 * c1 + s2 * s1
    l2 = x * x - x * (c2 + A * c1) + (1.0 + A * A) / 4.0 + A * c21 / 2.0
    l = sqrt(l2)
    ld = (2.0 * x * xd - xd * (c2 + A * c1) + x * (s2 * pd + A * s1 * qd)
          - A * s21 * (pd - qd) / 2.0) / (2.0 * l)
    fl = (K * (l - L0) + C * ld) / l
    return (-fl * A * (s21 / 2.0 + x * s1) / 2.0,
            fl * (c2 / 2.0 - x + A * c1 / 2.0) + F,
            -fl * (x * s2 - A * s21 / 2.0) / 2.0 - F * s2)


def rhs(_t, s):
    q, qd = s
    x, p, xd, pd, ax, bx, ap, bp = dependent(q, qd)
    qq = forces(q, x, p, qd, xd, pd)
    jmj = J1 + M2 * ax * ax + J2 * ap * ap
    jq = qq[0] + ax * (qq[1] - M2 * bx) + ap * (qq[2] - J2 * bp)
    return [qd, jq / jmj]


def main():
    from math import pi
    sol = solve_ivp(rhs, (0.0, 1.0), [pi / 2.0, 0.0], method="DOP853",
                    rtol=1e-12, atol=1e-14)
    q, qd = sol.y[0, -1], sol.y[1, -1]
    x, p, xd, pd, *_ = dependent(q, qd)
    for name, value in [("q", q), ("x", x), ("p", p), ("qd", qd), ("xd", xd), ("pd", pd)]:
        print(f"{name:3s} = {value:.15e}")


if __name__ == "__main__":
    main()
