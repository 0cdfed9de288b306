"""True nested uniform (Owen 1995) scrambling of mcint's unscrambled Sobol' points, a fresh
uniform flip for every node of every level, for comparison with mcint's hash-based Owen scramble
and its LMS scramble on the pick-freeze indices of Ishigami (see sensitivity_points.py).

Run:  /tmp/venv/bin/python benches/peers_python/sensitivity_true_owen.py N SEEDS
"""
import sys, subprocess, numpy as np
sys.path.insert(0, __import__('os').path.dirname(__import__('os').path.abspath(__file__)))
import sensitivity_points as sp
N = int(sys.argv[1]); SEEDS = int(sys.argv[2])
raw = subprocess.run([sp.POINTS,'--sampler','sobol','--scramble','none','--dims','6','--n',str(N)],capture_output=True,text=True,check=True).stdout
U = np.loadtxt(raw.splitlines(), delimiter=',')
W = np.round(U * 2.0**32).astype(np.uint64)  # 32-bit words (unscrambled Sobol' is 32-bit)
def owen(words, rng):
    out = np.zeros_like(words)
    for k in range(32):
        bit = (words >> np.uint64(31 - k)) & np.uint64(1)
        prefix = words >> np.uint64(32 - k) if k > 0 else np.zeros_like(words)
        uniq, inv = np.unique(prefix, return_inverse=True)
        flips = rng.integers(0, 2, size=len(uniq), dtype=np.uint64)
        out |= (bit ^ flips[inv]) << np.uint64(31 - k)
    return (out.astype(np.float64) + rng.random(len(words))) / 2.0**32
errs = []
for s in range(1, SEEDS + 1):
    rng = np.random.default_rng(1000 + s)
    u = np.stack([owen(W[:, j], rng) for j in range(6)], axis=1)
    s1, st = sp.indices(*sp.model_runs(u))
    errs.append((s1 - sp.S1, st - sp.ST))
e1 = np.array([e[0] for e in errs]); et = np.array([e[1] for e in errs])
print(f"N={N} true Owen ({SEEDS} seeds): RMS S1 {np.sqrt(np.mean(e1**2)):.2e}  ST {np.sqrt(np.mean(et**2)):.2e}  median max|ST err| {np.median(np.abs(et).max(axis=1)):.2e}")
