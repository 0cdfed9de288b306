"""Reference values for the Walsh-coefficient error bound of QMCPy 2.4's
CubQMCNetG (= CubQMCSobolG), computed by QMCPy's own integrate() loop.

Value sequence, natural point order:
    y_i = math.sin(0.001 * i * i) + math.cos(0.37 * i)      i = 0, 1, 2, ...
(Python floats; 0.001 * i * i evaluates as (0.001 * i) * i.)

How QMCPy is made to see this sequence:
  * a real CubQMCNetG(CustomFun(Uniform(DigitalNetB2(1, seed=7)), g), ...) is built;
  * its point generator attribute `sc.discrete_distrib` (the object
    integrate() calls as self.discrete_distrib(n_min=..., n_max=...)) is replaced
    by a fake that returns the points x_i = i / 2^13 (exact binary fractions,
    shape (n, 1)) for i in [n_min, n_max);
  * Uniform[0,1]'s transform x*1+0 is exact, so g recovers i = t * 2^13
    exactly (asserted) and returns y_i.
Everything else (fwht, omega_fwht, the doubling update, _update_kappanumap,
the mean, fudge(m) * sum |yt[kap[2^(m-5):2^(m-4)]]|) is QMCPy's integrate().
To stop at n = 2^m, integrate() is run with n_limit = 2^m and an unreachable
abs_tol, for m = 10, 11, 12, 13 (n_init = 2^10 each time; the runs are
deterministic, so run m repeats the first iterations of run m+1 exactly --
this is also checked by snapshotting every iteration of the 2^13 run).

Run: python3 tests/data/walsh_qmcpy_reference.py (pip install qmcpy==2.4 scipy==1.17.1)
"""
import math
import sys
import warnings

import numpy as np
import scipy
import qmcpy as qp
from qmcpy.stopping_criterion.abstract_cub_qmc_ld_g import AbstractCubQMCLDG

M_INIT, M_MAX = 10, 13
SCALE = 2 ** M_MAX
Y = [math.sin(0.001 * i * i) + math.cos(0.37 * i) for i in range(2 ** M_MAX)]
Y_ARR = np.array(Y, dtype=float)


def g(t):
    s = t[..., 0] * SCALE
    idx = np.rint(s).astype(np.int64)
    assert np.array_equal(idx.astype(float), s), "index encoding not exact"
    return Y_ARR[idx]


class FakePoints:
    """Stands in for sc.discrete_distrib inside integrate():
    natural-order point i is encoded as x_i = i / 2^13."""

    def __init__(self, real):
        self.real = real
        self.calls = []

    def __call__(self, n_min=0, n_max=None, **kw):
        self.calls.append((int(n_min), int(n_max)))
        i = np.arange(n_min, n_max, dtype=np.int64)
        return (i.astype(float) / SCALE)[:, None]

    def __getattr__(self, name):  # anything else -> the real DigitalNetB2
        return getattr(self.real, name)


def make_sc(n_limit):
    dn = qp.DigitalNetB2(1, seed=7)
    ig = qp.CustomFun(qp.Uniform(dn), g=g)
    sc = qp.CubQMCNetG(ig, abs_tol=1e-300, rel_tol=0.0, n_init=2 ** M_INIT,
                       n_limit=n_limit)
    assert type(sc).__name__ == "CubQMCNetG" and sc.r_lag == 4
    assert sc.ft is qp.fast_transform.fwht and sc.omega is qp.fast_transform.omega_fwht
    fake = FakePoints(sc.discrete_distrib)
    sc.discrete_distrib = fake
    return sc, fake


def run(m):
    sc, fake = make_sc(2 ** m)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # MaxSamplesWarning is expected
        sol, data = sc.integrate()
    assert int(data.n_total) == 2 ** m
    want = [(0, 2 ** M_INIT)] + [(2 ** k, 2 ** (k + 1)) for k in range(M_INIT, m)]
    assert fake.calls == want, fake.calls
    assert np.array_equal(data.yfull, Y_ARR[: 2 ** m])
    yt = np.asarray(data._ytildefull)
    kap = np.asarray(data._kappanumap)
    lo, hi = 2 ** (m - 5), 2 ** (m - 4)
    # same expression QMCPy uses for the bound (without the fudge factor)
    S = np.abs(np.take_along_axis(yt, kap[..., lo:hi], axis=-1)).sum(-1)
    hw = float(data.bounds_half_width)
    assert hw == sc.fudge(m) * S, (hw, sc.fudge(m) * S)
    assert hw == 5 * 2.0 ** -m * S
    return dict(m=m, S=float(S), hw=hw, kap=kap[:16].tolist(),
                mean=float(data.muhat), yt=yt.copy(), kapfull=kap.copy())


def snapshot_run():
    """One run to 2^13; record (yt, kap) after each _update_kappanumap call made
    by integrate() at the end of each iteration (calls with mfrom = m-1)."""
    sc, _ = make_sc(2 ** M_MAX)
    snaps = {}
    orig = AbstractCubQMCLDG._update_kappanumap

    def spy(self, kappanumap, ytildefull, mfrom, mto, m):
        out = orig(self, kappanumap, ytildefull, mfrom, mto, m)
        snaps[m] = (np.array(ytildefull, copy=True), np.array(out, copy=True))
        return out

    sc._update_kappanumap = spy.__get__(sc)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sc.integrate()
    return snaps


def main():
    print("qmcpy %s, numpy %s, scipy %s, python %s"
          % (qp.__version__, np.__version__, scipy.__version__, sys.version.split()[0]))
    print("y_i = math.sin(0.001*i*i) + math.cos(0.37*i), natural order; n_init = 2^10")
    print("S_m = sum_{p=2^(m-5)}^{2^(m-4)-1} |yt[kap[p]]|,  hw = 5*2^-m*S_m "
          "(= QMCPy data.bounds_half_width)")
    rows = [run(m) for m in range(M_INIT, M_MAX + 1)]
    snaps = snapshot_run()
    for r in rows:
        ys, ks = snaps[r["m"]]
        # later iterations pass ytildefull[compute_flags] (shape (1, n) for a
        # scalar integrand), hence the reshape
        assert np.array_equal(ys.reshape(-1), r["yt"]), r["m"]
        assert np.array_equal(ks.reshape(-1), r["kapfull"]), r["m"]
    print("(per-iteration snapshots of a single 2^13 run are identical to the "
          "n_limit=2^m runs: yes)")
    for r in rows:
        print()
        print("m = %d  (n = %d, slots [%d, %d))" % (r["m"], 2 ** r["m"],
                                                    2 ** (r["m"] - 5), 2 ** (r["m"] - 4)))
        print("  S_m      = %.17g" % r["S"])
        print("  hw       = %.17g" % r["hw"])
        print("  mean     = %.17g" % r["mean"])
        print("  kap[0..16] = [%s]" % ", ".join(str(k) for k in r["kap"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
