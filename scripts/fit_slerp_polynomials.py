#!/usr/bin/env python3
"""The polynomial coefficients of float slerp's angles (include/dq/interp/rotation.hpp:
sin_to_quarter_turn and chord_angle), fitted in 40-digit arithmetic, and their relative errors.

Each fit is a least-squares polynomial in u = x² at 300 Chebyshev nodes of the range (near the
minimax polynomial of that degree):
  sin x = x + x³ q(x²),   |x| ≤ π/2,        q of degree 4;
  asin x = x + x³ p(x²),  0 ≤ x ≤ sin(π/8), p of degree 4 (rotation.hpp scales it by powers of 4
                                                            for the chord form 2 asin(z/2)).
Run: /usr/bin/python3 scripts/fit_slerp_polynomials.py   (needs python3-mpmath)
"""
import mpmath as mp

mp.mp.dps = 40
NODES = 300


def fit(f, hi, degree):
    """Coefficients c0..c_degree of the least-squares fit of f(u) on [0, hi] at Chebyshev nodes."""
    us = [hi * (1 + mp.cos(mp.pi * (2 * i + 1) / (2 * NODES))) / 2 for i in range(NODES)]
    a = mp.matrix([[u ** j for j in range(degree + 1)] for u in us])
    b = mp.matrix([f(u) for u in us])
    c = mp.lu_solve(a.T * a, a.T * b)
    return [float(c[j]) for j in range(degree + 1)]


def max_relative_error(exact, coefficients, hi, samples=4000):
    """Over (0, hi], in double (by Horner's rule on the unscaled polynomial; the C++ uses Estrin's
    scheme and, for the chord form, coefficients scaled by powers of 4: the same values to a few
    double roundings), against 40 digits. tests/test_interp.cpp checks the C++ functions themselves."""
    worst = 0.0
    for i in range(1, samples + 1):
        x = float(hi) * i / samples
        u = x * x
        p = 0.0
        for c in reversed(coefficients):
            p = p * u + c
        worst = max(worst, abs((x + x * u * p) - exact(x)) / abs(exact(x)))
    return worst


def main():
    # (f(x) − x)/x³ as a function of u = x², with its limit at 0.
    def quotient(f, limit):
        return lambda u: (f(mp.sqrt(u)) - mp.sqrt(u)) / (u * mp.sqrt(u)) if u > 0 else mp.mpf(limit)

    half_pi, eighth = mp.pi / 2, mp.sin(mp.pi / 8)
    # The ranges are widened by 1e-4 relative: rounding may put an argument just past the end.
    q = fit(quotient(mp.sin, -mp.mpf(1) / 6), half_pi ** 2 * mp.mpf("1.0001"), 4)
    p = fit(quotient(mp.asin, mp.mpf(1) / 6), eighth ** 2 * mp.mpf("1.0001"), 4)
    print("sin_to_quarter_turn q:", ", ".join(repr(c) for c in q))
    print("  max relative error: %.2e" % max_relative_error(lambda x: float(mp.sin(x)), q, half_pi))
    print("chord_angle p (before scaling by 1/4, 1/16, 1/64, 1/256, 1/1024):", ", ".join(repr(c) for c in p))
    print("  max relative error: %.2e" % max_relative_error(lambda x: float(mp.asin(x)), p, eighth))


if __name__ == "__main__":
    main()
