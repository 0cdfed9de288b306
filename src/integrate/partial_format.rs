//! The saved form of a [`PartialRun`]: its fields and a CRC-32 (`crc32fast`) of their
//! content, checked when it is read back, so that a corrupted checkpoint is refused instead of
//! giving a different answer. An edited one passes a recomputed CRC, so the reader also checks
//! that the state is one its plan reaches (the counts of every chunk and replicate).

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
        let m = layout.outputs;
        if crate::estimator::checked_outputs(m).is_err() {
            return Err(format!(
                "an inconsistent partial run: {m} outputs per point"
            ));
        }
        // The CRC-32 catches accidents, not edits: the state must also be one a run reaches.
        check_state(&layout, saved.prefix, &saved.folded, &saved.chunks)
            .map_err(|e| format!("an inconsistent partial run: {e}"))?;
        Ok(PartialRun {
            layout,
            prefix: saved.prefix,
            folded: saved.folded,
            chunks: saved.chunks.into_iter().collect(),
        })
    }
}

/// Ok when the part's state fits its plan: the layout's chunks add up, every folded
/// accumulator holds exactly the points of chunks `0..prefix` of its replicate, the saved
/// chunks follow the prefix in increasing order with their own points each, and the first
/// non-finite values lie where values were counted non-finite. Otherwise the field at fault.
fn check_state(
    layout: &Layout,
    prefix: u64,
    folded: &Folded,
    chunks: &[(u64, ChunkResult)],
) -> Result<(), String> {
    let (m, replicates, samples, chunk) = (
        layout.outputs,
        layout.replicates,
        layout.samples,
        layout.chunk_points,
    );
    let total = layout.total_chunks;
    if replicates == 0 || samples == 0 || chunk == 0 {
        return Err(format!(
            "layout of {replicates} replicates of {samples} points in chunks of {chunk}, where \
             each must be at least 1"
        ));
    }
    let per_replicate = samples.div_ceil(chunk);
    let planned = per_replicate.checked_mul(replicates);
    if planned != Some(total) {
        return Err(format!(
            "layout.total_chunks {total} where {replicates} replicates of {samples} points in \
             chunks of {chunk} make {}",
            planned.map_or("more than 2^64".into(), |t| t.to_string())
        ));
    }
    if prefix > total {
        return Err(format!(
            "prefix {prefix} beyond layout.total_chunks {total}"
        ));
    }
    if folded.outputs != m {
        return Err(format!(
            "folded.outputs {} where layout.outputs is {m}",
            folded.outputs
        ));
    }
    // Points of chunk `c`: whole chunks but the last of a replicate.
    let points = |c: u64| (samples - c % per_replicate * chunk).min(chunk);
    let accumulators = &folded.accumulators;
    if accumulators.len() as u64 != replicates.saturating_mul(m as u64) {
        return Err(format!(
            "folded.replicates holds {} accumulators where {replicates} replicates of {m} \
             outputs need {}",
            accumulators.len(),
            replicates.saturating_mul(m as u64)
        ));
    }
    let covariances = &folded.covariances;
    if !(covariances.is_empty() || (m > 1 && covariances.len() as u64 == replicates)) {
        return Err(format!(
            "folded.covariances holds {} where none, or one per replicate ({replicates}) of \
             several outputs, is allowed",
            covariances.len()
        ));
    }
    for (r, cov) in covariances.iter().enumerate() {
        if cov.dims() != m {
            return Err(format!(
                "folded.covariances[{r}] has {} outputs where layout.outputs is {m}",
                cov.dims()
            ));
        }
    }
    for r in 0..replicates {
        let (first, end) = (r * per_replicate, (r + 1) * per_replicate);
        let done = prefix.clamp(first, end);
        let expected = if done == end {
            samples
        } else {
            (done - first) * chunk
        };
        let slot = r as usize * m;
        let held = accumulators[slot..slot + m]
            .iter()
            .map(|a| (a.count(), a.non_finite()))
            .chain(
                covariances
                    .get(r as usize)
                    .map(|c| (c.count(), c.non_finite())),
            );
        for (k, (count, non_finite)) in held.enumerate() {
            if count.checked_add(non_finite) != Some(expected) {
                let field = if k < m {
                    format!("folded.replicates[{}]", slot + k)
                } else {
                    format!("folded.covariances[{r}]")
                };
                return Err(format!(
                    "replicate {r} holds {} points in {field} where chunks {first}..{done} hold \
                     {expected}",
                    sum(count, non_finite)
                ));
            }
        }
    }
    check_non_finite(
        "folded.first_non_finite",
        folded.first_non_finite.as_ref(),
        accumulators,
        m,
        |n| {
            n.replicate < replicates
                && n.index < samples
                && n.replicate * per_replicate + n.index / chunk < prefix
        },
    )?;
    let mut previous = None;
    for (c, result) in chunks {
        let c = *c;
        if c <= prefix || c >= total {
            return Err(format!(
                "chunk {c} in chunks, where only chunks {}..{total} follow the {prefix} folded",
                prefix + 1
            ));
        }
        if let Some(before) = previous.filter(|&before| c <= before) {
            return Err(format!(
                "chunk {c} after chunk {before} in chunks, which are saved in increasing order"
            ));
        }
        previous = Some(c);
        if result.accumulators.len() != m {
            return Err(format!(
                "chunk {c} has {} outputs where layout.outputs is {m}",
                result.accumulators.len()
            ));
        }
        match (&result.covariance, covariances.is_empty()) {
            (Some(cov), false) if cov.dims() != m => {
                return Err(format!(
                    "chunk {c} has a covariance of {} outputs where layout.outputs is {m}",
                    cov.dims()
                ));
            }
            (Some(_), true) => {
                return Err(format!(
                    "chunk {c} has a covariance where folded.covariances keeps none"
                ));
            }
            (None, false) => {
                return Err(format!(
                    "chunk {c} has no covariance where folded.covariances keeps one per replicate"
                ));
            }
            _ => {}
        }
        let expected = points(c);
        let held = result
            .accumulators
            .iter()
            .map(|a| (a.count(), a.non_finite()))
            .chain(
                result
                    .covariance
                    .iter()
                    .map(|c| (c.count(), c.non_finite())),
            );
        for (k, (count, non_finite)) in held.enumerate() {
            if count.checked_add(non_finite) != Some(expected) {
                let what = if k < m {
                    format!("output {k}")
                } else {
                    "covariance".into()
                };
                return Err(format!(
                    "chunk {c} holds {} points in its {what} where it has {expected}",
                    sum(count, non_finite)
                ));
            }
        }
        let (replicate, start) = (c / per_replicate, c % per_replicate * chunk);
        check_non_finite(
            &format!("chunk {c}'s first_non_finite"),
            result.first_non_finite.as_ref(),
            &result.accumulators,
            m,
            |n| n.replicate == replicate && (start..start + expected).contains(&n.index),
        )?;
    }
    Ok(())
}

