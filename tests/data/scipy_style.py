# Reference values of tests/samplers/scipy_style.rs: /tmp/venv/bin/python this file (scipy 1.17.1).
import numpy as np
from scipy.stats import qmc
bits = lambda a: np.asarray(a, dtype=np.float64).view(np.uint64).tolist()
rows = np.array([[0.1, 0.7, 0.33], [0.999, 0.0, 0.5], [0.123456789, 0.987654321, 0.25]])
lo, hi = [-1.5, 0.1, 3.0], [2.25, 0.7, 1e6]
scaled = qmc.scale(rows, lo, hi)
print("scale", bits(scaled))
print("unscale", bits(qmc.scale(scaled, lo, hi, reverse=True)))
print("random", bits(qmc.Sobol(d=3, scramble=False).random(8)))
print("integers", qmc.Sobol(d=2, scramble=False).integers([0, -5], u_bounds=[7, 5], n=8).tolist())
print("integers_h", qmc.Halton(d=2, scramble=False).integers([1, -100], u_bounds=[4, 1000], n=6).tolist())
