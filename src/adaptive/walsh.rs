//! [`WalshCoefficients`]: the discrete Walsh coefficients of integrand values at the first
//! `2^m` points of a digital sequence, kept as the sequence doubles, with the map from
//! wavenumber order to coefficients that the cone-based error bound of
//! [`SobolG`](super::SobolG) reads (Hickernell & Jiménez Rugama 2016, "Reliable adaptive
//! cubature using digital sequences").
//!
//! For values `y_i` at the points `i = 0 .. N-1` in natural (not Gray-code) order, coefficient
//! `k` is `yt_k = (1/N) sum_i (-1)^popcount(i & k) y_i`; `yt_0` is the mean. Doubling from `n`
//! to `2n` points needs the transform of the new `n` values only: for `k < n`,
//! `yt'_k = (yt_k + z_k) / 2` and `yt'_(n+k) = (yt_k - z_k) / 2`, with `z` the transform of the
//! new values alone.
//!
//! The coefficient index is not a wavenumber. The map `kappa` reorders the coefficients so
//! that, level by level (`h = 2^l`), the larger of the coefficients at slots `j` and `h + j`
//! of the first block of `2h` sits at slot `j`, and every later block of `2h` is swapped the
//! same way; the bound then sums the slots `[N/32, N/16)`. After a doubling only the four
//! finest levels are refined again (`r_lag = 4`), as GAIL's `cubSobol_g` and QMCPy's
//! `CubQMCSobolG` do.

/// Levels refined after each doubling.
pub(super) const LAG: u32 = 4;

/// The discrete Walsh coefficients of the values seen so far and their wavenumber map.
///
/// The coefficients are stored in slot order (`at_slot[p] = yt_kappa(p)`), so that refining
/// the map and summing slots read memory in order; only a doubling looks up the new values'
/// coefficients through `kappa`.
#[derive(Debug, Clone, Default)]
pub(super) struct WalshCoefficients {
    /// `yt_kappa(p)` for `p < N`.
    at_slot: Vec<f64>,
    /// `kappa[p]`: the index of the coefficient at wavenumber slot `p`.
    kappa: Vec<u32>,
}

impl WalshCoefficients {
    /// The coefficients of the first `N = values.len()` values (a power of two, at least 2),
    /// in natural point order, with every level of the map refined.
    pub(super) fn new(mut values: Vec<f64>) -> Self {
        debug_assert!(values.len().is_power_of_two() && values.len() >= 2);
        transform(&mut values, &|| false);
        let mut walsh = WalshCoefficients {
            kappa: (0..values.len() as u32).collect(),
            at_slot: values,
        };
        walsh.refine(walsh.levels(), &|| false);
        walsh
    }

    /// Appends the values of points `N .. 2N` in natural order (`N` of them, transformed in
    /// place) and refines the map's `LAG` finest levels. `stopped` is asked between passes
    /// over the values (each `O(N)`): once it says so, the doubling is abandoned, `false` is
    /// returned and the coefficients are left unusable.
    pub(super) fn double(&mut self, values: &mut [f64], stopped: &dyn Fn() -> bool) -> bool {
        let n = self.at_slot.len();
        debug_assert_eq!(values.len(), n);
        if !transform(values, stopped) {
            return false;
        }
        // Slot p holds index k = kappa[p]; slot n + p holds index n + k.
        self.at_slot.resize(2 * n, 0.0);
        self.kappa.resize(2 * n, 0);
        let (old, new) = self.at_slot.split_at_mut(n);
        let (kappa, new_kappa) = self.kappa.split_at_mut(n);
        for (((a, b), &k), new_k) in old.iter_mut().zip(new).zip(kappa.iter()).zip(new_kappa) {
            let z = values[k as usize];
            (*a, *b) = ((*a + z) / 2.0, (*a - z) / 2.0);
            *new_k = k + n as u32;
        }
        self.refine(LAG.min(self.levels()), stopped)
    }

    /// `N`, the number of values.
    pub(super) fn len(&self) -> usize {
        self.at_slot.len()
    }

