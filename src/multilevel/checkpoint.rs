//! [`MultilevelCheckpoint`]: a multilevel run between calls, saved as it goes (down to the
//! chunk a limit stopped at) so that a resumed run takes the same steps and folds the same
//! sums, bit for bit, as one that was never interrupted.

use super::sums::{Extension, LevelSums};
use crate::error::{Error, Result};
use crate::stats::{Accumulator, StopReason};

/// The state of a multilevel run: the sums of every level, the samples its current
/// iteration still takes (with the sums of an extension of a level a limit cut short), the
/// cost spent. Get one from
/// [`Multilevel::checkpoint`](super::Multilevel::checkpoint), run it with
/// [`Multilevel::run_from`](super::Multilevel::run_from), and save it with the `serde` feature
/// (the `mlmc` program's `--checkpoint FILE`). A checkpoint is refused by a run of other
/// settings (a fingerprint of the seed, target, QMC settings, levels, and the model's samples
/// at fixed points, which tell another strike, payoff or volatility apart), and when its
/// content was altered (a CRC-32 of every field).
///
/// ```
/// use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};
/// use mcint::stats::StopReason;
/// let levels = || SdeLevels::new(Sde::gbm(100.0, 0.05, 0.2).unwrap(), Scheme::Milstein,
///     Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
/// let whole = Multilevel::new(levels()).rmse(0.05).seed(1).run().unwrap();
/// // The same run cut short by a cost limit, then resumed without one.
/// let mut saved = Multilevel::new(levels()).rmse(0.05).seed(1).checkpoint().unwrap();
/// let cut = Multilevel::new(levels()).rmse(0.05).seed(1).max_cost(1e5).run_from(&mut saved).unwrap();
/// assert_eq!(cut.stop, StopReason::MaxEvaluations);
/// let resumed = Multilevel::new(levels()).rmse(0.05).seed(1).run_from(&mut saved).unwrap();
/// assert_eq!(resumed, whole);
/// ```
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct MultilevelCheckpoint {
    /// The settings it belongs to.
    pub(super) fingerprint: u64,
    /// Per level, one sum per replicate.
    pub(super) levels: Vec<Vec<LevelSums>>,
    /// Samples per replicate the next iteration adds to each level.
    pub(super) pending: Vec<u64>,
    pub(super) spent: f64,
    pub(super) bias_stuck: bool,
    /// The extension of a level a limit cut short, continued first on resuming.
    pub(super) in_flight: Option<Extension>,
    /// How the run ended, once it has (a tolerance met or the deepest level reached).
    pub(super) finished: Option<StopReason>,
    /// CRC-32 of the fields above.
    pub(super) checksum: u32,
}

impl MultilevelCheckpoint {
    pub(super) fn new(fingerprint: u64, levels: Vec<Vec<LevelSums>>, pending: Vec<u64>) -> Self {
        let mut state = MultilevelCheckpoint {
            fingerprint,
            levels,
            pending,
            spent: 0.0,
            bias_stuck: false,
            in_flight: None,
            finished: None,
            checksum: 0,
        };
        state.seal();
        state
    }

    /// Recomputes the checksum after the fields changed.
    pub(super) fn seal(&mut self) {
        self.checksum = self.crc();
    }

    fn crc(&self) -> u32 {
        let mut h = crc32fast::Hasher::new();
        let mut words = vec![self.fingerprint, self.levels.len() as u64];
        words.extend(&self.pending);
        words.extend([self.spent.to_bits(), u64::from(self.bias_stuck)]);
        words.push(self.finished.map_or(0, |s| 1 + s as u64));
        for word in words {
            h.update(&word.to_le_bytes());
        }
        if let Some(cut) = &self.in_flight {
            for word in [cut.level as u64, cut.chunks, cut.sums.len() as u64] {
                h.update(&word.to_le_bytes());
            }
        }
        let cut = self.in_flight.iter().flat_map(|c| &c.sums);
        for sums in self.levels.iter().flatten().chain(cut) {
            Accumulator::feed_checksum(&mut h, &sums.difference);
            Accumulator::feed_checksum(&mut h, &sums.fine);
            h.update(&sums.cube.to_bits().to_le_bytes());
            h.update(&sums.fourth.to_bits().to_le_bytes());
        }
        h.finalize()
    }

    /// Refuses a checkpoint of other settings, an altered one, or one whose shape no run of
    /// these settings reaches.
    pub(super) fn check(&self, fingerprint: u64, replicates: u64, levels: usize) -> Result<()> {
        if self.fingerprint != fingerprint {
            return Err(Error::invalid(
                "checkpoint",
                format!("fingerprint {:#018x}", self.fingerprint),
                format!(
                    "a checkpoint of this run ({fingerprint:#018x}): the seed, target, QMC \
                     settings, levels or model differ"
                ),
            ));
        }
        if self.checksum != self.crc() {
            return Err(Error::invalid(
                "checkpoint",
                format!("checksum {:#010x}", self.checksum),
                format!(
                    "an unaltered checkpoint (its content gives {:#010x})",
                    self.crc()
                ),
            ));
        }
        let shaped = self.levels.len() == self.pending.len()
            && (levels..=61).contains(&self.levels.len())
            && self.levels.iter().all(|sums| {
                sums.len() as u64 == replicates && sums.iter().all(|s| s.count() == sums[0].count())
            })
            && self.in_flight.as_ref().is_none_or(|cut| {
                cut.level < self.levels.len()
                    && self.pending[cut.level] > 0
                    && cut.sums.len() as u64 == replicates
            })
            && self.spent.is_finite()
            && self.spent >= 0.0;
        if !shaped {
            return Err(Error::invalid(
                "checkpoint",
                format!("{} levels", self.levels.len()),
                format!(
                    "a state this run reaches: at least {levels} levels, {replicates} replicate \
                     sums of equal counts each"
                ),
            ));
        }
        Ok(())
    }
}
