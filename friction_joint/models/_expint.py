# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Exact steps of small affine ODE systems, the core of the joint integrator.

:func:`affine2_step` solves x' = A x + b (2x2, constant) over a step exactly
(phi-functions of hA in closed form, real arithmetic);
:func:`implicit_euler_v` is the cheap L-stable predictor used before it.
"""
import math

from .._jit import njit

__all__ = ['affine2_step', 'implicit_euler_v']


@njit
def _phi_real(z: float) -> tuple[float, float]:
    """phi1(z) = (e^z - 1)/z and phi2(z) = (e^z - 1 - z)/z^2 for real z."""
    if abs(z) < 1e-2:
        return (1.0 + z * (0.5 + z * (1.0 / 6.0 + z * (1.0 / 24.0 + z / 120.0))),
                0.5 + z * (1.0 / 6.0 + z * (1.0 / 24.0 + z * (1.0 / 120.0 + z / 720.0))))
    e = math.expm1(z)
    return e / z, (e - z) / (z * z)


@njit
def _phi_cplx(x: float, y: float) -> tuple[float, float, float, float]:
    """Real and imaginary parts of phi1, phi2 at z = x + iy (|z| >= 1e-2)."""
    ex = math.exp(x)
    er = ex * math.cos(y) - 1.0
    ei = ex * math.sin(y)
    d2 = x * x + y * y
    p1r = (er * x + ei * y) / d2
    p1i = (ei * x - er * y) / d2
    nr = er - x
    ni = ei - y
    zr = x * x - y * y          # z^2 = zr + i zi, |z^2| = d2
    zi = 2.0 * x * y
    d4 = d2 * d2
    p2r = (nr * zr + ni * zi) / d4
    p2i = (ni * zr - nr * zi) / d4
    return p1r, p1i, p2r, p2i


@njit
def affine2_step(a: tuple[float, float, float, float], b: tuple[float, float],
                 x: tuple[float, float], h: float) -> tuple[float, float, float, float]:
    """
    Exact solution of x' = A x + b (2x2, constant) over h.

    ``a`` is (a11, a12, a21, a22), ``b`` (b1, b2), ``x`` the start (x1, x2).

    Returns ``(x1(h), x2(h), int_0^h x1, int_0^h x2)``.  Uses
    x(h) = x0 + h phi1(hA)(A x0 + b) and int x = h x0 + h^2 phi2(hA)(A x0 + b);
    a matrix function of a 2x2 A is c0 I + c1 A, with c0, c1 interpolating
    the scalar function at the eigenvalues (Sylvester's formula), all in real
    arithmetic.
    """
    a11, a12, a21, a22 = a
    b1, b2 = b
    x1, x2 = x
    tr = a11 + a22
    det = a11 * a22 - a12 * a21
    al = 0.5 * tr
    disc = al * al - det
    rad = math.sqrt(abs(disc))
    if h * (abs(al) + rad) < 1e-2:
        # small spectrum: Taylor series of phi1, phi2 interpolated at the
        # eigenvalues, via divided differences of z^n from sp = z1 + z2 and
        # pp = z1 z2 (no eigenvalues needed): D_n = sp D_{n-1} - pp D_{n-2},
        # c1 = sum a_n D_n, c0 = a_0 - pp sum_{n>=2} a_n D_{n-1}.
        sp = tr * h
        pp = det * h * h
        c01 = 1.0
        c02 = 0.5
        c11 = 0.5
        c12 = 1.0 / 6.0
        dm1 = 1.0          # D_1
        d0 = sp            # D_2
        f1 = 1.0 / 6.0     # a_2 of phi1 = 1/3!
        f2 = 1.0 / 24.0    # a_2 of phi2 = 1/4!
        for n in range(2, 7):
            c11 += f1 * d0
            c12 += f2 * d0
            c01 -= pp * f1 * dm1
            c02 -= pp * f2 * dm1
            dm1, d0 = d0, sp * d0 - pp * dm1
            f1 /= n + 2
            f2 /= n + 3
    elif disc < 0.0 and rad * h >= 1e-7:
        p1r, p1i, p2r, p2i = _phi_cplx(al * h, rad * h)
        c11 = p1i / (rad * h)          # (phi(z1) - phi(z2)) / (z1 - z2), z = lambda h
        c01 = p1r - c11 * al * h
        c12 = p2i / (rad * h)
        c02 = p2r - c12 * al * h
    else:
        if disc > 0.0:
            big = al + rad if al >= 0.0 else al - rad
            l1 = big
            l2 = det / big
        else:
            l1 = al
            l2 = al
        if abs(l1 - l2) * h < 1e-7:
            # (nearly) repeated large eigenvalue: split it symmetrically; the
            # interpolation error is O(split^2), far below round-off here.
            m = 0.5 * (l1 + l2)
            l1 = m + 0.5e-7 / h
            l2 = m - 0.5e-7 / h
        z1 = l1 * h
        z2 = l2 * h
        p1a, p2a = _phi_real(z1)
        p1b, p2b = _phi_real(z2)
        c11 = (p1a - p1b) / (z1 - z2)
        c01 = p1a - c11 * z1
        c12 = (p2a - p2b) / (z1 - z2)
        c02 = p2a - c12 * z1
    # phi(hA) = c0 I + c1 hA
    r1 = a11 * x1 + a12 * x2 + b1
    r2 = a21 * x1 + a22 * x2 + b2
    ar1 = h * (a11 * r1 + a12 * r2)
    ar2 = h * (a21 * r1 + a22 * r2)
    x1n = x1 + h * (c01 * r1 + c11 * ar1)
    x2n = x2 + h * (c01 * r2 + c11 * ar2)
    i1 = h * x1 + h * h * (c02 * r1 + c12 * ar1)
    i2 = h * x2 + h * h * (c02 * r2 + c12 * ar2)
    return x1n, x2n, i1, i2


@njit
def implicit_euler_v(a: tuple[float, float, float, float], b: tuple[float, float],
                     x: tuple[float, float], h: float) -> float:
    """x2 after one implicit Euler step of x' = A x + b (cheap, L-stable predictor)."""
    a11, a12, a21, a22 = a
    b1, b2 = b
    x1, x2 = x
    m11 = 1.0 - h * a11
    m12 = -h * a12
    m21 = -h * a21
    m22 = 1.0 - h * a22
    r1 = x1 + h * b1
    r2 = x2 + h * b2
    return (m11 * r2 - m21 * r1) / (m11 * m22 - m12 * m21)