    /// `sum_(p in [N/32, N/16)) |yt_kappa(p)|`: the coefficients one level coarser than the
    /// `LAG` finest, from whose size the bound extrapolates the error. Zero below 32 values.
    pub(super) fn lagged_sum(&self) -> f64 {
        let n = self.len();
        self.at_slot[n >> (LAG + 1)..n >> LAG]
            .iter()
            .map(|c| c.abs())
            .sum()
    }

    /// `log2 N`.
    fn levels(&self) -> u32 {
        self.at_slot.len().trailing_zeros()
    }

    /// Refines the map at levels `m-1, m-2, ..` (`count` of them, finest first, `m = log2 N`,
    /// never level 0): at level `l`, the slots `j` in `1 .. 2^l` whose partner `2^l + j` holds
    /// a strictly larger coefficient in the first block of `2^(l+1)` are swapped with their
    /// partners in every block. `false` when `stopped` said so between two levels.
    fn refine(&mut self, count: u32, stopped: &dyn Fn() -> bool) -> bool {
        let m = self.levels();
        let lowest = m.saturating_sub(count).max(1);
        let mut larger = Vec::new();
        for level in (lowest..m).rev() {
            if stopped() {
                return false;
            }
            let h = 1usize << level;
            let (low, high) = self.at_slot[..2 * h].split_at(h);
            // The slots to swap, collected without a branch per slot (each comparison is a
            // coin flip to a branch predictor): every slot is written, the count advances
            // past the larger ones only.
            larger.resize(h, 0);
            let mut count = 0;
            for j in 1..h {
                larger[count] = j;
                count += usize::from(high[j].abs() > low[j].abs());
            }
            larger.truncate(count);
            for block in (0..self.len()).step_by(2 * h) {
                for &j in &larger {
                    self.at_slot.swap(block + j, block + h + j);
                    self.kappa.swap(block + j, block + h + j);
                }
            }
        }
        true
    }
}

/// Values per cache-resident block of the transform (32 KiB).
const BLOCK: usize = 1 << 12;

/// The Walsh-Hadamard transform in place, divided by the length (a power of two): the
/// spans within a cache-resident block first, block by block, then the longer ones. `false`
/// when `stopped` said so between two passes (every `BLOCK` blocks, and every longer span).
fn transform(values: &mut [f64], stopped: &dyn Fn() -> bool) -> bool {
    let n = values.len();
    for (i, block) in values.chunks_mut(BLOCK).enumerate() {
        if i % BLOCK == BLOCK - 1 && stopped() {
            return false;
        }
        butterflies(block, 1, block.len());
    }
    let mut h = BLOCK;
    while h < n {
        if stopped() {
            return false;
        }
        butterflies(values, h, 2 * h);
        h *= 2;
    }
    let scale = 1.0 / n as f64;
    for v in values.iter_mut() {
        *v *= scale;
    }
    true
}

