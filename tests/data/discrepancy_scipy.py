#!/usr/bin/env python3
"""Reference values for tests/quality/quality_discrepancy.rs: scipy's discrepancies and exact ones.

Made with:
    python3 tests/data/discrepancy_scipy.py > tests/data/discrepancy_scipy.txt
(scipy and numpy versions are written into the output's header.)

For every point set and every method it writes scipy.stats.qmc.discrepancy(sample, method=M)
next to the exact value of the same quantity. The exact value is computed in integer arithmetic:
every f64 is a dyadic rational, so after scaling all coordinates by a common power of two S the
closed forms (Warnock 1972; Hickernell 1998; Zhou, Fang & Ning 2013) are ratios of integers, and
the result is a Fraction rounded once to the nearest f64. scipy sums the O(N^2) pair terms
naively in f64 and subtracts numbers of size C^d (C = 13/12, 4/3, 19/12) to get a result that can
be far smaller, so its own rounding error is recorded too (it reaches 1e-9 relative for 1024
Sobol' points in 5 dimensions).

Forms, exactly as scipy returns them: 'L2-star' is the square root (Warnock's T_N), 'CD', 'WD'
and 'MD' are squares. Method 'star' (not in scipy) is the star discrepancy D*_N of 2-D sets,
by brute force over the grid of coordinates in exact arithmetic; its scipy column is '-'.

Every point set can be rebuilt exactly by the Rust test from its generator field:
  splitmix:SEED       row-major draws of splitmix64 from state SEED, x = (z >> 11) * 2^-53
  lattice:G1,G2,...   rank-1 lattice, x_ik = ((i * G_k) mod n) / n (one correctly rounded division)
  hammersley:M        (i / 2^M, radical inverse of i in base 2), i < 2^M
  sobol               scipy's Sobol(d, scramble=False).random(n) (mcint's unscrambled Sobol')
  rows:R;R;...        explicit points, coordinates comma-separated in repr form
and the checksum field (sum over coordinates of (i*d + k + 1) * bits(x_ik) mod 2^64) confirms it.

Line format: name generator n d checksum method scipy exact
"""
import sys
from decimal import Decimal, getcontext
from fractions import Fraction

import numpy as np
import scipy
from scipy.stats import qmc

MASK = (1 << 64) - 1
getcontext().prec = 60


def splitmix(seed, n, d):
    state, rows = seed & MASK, []
    for _ in range(n):
        row = []
        for _ in range(d):
            state = (state + 0x9E3779B97F4A7C15) & MASK
            z = state
            z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
            z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
            z ^= z >> 31
            row.append((z >> 11) * 2.0**-53)
        rows.append(row)
    return rows


def lattice(n, gens):
    return [[((i * g) % n) / n for g in gens] for i in range(n)]


def radical_inverse_2(i, m):
    r = 0
    for k in range(m):
        r |= ((i >> k) & 1) << (m - 1 - k)
    return r


def hammersley(m):
    n = 2**m
    return [[i / n, radical_inverse_2(i, m) / n] for i in range(n)]


def checksum(rows):
    d, h = len(rows[0]), 0
    for i, row in enumerate(rows):
        for k, x in enumerate(row):
            bits = int(np.float64(x).view(np.uint64))
            h = (h + (i * d + k + 1) * bits) & MASK
    return h


def exact_squared(rows, method):
    """Exact squared discrepancy (a Fraction) of the f64 points `rows`."""
    scale = max(Fraction(x).denominator for row in rows for x in row)
    pts = [[int(Fraction(x) * scale) for x in row] for row in rows]
    n, d, S = len(pts), len(pts[0]), scale

    def product(values):
        p = 1
        for v in values:
            p *= v
        return p

    # Each one-dimensional factor as integer / denominator, with a = x * S.
    if method == "L2-star":
        const = Fraction(1, 3) ** d
        single, sden = (lambda a: S * S - a * a), 2 * S * S  # (1 - x^2) / 2
        pair, pden = (lambda a, b: S - max(a, b)), S  # 1 - max(x, y)
    elif method == "CD":
        const = Fraction(13, 12) ** d
        # 1 + |x - 1/2| / 2 - |x - 1/2|^2 / 2
        single, sden = (lambda a: 8 * S * S + 2 * S * abs(2 * a - S) - (2 * a - S) ** 2), 8 * S * S
        # 1 + |x - 1/2| / 2 + |y - 1/2| / 2 - |x - y| / 2
        pair, pden = (lambda a, b: 4 * S + abs(2 * a - S) + abs(2 * b - S) - 2 * abs(a - b)), 4 * S
    elif method == "WD":
        const = Fraction(4, 3) ** d
        single, sden = (lambda a: 4), 3  # the integral over y of the pair kernel
        # 3/2 - |x - y| + |x - y|^2
        pair, pden = (lambda a, b: 3 * S * S - 2 * S * abs(a - b) + 2 * (a - b) ** 2), 2 * S * S
    elif method == "MD":
        const = Fraction(19, 12) ** d
        # 5/3 - |x - 1/2| / 4 - |x - 1/2|^2 / 4
        single, sden = (lambda a: 80 * S * S - 6 * S * abs(2 * a - S) - 3 * (2 * a - S) ** 2), 48 * S * S
        # 15/8 - |x - 1/2| / 4 - |y - 1/2| / 4 - 3 |x - y| / 4 + |x - y|^2 / 2
        pair = lambda a, b: (15 * S * S - S * abs(2 * a - S) - S * abs(2 * b - S)
                             - 6 * S * abs(a - b) + 4 * (a - b) ** 2)
        pden = 8 * S * S
    else:
        raise ValueError(method)
    s1 = Fraction(sum(product(single(a) for a in p) for p in pts), sden**d)
    s2 = 0
    for i in range(n):
        s2 += product(pair(a, a) for a in pts[i])
        for j in range(i + 1, n):
            s2 += 2 * product(pair(a, b) for a, b in zip(pts[i], pts[j]))
    return const - 2 * s1 / n + Fraction(s2, pden**d) / (n * n)


