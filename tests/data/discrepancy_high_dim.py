#!/usr/bin/env python3
"""Exact high-dimension reference values for tests/quality/quality_discrepancy.rs (high_dimension_*).

Made with (Python standard library only, about a minute):
    python3 tests/data/discrepancy_high_dim.py

In a few thousand dimensions the terms of the closed forms are products of thousands of factors
(13/12, 4/3, 19/12 and 1.5 to the power d), beyond the range of f64, and scipy's
qmc.discrepancy returns inf, nan or garbage there; so the reference is exact rational
arithmetic. Every coordinate is a dyadic rational, every factor of the closed forms is an exact
Fraction, and D^2 is an exact Fraction printed to 20 significant digits with its root (Decimal,
60 digits of working precision).

Point sets (the Rust test builds the same ones): point i < n, coordinate k < d, with the
10-bit hash h = (((i * d + k + 1) * 2654435761) mod 2^32) >> 22 and
  uniform  x = (2h + 1) / 2^11          spread over (0, 1)
  corner   x = (2h + 1) / 2^17          within 1/64 of the corner 0
  centre   x = 1/2 + (2h + 1 - 1024) / 2^17   within 1/128 of the centre

Line format: method style n d squared root
"""
from decimal import Decimal, getcontext
from fractions import Fraction

getcontext().prec = 60

HALF = Fraction(1, 2)


def coordinate(style, i, k, d):
    h = (((i * d + k + 1) * 2654435761) % (1 << 32)) >> 22
    if style == "uniform":
        return Fraction(2 * h + 1, 1 << 11)
    if style == "corner":
        return Fraction(2 * h + 1, 1 << 17)
    if style == "centre":
        return HALF + Fraction(2 * h + 1 - 1024, 1 << 17)
    raise ValueError(style)


# (C, g(x), K(x, y)) of each closed form, as in src/quality/discrepancy.rs.
def cd():
    def g(x):
        a = abs(x - HALF)
        return 1 + a / 2 - a * a / 2

    def k(x, y):
        return 1 + abs(x - HALF) / 2 + abs(y - HALF) / 2 - abs(x - y) / 2

    return Fraction(13, 12), g, k


def wd():
    def k(x, y):
        t = abs(x - y)
        return Fraction(3, 2) - t + t * t

    return Fraction(4, 3), (lambda x: Fraction(4, 3)), k


def md():
    def g(x):
        a = abs(x - HALF)
        return Fraction(5, 3) - a / 4 - a * a / 4

    def k(x, y):
        t = abs(x - y)
        a, b = abs(x - HALF), abs(y - HALF)
        return Fraction(15, 8) - a / 4 - b / 4 - 3 * t / 4 + t * t / 2

    return Fraction(19, 12), g, k


def l2_star():
    return Fraction(1, 3), (lambda x: (1 - x * x) / 2), (lambda x, y: 1 - max(x, y))


FORMS = {"L2-star": l2_star, "CD": cd, "WD": wd, "MD": md}


def product(factors):
    # Exact products of many Fractions: multiply numerators and denominators, reduce once.
    num, den = 1, 1
    for f in factors:
        num *= f.numerator
        den *= f.denominator
    return Fraction(num, den)


def squared(method, style, n, d):
    c, g, k = FORMS[method]()
    x = [[coordinate(style, i, j, d) for j in range(d)] for i in range(n)]
    single = sum(product(g(v) for v in row) for row in x)
    pairs = sum(
        product(k(u, v) for u, v in zip(x[i], x[j])) * (1 if i == j else 2)
        for i in range(n)
        for j in range(i, n)
    )
    return c**d - 2 * single / n + pairs / (n * n)


CASES = [
    ("WD", "uniform", 16, 1745),
    ("MD", "uniform", 3, 1500),
    ("CD", "corner", 4, 3000),
    ("WD", "uniform", 4, 3000),
    ("CD", "centre", 4, 9000),
    ("CD", "uniform", 8, 3000),
    ("L2-star", "uniform", 5, 1000),
]

for method, style, n, d in CASES:
    exact = squared(method, style, n, d)
    value = Decimal(exact.numerator) / Decimal(exact.denominator)
    print(method, style, n, d, f"{value:.19e}", f"{value.sqrt():.19e}")