/// The butterflies of spans `h = from, 2 from, ..` below `to` over `values`.
fn butterflies(values: &mut [f64], from: usize, to: usize) {
    let mut h = from;
    while h < to {
        for pair in values.chunks_exact_mut(2 * h) {
            let (low, high) = pair.split_at_mut(h);
            for (a, b) in low.iter_mut().zip(high.iter_mut()) {
                (*a, *b) = (*a + *b, *a - *b);
            }
        }
        h *= 2;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hash::{mix64, unit_f64};

    fn values(n: usize, seed: u64) -> Vec<f64> {
        (0..n as u64)
            .map(|i| unit_f64(mix64(seed ^ i)) - 0.3)
            .collect()
    }

    #[test]
    fn transform_is_the_walsh_sum() {
        let y = values(64, 1);
        let mut fast = y.clone();
        transform(&mut fast, &|| false);
        for (k, &c) in fast.iter().enumerate() {
            let direct: f64 = y
                .iter()
                .enumerate()
                .map(|(i, &v)| if (i & k).count_ones() % 2 == 0 { v } else { -v })
                .sum::<f64>()
                / 64.0;
            assert!((c - direct).abs() < 1e-14, "k {k}: {c} vs {direct}");
        }
    }

    #[test]
    fn blocked_transform_equals_the_plain_one() {
        let y = values(4 * BLOCK, 5);
        let mut blocked = y.clone();
        transform(&mut blocked, &|| false);
        let mut plain = y;
        butterflies(&mut plain, 1, 4 * BLOCK);
        for (k, (&a, &b)) in blocked.iter().zip(&plain).enumerate() {
            assert_eq!(a, b / (4 * BLOCK) as f64, "k {k}");
        }
    }

    #[test]
    fn doubling_gives_the_transform_of_all_values() {
        let y = values(256, 2);
        let mut walsh = WalshCoefficients::new(y[..64].to_vec());
        assert!(walsh.double(&mut y[64..128].to_vec(), &|| false));
        assert!(walsh.double(&mut y[128..].to_vec(), &|| false));
        let mut all = y.clone();
        transform(&mut all, &|| false);
        for (&c, &k) in walsh.at_slot.iter().zip(&walsh.kappa) {
            let exact = all[k as usize];
            assert!((c - exact).abs() < 1e-14, "k {k}: {c} vs {exact}");
        }
    }

    #[test]
    fn the_map_is_a_permutation_that_keeps_the_mean_first_and_puts_larger_first() {
        let y = values(1024, 3);
        let mut walsh = WalshCoefficients::new(y[..512].to_vec());
        assert!(walsh.double(&mut y[512..].to_vec(), &|| false));
        let mut seen = walsh.kappa.clone();
        seen.sort_unstable();
        assert!(seen.iter().enumerate().all(|(p, &k)| k as usize == p));
        assert_eq!(walsh.kappa[0], 0);
        // After refining, the finest level compares the first block's partners: none of
        // slots j in 1..h may hold a smaller coefficient than slot h + j.
        let h = 512;
        let size = |p: usize| walsh.at_slot[p].abs();
        assert!((1..h).all(|j| size(j) >= size(h + j)));
    }

    /// QMCPy 2.4's own `CubQMCNetG.integrate()` on `y_i = sin(0.001 i i) + cos(0.37 i)` in
    /// natural order from 2^10 to 2^13 values: its lagged sums and the first slots of its
    /// kappa map (`python3 tests/data/walsh_qmcpy_reference.py`, output beside it; scipy
    /// 1.17.1, numpy 2.4.6; the script drives QMCPy's unmodified loop with a point generator
    /// that numbers the points).
    #[test]
    fn matches_qmcpy_on_a_fixed_sequence() {
        let y: Vec<f64> = (0..1u32 << 13)
            .map(|i| {
                let i = f64::from(i);
                (0.001 * i * i).sin() + (0.37 * i).cos()
            })
            .collect();
        let reference: [(f64, [u32; 16]); 4] = [
            (
                1.2071537245288226,
                [
                    0, 891, 202, 141, 140, 943, 654, 201, 136, 179, 594, 165, 788, 23, 550, 337,
                ],
            ),
            (
                2.3975603596095905,
                [
                    0, 1915, 1226, 1165, 140, 1967, 1166, 1225, 1160, 1203, 1618, 1061, 1812, 1047,
                    1702, 1233,
                ],
            ),
            (
                2.605821051929942,
                [
                    0, 379, 3274, 3213, 2188, 1967, 3214, 3273, 3208, 3251, 2642, 1061, 1812, 1047,
                    1702, 3281,
                ],
            ),
            (
                3.906948676289984,
                [
                    0, 379, 7370, 3213, 3212, 6063, 7310, 2249, 2184, 3251, 2642, 7205, 1812, 1047,
                    1702, 1233,
                ],
            ),
        ];
        let mut walsh = WalshCoefficients::new(y[..1024].to_vec());
        for (stage, (sum, kappa)) in reference.iter().enumerate() {
            if stage > 0 {
                let n = walsh.len();
                assert!(walsh.double(&mut y[n..2 * n].to_vec(), &|| false));
            }
            let ours = walsh.lagged_sum();
            assert!(
                (ours - sum).abs() <= 1e-12 * sum,
                "stage {stage}: {ours} vs {sum}"
            );
            assert_eq!(&walsh.kappa[..16], kappa, "stage {stage}");
        }
    }

    #[test]
    fn the_lagged_sum_reads_slots_n_over_32_to_n_over_16() {
        let mut walsh = WalshCoefficients::new(values(64, 4));
        walsh.at_slot = (0..64).map(|k| -(k as f64)).collect();
        assert_eq!(walsh.lagged_sum(), 2.0 + 3.0);
    }
}