/// Ok when `first` is present exactly when `accumulators` counted a non-finite value, and
/// then a non-finite value of one of the `outputs` at a point that `within` allows.
fn check_non_finite(
    field: &str,
    first: Option<&NonFinite>,
    accumulators: &[Accumulator],
    outputs: usize,
    within: impl Fn(&NonFinite) -> bool,
) -> Result<(), String> {
    let counted = accumulators.iter().any(|a| a.non_finite() > 0);
    match first {
        None if counted => Err(format!(
            "{field} is missing where non-finite values were counted"
        )),
        Some(_) if !counted => Err(format!(
            "{field} is present where no non-finite value was counted"
        )),
        Some(n) if n.value.is_finite() || n.output >= outputs || !within(n) => Err(format!(
            "{field} (replicate {}, index {}, output {}, value {}) is no non-finite value of \
             the points it belongs to",
            n.replicate, n.index, n.output, n.value
        )),
        _ => Ok(()),
    }
}

/// `count + non_finite`, or words for a sum past `u64::MAX`.
fn sum(count: u64, non_finite: u64) -> String {
    count
        .checked_add(non_finite)
        .map_or(format!("{count} + {non_finite} (past 2^64)"), |n| {
            n.to_string()
        })
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
        Accumulator::feed_checksum(&mut h, acc);
    }
    feed_non_finite(&mut h, folded.first_non_finite.as_ref(), several);
    for cov in &folded.covariances {
        feed_covariance(&mut h, cov);
    }
    for (chunk, result) in chunks {
        h.update(&chunk.to_le_bytes());
        for acc in &result.accumulators {
            Accumulator::feed_checksum(&mut h, acc);
        }
        feed_non_finite(&mut h, result.first_non_finite.as_ref(), several);
        if let Some(cov) = &result.covariance {
            feed_covariance(&mut h, cov);
        }
    }
    h.finalize()
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

