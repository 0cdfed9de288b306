//! [`Layout`]: the fingerprint of everything that decides a fixed-budget run's numbers, so that
//! parts of different runs are never combined.
//!
//! It records the run's plan (points per replicate, replicates, their spacing, the chunk size
//! and count), the sampler's name, seed and dimension, the non-finite policy, the checkpoint
//! format and an optional label for the integrand, and a digest of the run's values at a few
//! probe points: the sampler's points (which change with its scramble, generating vector,
//! offsets or randomization), and the estimator's contributions there (which change with the
//! integrand, the domain, the pdf or the estimator; and, for control variates, the value of
//! every control). The digest is a CRC-32 (`crc32fast`).
//!
//! Not checked: an integrand that differs from the original only away from the probe points.
//! [`Integrator::label`](super::Integrator::label) names it for that case.

use std::fmt::Display;

use super::plan::Plan;
use super::{CHUNK, NonFinitePolicy};
use crate::engine::{RunConfig, guarded};
use crate::error::{Error, Result};
use crate::estimator::{PilotFit, VectorEstimator};
use crate::sampler::Sampler;

/// The version of the layout and of the saved form of a partial run; a part of another
/// version is refused.
pub(super) const FORMAT_VERSION: u32 = 2;

/// What must agree for two parts to belong to the same run.
#[derive(Debug, Clone, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(super) struct Layout {
    pub(super) format: u32,
    pub(super) label: Option<String>,
    pub(super) sampler: String,
    pub(super) seed: u64,
    pub(super) dims: usize,
    pub(super) samples: u64,
    pub(super) replicates: u64,
    pub(super) stride: u64,
    pub(super) chunk_points: u64,
    pub(super) total_chunks: u64,
    pub(super) non_finite: NonFinitePolicy,
    /// Outputs per point (1 for a scalar integrand, and then not saved).
    #[cfg_attr(
        feature = "serde",
        serde(
            default = "super::plan::one",
            skip_serializing_if = "super::plan::is_one"
        )
    )]
    pub(super) outputs: usize,
    /// CRC-32 of the sampler's points and the estimator's values at the probe points.
    pub(super) probe: u32,
}

impl Layout {
    /// The layout of the run of `plan` with `sampler` and `estimator` (and the pilot stage
    /// it fits itself on, if any), under `config`'s label and non-finite policy.
    pub(super) fn of(
        plan: &Plan,
        sampler: &dyn Sampler,
        estimator: &dyn VectorEstimator,
        pilot: Option<&dyn PilotFit>,
        config: &RunConfig,
    ) -> Result<Layout> {
        Ok(Layout {
            format: FORMAT_VERSION,
            label: config.label.clone(),
            sampler: sampler.name().to_string(),
            seed: sampler.seed(),
            dims: sampler.dims(),
            samples: plan.samples,
            replicates: plan.replicates,
            stride: plan.stride,
            chunk_points: CHUNK,
            total_chunks: plan.total_chunks()?,
            non_finite: config.non_finite,
            outputs: estimator.outputs(),
            probe: probe(plan, sampler, estimator, pilot)?,
        })
    }

    /// Chunks per replicate.
    pub(super) fn chunks_per_replicate(&self) -> u64 {
        self.total_chunks / self.replicates.max(1)
    }

    /// Ok when `other` is a layout of the same run; otherwise an error naming the first
    /// field that differs, with both values.
    pub(super) fn check(&self, other: &Layout) -> Result<()> {
        fn differs<T: PartialEq + Display>(name: &str, ours: T, theirs: T) -> Result<()> {
            if ours == theirs {
                return Ok(());
            }
            let what = if name == "probe" {
                " (the sampler's points or the integrand's values at the probe points)"
            } else {
                ""
            };
            Err(Error::invalid(
                "partial run",
                format!("{name} {theirs}"),
                format!(
                    "a part of this run, whose {name} is {ours}: {name} is the first field that \
                     differs{what}"
                ),
            ))
        }
        let label = |l: &Option<String>| l.clone().unwrap_or_else(|| "(none)".into());
        differs("format", self.format, other.format)?;
        differs("label", label(&self.label), label(&other.label))?;
        differs("sampler", &self.sampler, &other.sampler)?;
        differs("seed", self.seed, other.seed)?;
        differs("dims", self.dims, other.dims)?;
        differs("samples", self.samples, other.samples)?;
        differs("replicates", self.replicates, other.replicates)?;
        differs("stride", self.stride, other.stride)?;
        differs("chunk_points", self.chunk_points, other.chunk_points)?;
        differs("total_chunks", self.total_chunks, other.total_chunks)?;
        differs("outputs", self.outputs, other.outputs)?;
        differs(
            "non_finite",
            format!("{:?}", self.non_finite),
            format!("{:?}", other.non_finite),
        )?;
        differs(
            "probe",
            format!("{:08x}", self.probe),
            format!("{:08x}", other.probe),
        )
    }
}

/// The CRC-32 of the sampler's points and the estimator's values (and, for an estimator with
/// a pilot, its pilot values) at the first, second and last points of the first replicate
/// and the first point of the last one.
fn probe(
    plan: &Plan,
    sampler: &dyn Sampler,
    estimator: &dyn VectorEstimator,
    pilot: Option<&dyn PilotFit>,
) -> Result<u32> {
    let last = plan.samples - 1;
    let replicate = (plan.replicates - 1) * plan.stride;
    let indices = [0, 1.min(last), last, replicate];
    let mut hasher = crc32fast::Hasher::new();
    let mut u = vec![0.0; sampler.dims()];
    let mut x = vec![0.0; estimator.domain_dims()];
    let mut y = vec![0.0; estimator.outputs()];
    let mut row = vec![0.0; pilot.map_or(0, |p| p.values())];
    let mut feed = |values: &[f64]| {
        for v in values {
            hasher.update(&v.to_bits().to_le_bytes());
        }
    };
    for index in indices {
        sampler.point(index, &mut u)?;
        feed(&u);
        guarded((index / plan.stride, index % plan.stride), || {
            estimator.contribution(&u, &mut x, &mut y);
            if let Some(pilot) = pilot {
                pilot.row(&u, &mut x, &mut row);
            }
            Ok(())
        })?;
        feed(&y);
        feed(&row);
    }
    Ok(hasher.finalize())
}
