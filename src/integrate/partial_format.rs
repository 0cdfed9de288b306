//! The saved form of a [`PartialRun`]: its fields and a CRC-32 (`crc32fast`) of their
//! content, checked when it is read back, so that a corrupted checkpoint is refused instead of
//! giving a different answer.

use std::collections::BTreeMap;

use super::layout::{FORMAT_VERSION, Layout};
use super::partial::PartialRun;
use super::plan::{ChunkResult, Folded, NonFinite};
use crate::stats::Accumulator;

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
        let replicates_ok = saved.folded.replicates.len() as u64 == layout.replicates;
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
                saved.folded.replicates.len(),
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
        folded.replicates.len() as u64,
        chunks.len() as u64,
    ]);
    let text = |h: &mut crc32fast::Hasher, s: &str| {
        h.update(&(s.len() as u64).to_le_bytes());
        h.update(s.as_bytes());
    };
    text(&mut h, &layout.sampler);
    text(&mut h, layout.label.as_deref().unwrap_or("\u{0}none"));
    for acc in &folded.replicates {
        feed_accumulator(&mut h, acc);
    }
    feed_non_finite(&mut h, folded.first_non_finite.as_ref());
    for (chunk, result) in chunks {
        h.update(&chunk.to_le_bytes());
        feed_accumulator(&mut h, &result.accumulator);
        feed_non_finite(&mut h, result.first_non_finite.as_ref());
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

fn feed_non_finite(h: &mut crc32fast::Hasher, first: Option<&NonFinite>) {
    match first {
        None => h.update(&[0]),
        Some(n) => {
            h.update(&[1]);
            for word in [n.replicate, n.index, n.value.to_bits()] {
                h.update(&word.to_le_bytes());
            }
        }
    }
}