/// Forged checkpoints: a saved part edited and its checksum recomputed, as anyone can, must
/// still be refused when its state is not one a run reaches, naming the field at fault.
#[cfg(test)]
mod tests {
    use super::*;
    use crate::Integrator;
    use crate::pdf::UniformBox;
    use crate::sampler::{Scramble, Sobol};
    use serde_json::{Value, json};

    /// 400,000 points in 25 chunks, the last one partial.
    fn plain() -> Integrator<impl crate::Estimator> {
        Integrator::over_box(|x: &[f64]| x[0] * x[1], UniformBox::unit(2).unwrap())
            .samples(400_000)
            .seed(7)
    }

    /// Four replicates of two chunks each.
    fn replicates() -> Integrator<impl crate::Estimator> {
        Integrator::over_box(|x: &[f64]| x[0] * x[1], UniformBox::unit(2).unwrap())
            .sampler(Sobol::new(2, Scramble::Owen, 5).unwrap())
            .samples(1 << 15)
            .replicates(4)
    }

    /// The part's JSON edited by `edit`, with the checksum of the edited content, read back.
    fn forged(part: &PartialRun, edit: impl FnOnce(&mut Value)) -> Result<PartialRun, String> {
        let mut value = serde_json::to_value(part).unwrap();
        edit(&mut value);
        let mut saved: Saved = serde_json::from_value(value).map_err(|e| e.to_string())?;
        let sum = content_checksum(&saved.layout, saved.prefix, &saved.folded, &saved.chunks);
        saved.checksum = format!("{sum:08x}");
        serde_json::from_value(serde_json::to_value(saved).unwrap()).map_err(|e| e.to_string())
    }

    /// Asserts that `part` is read back as it was (compared as JSON: NaN is not NaN).
    fn read_back(part: &PartialRun) {
        let back = forged(part, |_| {}).unwrap();
        let json = |p: &PartialRun| serde_json::to_value(p).unwrap();
        assert_eq!(json(&back), json(part));
    }

    /// `edit` of `part` is refused with an error that contains `expected`; the honest part,
    /// through the same steps, is read back unchanged.
    fn refused(part: &PartialRun, edit: impl FnOnce(&mut Value), expected: &str) {
        read_back(part);
        match forged(part, edit) {
            Ok(_) => panic!("a forged part was accepted; expected {expected:?}"),
            Err(e) => assert!(e.contains(expected), "{e:?} does not say {expected:?}"),
        }
    }

    #[test]
    fn a_prefix_raised_to_complete_is_refused() {
        let part = plain().run_part(0..3).unwrap();
        refused(
            &part,
            |v| v["prefix"] = json!(25),
            "an inconsistent partial run: replicate 0 holds 49152 points in \
             folded.replicates[0] where chunks 0..25 hold 400000",
        );
        refused(
            &part,
            |v| v["prefix"] = json!(26),
            "prefix 26 beyond layout.total_chunks 25",
        );
        // A plan shrunk to the chunks done.
        refused(
            &part,
            |v| v["layout"]["total_chunks"] = json!(3),
            "layout.total_chunks 3 where 1 replicates of 400000 points in chunks of 16384 \
             make 25",
        );
        refused(
            &part,
            |v| v["layout"]["chunk_points"] = json!(0),
            "layout of 1 replicates of 400000 points in chunks of 0",
        );
    }

