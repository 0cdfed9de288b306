//! The saved form of a [`PartialRun`]: its fields and a CRC-32 (`crc32fast`) of their
//! content, checked when it is read back, so that a corrupted checkpoint is refused instead of
//! giving a different answer.

use std::collections::BTreeMap;

use super::layout::{FORMAT_VERSION, Layout};
use super::partial::PartialRun;
use super::plan::{ChunkResult, Folded, NonFinite};
use crate::stats::{Accumulator, CovarianceAccumulator};

/// A [`PartialRun`] as serde writes it.
#[derive(serde::Serialize, serde::Deserialize)]
pub(super) struct Saved {
    layout: Layout,
    prefix: u64,
    folded: Folded,
    chunks: Vec<(u64, ChunkResult)>,
    /// CRC-32 of everything above, as eight hexadecimal digits.
    checksum: String,
}

impl From<PartialRun> for Saved {
    fn from(part: PartialRun) -> Saved {
        let chunks: Vec<(u64, ChunkResult)> = part.chunks.into_iter().collect();
        let checksum = format!(
            "{:08x}",
            content_checksum(&part.layout, part.prefix, &part.folded, &chunks)
        );
        Saved {
            layout: part.layout,
            prefix: part.prefix,
            folded: part.folded,
            chunks,
            checksum,
        }
    }
}

impl TryFrom<Saved> for PartialRun {
    type Error = String;

    fn try_from(saved: Saved) -> Result<PartialRun, String> {
        let layout = saved.layout;
        if layout.format != FORMAT_VERSION {
            return Err(format!(
                "a partial run of format {}; this version reads format {FORMAT_VERSION}",
                layout.format
            ));
        }
        let computed = content_checksum(&layout, saved.prefix, &saved.folded, &saved.chunks);
        if format!("{computed:08x}") != saved.checksum {
            return Err(format!(
                "a corrupted partial run: its content has checksum {computed:08x}, it records {}",
                saved.checksum
            ));
        }
        let total = layout.total_chunks;
        let m = layout.outputs;
        if crate::estimator::checked_outputs(m).is_err() {
            return Err(format!(
                "an inconsistent partial run: {m} outputs per point"
            ));
        }
        let replicates_ok = saved.folded.outputs == m
            && saved.folded.accumulators.len() as u64 == layout.replicates.saturating_mul(m as u64)
            && saved.chunks.iter().all(|(_, r)| r.accumulators.len() == m);
        let mut chunks = BTreeMap::new();
        for (chunk, result) in saved.chunks {
            if chunk <= saved.prefix || chunk >= total || chunks.insert(chunk, result).is_some() {
                return Err(format!(
                    "an inconsistent partial run: chunk {chunk} with {} of {total} folded",
                    saved.prefix
                ));
            }
        }
        if !replicates_ok || saved.prefix > total {
            return Err(format!(
                "an inconsistent partial run: {} of {total} chunks folded into {} replicates \
                 of {}",
                saved.prefix,
                saved.folded.accumulators.len(),
                layout.replicates
            ));
        }
        Ok(PartialRun {
            layout,
            prefix: saved.prefix,
            folded: saved.folded,
            chunks,
        })
    }
}

/// The CRC-32 of a part's content, fed field by field in a fixed order (floats by their bits).
fn content_checksum(
    layout: &Layout,
    prefix: u64,
    folded: &Folded,
    chunks: &[(u64, ChunkResult)],
) -> u32 {
    let mut h = crc32fast::Hasher::new();
    let mut words = |values: &[u64]| {
        for v in values {
            h.update(&v.to_le_bytes());
        }
    };
    words(&[
        u64::from(layout.format),
        layout.seed,
        layout.dims as u64,
        layout.samples,
        layout.replicates,
        layout.stride,
        layout.chunk_points,
        layout.total_chunks,
        u64::from(layout.non_finite == super::NonFinitePolicy::Skip),
        u64::from(layout.probe),
        prefix,
        folded.accumulators.len() as u64,
        chunks.len() as u64,
    ]);
    // Several outputs add their fields; a scalar part keeps the checksum of its earlier form.
    let several = layout.outputs > 1;
    if several {
        h.update(&(layout.outputs as u64).to_le_bytes());
    }
    let text = |h: &mut crc32fast::Hasher, s: &str| {
        h.update(&(s.len() as u64).to_le_bytes());
        h.update(s.as_bytes());
    };
    text(&mut h, &layout.sampler);
    text(&mut h, layout.label.as_deref().unwrap_or("\u{0}none"));
    for acc in &folded.accumulators {
        feed_accumulator(&mut h, acc);
    }
    feed_non_finite(&mut h, folded.first_non_finite.as_ref(), several);
    for cov in &folded.covariances {
        feed_covariance(&mut h, cov);
    }
    for (chunk, result) in chunks {
        h.update(&chunk.to_le_bytes());
        for acc in &result.accumulators {
            feed_accumulator(&mut h, acc);
        }
        feed_non_finite(&mut h, result.first_non_finite.as_ref(), several);
        if let Some(cov) = &result.covariance {
            feed_covariance(&mut h, cov);
        }
    }
    h.finalize()
}

fn feed_accumulator(h: &mut crc32fast::Hasher, acc: &Accumulator) {
    for word in [
        acc.count(),
        acc.mean().to_bits(),
        acc.m2().to_bits(),
        acc.min().to_bits(),
        acc.max().to_bits(),
        acc.non_finite(),
        acc.rounding_bound().to_bits(),
    ] {
        h.update(&word.to_le_bytes());
    }
}

fn feed_non_finite(h: &mut crc32fast::Hasher, first: Option<&NonFinite>, with_output: bool) {
    match first {
        None => h.update(&[0]),
        Some(n) => {
            h.update(&[1]);
            for word in [n.replicate, n.index, n.value.to_bits()] {
                h.update(&word.to_le_bytes());
            }
            if with_output {
                h.update(&(n.output as u64).to_le_bytes());
            }
        }
    }
}

fn feed_covariance(h: &mut crc32fast::Hasher, cov: &CovarianceAccumulator) {
    h.update(&cov.count().to_le_bytes());
    h.update(&cov.non_finite().to_le_bytes());
    for mean in cov.means() {
        h.update(&mean.to_bits().to_le_bytes());
    }
    for i in 0..cov.dims() {
        for j in 0..=i {
            h.update(&cov.comoment(i, j).to_bits().to_le_bytes());
        }
    }
}

/// A [`ChunkResult`] as serde writes it: the first output's accumulator under the name of the
/// scalar form, the other outputs' and the covariance only when there are several.
#[derive(serde::Serialize, serde::Deserialize)]
pub(super) struct SavedChunk {
    accumulator: Accumulator,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    more_outputs: Vec<Accumulator>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    covariance: Option<CovarianceAccumulator>,
    first_non_finite: Option<NonFinite>,
}

impl From<ChunkResult> for SavedChunk {
    fn from(result: ChunkResult) -> SavedChunk {
        let mut outputs = result.accumulators.into_iter();
        SavedChunk {
            accumulator: outputs.next().unwrap_or_default(),
            more_outputs: outputs.collect(),
            covariance: result.covariance,
            first_non_finite: result.first_non_finite,
        }
    }
}

impl From<SavedChunk> for ChunkResult {
    fn from(saved: SavedChunk) -> ChunkResult {
        let mut accumulators = vec![saved.accumulator];
        accumulators.extend(saved.more_outputs);
        ChunkResult {
            accumulators,
            covariance: saved.covariance,
            first_non_finite: saved.first_non_finite,
        }
    }
}