def exact_in_scipy_form(rows, method):
    sq = exact_squared(rows, method)
    if method == "L2-star":
        return float((Decimal(sq.numerator) / Decimal(sq.denominator)).sqrt())
    return float(sq)


def star_exact(rows):
    """D*_N of a 2-D set: max over the grid (coordinates and 1) of open and closed boxes."""
    pts = [(Fraction(x), Fraction(y)) for x, y in rows]
    n = len(pts)
    xs = sorted({p[0] for p in pts} | {Fraction(1)})
    ys = sorted({p[1] for p in pts} | {Fraction(1)})
    best = Fraction(0)
    for a in xs:
        for b in ys:
            open_count = sum(1 for x, y in pts if x < a and y < b)
            closed_count = sum(1 for x, y in pts if x <= a and y <= b)
            best = max(best, a * b - Fraction(open_count, n), Fraction(closed_count, n) - a * b)
    return best


def de_clerck(m):
    """De Clerck (1986): 2^m D* of the 2-D Hammersley set of 2^m points, m >= 2."""
    return Fraction(m, 3) + Fraction(13, 9) - Fraction(4 * (-1) ** m, 9 * 2**m)


def halton_zaremba(m):
    """Halton & Zaremba (1969): (2^m T_N)^2 of the 2-D Hammersley set of 2^m points."""
    return (Fraction(m * m, 64) + Fraction(29 * m, 192) + Fraction(3, 8) - Fraction(m, 2 ** (m + 4))
            + Fraction(1, 2 ** (m + 2)) - Fraction(1, 9 * 2 ** (2 * m + 3)))


def sets():
    yield "random-n40-d3", "splitmix:1", splitmix(1, 40, 3)
    yield "random-n200-d5", "splitmix:2", splitmix(2, 200, 5)
    yield "random-n100-d10", "splitmix:3", splitmix(3, 100, 10)
    yield "random-n64-d20", "splitmix:4", splitmix(4, 64, 20)
    yield "random-n1-d4", "splitmix:5", splitmix(5, 1, 4)
    yield "random-n300-d1", "splitmix:6", splitmix(6, 300, 1)
    yield "fibonacci-n233", "lattice:1,144", lattice(233, [1, 144])
    yield "korobov-n1021-d4", "lattice:1,76,671,957", lattice(1021, [1, 76, 671, 957])
    for m in (1, 2, 3, 4, 6, 8, 10):
        yield f"hammersley-m{m}", f"hammersley:{m}", hammersley(m)
    for n, d in ((1024, 5), (256, 12)):
        yield f"sobol-n{n}-d{d}", "sobol", qmc.Sobol(d, scramble=False).random(n).tolist()
    explicit = {
        "corners": [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0], [1.0, 0.0]],
        "duplicates": [[0.3, 0.3], [0.3, 0.3], [0.7, 0.1], [0.3, 0.9]],
        "tiny": [[5e-324, 0.5], [1e-300, 1.0], [0.25, 2.0**-60], [0.75, 0.75]],
        "centre": [[0.5, 0.5, 0.5]],
    }
    for name, rows in explicit.items():
        text = ";".join(",".join(repr(x) for x in row) for row in rows)
        yield name, "rows:" + text, rows


def main():
    out = sys.stdout
    print(f"# Written by tests/data/discrepancy_scipy.py (scipy {scipy.__version__}, numpy {np.__version__}):", file=out)
    print("#   python3 tests/data/discrepancy_scipy.py > tests/data/discrepancy_scipy.txt", file=out)
    print("# scipy = scipy.stats.qmc.discrepancy(sample, method=M); exact = the same quantity in exact", file=out)
    print("# rational arithmetic, rounded once. L2-star is the root, CD/WD/MD are squares; 'star' is D*_N.", file=out)
    print("# name generator n d checksum method scipy exact", file=out)
    worst = {}
    for name, generator, rows in sets():
        n, d, check = len(rows), len(rows[0]), checksum(rows)
        sample = np.array(rows, dtype=np.float64)
        for method in ("L2-star", "CD", "WD", "MD"):
            ours = exact_in_scipy_form(rows, method)
            theirs = float(qmc.discrepancy(sample, method=method))
            rel = abs(theirs - ours) / abs(ours)
            worst[method] = max(worst.get(method, (0, "")), (rel, name))
            print(f"{name} {generator} {n} {d} {check} {method} {theirs!r} {ours!r}", file=out)
        if d == 2 and n <= 256:
            star = star_exact(rows)
            print(f"{name} {generator} {n} {d} {check} star - {float(star)!r}", file=out)
            if generator.startswith("hammersley:"):
                m = int(generator.split(":")[1])
                if m >= 2:
                    assert star * 2**m == de_clerck(m), (m, star)
        if generator.startswith("hammersley:"):
            m = int(generator.split(":")[1])
            assert exact_squared(rows, "L2-star") * 4**m == halton_zaremba(m), m
    for method, (rel, name) in sorted(worst.items()):
        print(f"# largest |scipy - exact| / exact for {method}: {rel:.3g} ({name})", file=out)
    print("# checked here in exact arithmetic: De Clerck's 2^m D* = m/3 + 13/9 - (-1)^m 4/(9 2^m) for", file=out)
    print("# m = 2, 3, 4, 6, 8 and Halton & Zaremba's (2^m T)^2 for m = 1, 2, 3, 4, 6, 8, 10.", file=out)


if __name__ == "__main__":
    main()