    #[test]
    fn counts_past_the_points_are_refused_without_wrapping() {
        let mut part = plain().run_part(0..3).unwrap();
        part.merge(plain().run_part(24..25).unwrap()).unwrap();
        refused(
            &part,
            |v| v["folded"]["replicates"][0]["count"] = json!(u64::MAX),
            "replicate 0 holds 18446744073709551615 points in folded.replicates[0] where \
             chunks 0..3 hold 49152",
        );
        refused(
            &part,
            |v| v["folded"]["replicates"][0]["non_finite"] = json!(u64::MAX),
            "holds 49152 + 18446744073709551615 (past 2^64) points in folded.replicates[0]",
        );
        // The last chunk holds 400,000 - 24 * 16384 = 6784 points.
        refused(
            &part,
            |v| v["chunks"][0][1]["accumulator"]["count"] = json!(16384),
            "chunk 24 holds 16384 points in its output 0 where it has 6784",
        );
    }

    #[test]
    fn chunks_out_of_order_or_folded_are_refused() {
        let mut part = plain().run_part(0..2).unwrap();
        part.merge(plain().run_part(5..6).unwrap()).unwrap();
        part.merge(plain().run_part(7..8).unwrap()).unwrap();
        let swap = |v: &mut Value| {
            let chunks = v["chunks"].as_array_mut().unwrap();
            chunks.swap(0, 1);
        };
        refused(
            &part,
            swap,
            "chunk 5 after chunk 7 in chunks, which are saved in increasing order",
        );
        refused(
            &part,
            |v| v["chunks"][0][0] = json!(2),
            "chunk 2 in chunks, where only chunks 3..25 follow the 2 folded",
        );
        refused(
            &part,
            |v| v["chunks"][1][0] = json!(25),
            "chunk 25 in chunks, where only chunks 3..25 follow the 2 folded",
        );
    }

    #[test]
    fn replicates_hold_exactly_their_folded_chunks() {
        // Replicate 0 complete (chunks 0 and 1), replicate 1 half (chunk 2).
        let part = replicates().run_part(0..3).unwrap();
        refused(
            &part,
            |v| {
                v["folded"]["replicates"].as_array_mut().unwrap().pop();
            },
            "folded.replicates holds 3 accumulators where 4 replicates of 1 outputs need 4",
        );
        let copy = |to: usize| {
            move |v: &mut Value| {
                let first = v["folded"]["replicates"][0].clone();
                v["folded"]["replicates"][to] = first;
            }
        };
        refused(
            &part,
            copy(1),
            "replicate 1 holds 32768 points in folded.replicates[1] where chunks 2..3 hold 16384",
        );
        refused(
            &part,
            copy(3),
            "replicate 3 holds 32768 points in folded.replicates[3] where chunks 6..6 hold 0",
        );
    }

    #[test]
    fn every_output_and_covariance_holds_the_points() {
        let f = |x: &[f64], out: &mut [f64]| {
            out[0] = x[0];
            out[1] = x[0] * x[1];
        };
        let vector = Integrator::over_box_vector(2, f, UniformBox::unit(2).unwrap())
            .samples(50_000)
            .seed(3);
        // Chunk 3, the last, holds 50,000 - 3 * 16384 = 848 points.
        let mut part = vector.run_part(0..2).unwrap();
        part.merge(vector.run_part(3..4).unwrap()).unwrap();
        refused(
            &part,
            |v| v["folded"]["replicates"][1]["count"] = json!(32769),
            "replicate 0 holds 32769 points in folded.replicates[1] where chunks 0..2 hold 32768",
        );
        refused(
            &part,
            |v| v["folded"]["covariances"][0]["count"] = json!(49152),
            "replicate 0 holds 49152 points in folded.covariances[0] where chunks 0..2 hold \
             32768",
        );
        refused(
            &part,
            |v| v["chunks"][0][1]["more_outputs"][0]["count"] = json!(849),
            "chunk 3 holds 849 points in its output 1 where it has 848",
        );
        refused(
            &part,
            |v| v["chunks"][0][1]["covariance"]["count"] = json!(847),
            "chunk 3 holds 847 points in its covariance where it has 848",
        );
        refused(
            &part,
            |v| {
                v["chunks"][0][1]
                    .as_object_mut()
                    .unwrap()
                    .remove("covariance");
            },
            "chunk 3 has no covariance where folded.covariances keeps one per replicate",
        );
        refused(
            &part,
            |v| {
                v["folded"].as_object_mut().unwrap().remove("covariances");
            },
            "chunk 3 has a covariance where folded.covariances keeps none",
        );
    }

    /// A vector run of independent points whose covariances were all removed reads back (the
    /// saved part cannot tell), but does not finish.
    #[test]
    fn a_part_without_the_covariances_of_its_run_does_not_finish() {
        let f = |x: &[f64], out: &mut [f64]| out.fill(x[0]);
        let vector = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap())
            .samples(50_000)
            .seed(3);
        let mut part = vector.run_part(0..1).unwrap();
        part.merge(vector.run_part(2..4).unwrap()).unwrap();
        let mut stripped = forged(&part, |v| {
            v["folded"].as_object_mut().unwrap().remove("covariances");
            for chunk in v["chunks"].as_array_mut().unwrap() {
                chunk[1].as_object_mut().unwrap().remove("covariance");
            }
        })
        .unwrap();
        vector.resume(&mut stripped, 4).unwrap();
        let e = vector.finish(&stripped).unwrap_err().to_string();
        assert!(e.contains("without covariances"), "{e}");
        vector.resume(&mut part, 4).unwrap();
        assert_eq!(vector.finish(&part).unwrap(), vector.run().unwrap());
    }

    #[test]
    fn the_first_non_finite_value_is_where_one_was_counted() {
        let nan_corner = |x: &[f64]| if x[0] > 0.999 { f64::NAN } else { x[0] };
        let integrator = Integrator::over_box(nan_corner, UniformBox::unit(1).unwrap())
            .samples(100_000)
            .seed(2);
        let mut part = integrator.run_part(0..3).unwrap();
        part.merge(integrator.run_part(4..5).unwrap()).unwrap();
        assert!(part.folded.first_non_finite.is_some());
        // Without it, the finished run would hide the non-finite values it had.
        refused(
            &part,
            |v| v["folded"]["first_non_finite"] = Value::Null,
            "folded.first_non_finite is missing where non-finite values were counted",
        );
        refused(
            &part,
            |v| v["folded"]["first_non_finite"]["index"] = json!(49152),
            "folded.first_non_finite (replicate 0, index 49152, output 0, value NaN) is no \
             non-finite value of the points it belongs to",
        );
        refused(
            &part,
            |v| v["folded"]["first_non_finite"]["value"] = json!(1.5f64.to_bits()),
            "value 1.5) is no non-finite value",
        );
        refused(
            &part,
            |v| v["chunks"][0][1]["first_non_finite"]["index"] = json!(3),
            "chunk 4's first_non_finite (replicate 0, index 3,",
        );
        let clean = plain().run_part(0..1).unwrap();
        refused(
            &clean,
            |v| {
                let nan = json!({"replicate": 0, "index": 5, "value": f64::NAN.to_bits()});
                v["folded"]["first_non_finite"] = nan;
            },
            "folded.first_non_finite is present where no non-finite value was counted",
        );
    }

    /// Parts of every shape a run leaves are read back as they were.
    #[test]
    fn honest_parts_are_accepted() {
        let skip = Integrator::over_box(
            |x: &[f64]| if x[0] > 0.5 { f64::NAN } else { x[0] },
            UniformBox::unit(1).unwrap(),
        )
        .samples(40_000)
        .non_finite(crate::NonFinitePolicy::Skip);
        let parts = [
            plain().run_part(0..25).unwrap(),
            plain().run_part(3..5).unwrap(),
            plain().run_part(24..25).unwrap(),
            replicates().run_part(0..8).unwrap(),
            replicates().run_part(1..6).unwrap(),
            skip.run_part(0..3).unwrap(),
            skip.run_part(1..3).unwrap(),
        ];
        for part in &parts {
            read_back(part);
        }
    }
}
