//! Choosing a sampler by name, as configuration files and the example binaries do.

use super::{Independent, Jittered, LatinHypercube, Sampler};
use crate::{Error, Result};
use std::fmt;
use std::str::FromStr;

/// The samplers that can be built from a name and a point count.
///
/// ```
/// use mcint::sampler::SamplerKind;
/// let kind: SamplerKind = "latin".parse().unwrap();
/// let sampler = kind.build(3, 100, 7).unwrap();
/// assert_eq!(sampler.name(), "latin");
/// assert!("sobel".parse::<SamplerKind>().unwrap_err().to_string().contains("independent"));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SamplerKind {
    /// [`Independent`] uniform points.
    Independent,
    /// [`Jittered`] (stratified) points; the point count must be `k^dims`.
    Jittered,
    /// [`LatinHypercube`] (N-rooks) points.
    Latin,
}

impl SamplerKind {
    /// Every kind, in the order listed in messages.
    pub const ALL: [SamplerKind; 3] = [
        SamplerKind::Independent,
        SamplerKind::Jittered,
        SamplerKind::Latin,
    ];

    /// The name accepted by [`FromStr`].
    ///
    /// ```
    /// assert_eq!(mcint::sampler::SamplerKind::Jittered.name(), "jittered");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            SamplerKind::Independent => "independent",
            SamplerKind::Jittered => "jittered",
            SamplerKind::Latin => "latin",
        }
    }

    /// Builds the sampler in `dims` dimensions with `points` per pass (ignored by
    /// `independent`, whose points are not grouped in passes).
    ///
    /// ```
    /// use mcint::sampler::SamplerKind;
    /// assert!(SamplerKind::Jittered.build(2, 16, 0).is_ok());
    /// assert!(SamplerKind::Jittered.build(2, 15, 0).is_err());
    /// ```
    pub fn build(self, dims: usize, points: u64, seed: u64) -> Result<Box<dyn Sampler>> {
        Ok(match self {
            SamplerKind::Independent => Box::new(Independent::new(dims, seed)?),
            SamplerKind::Jittered => Box::new(Jittered::with_points(dims, points, seed)?),
            SamplerKind::Latin => Box::new(LatinHypercube::new(dims, points, seed)?),
        })
    }
}

impl fmt::Display for SamplerKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for SamplerKind {
    type Err = Error;

    fn from_str(name: &str) -> Result<Self> {
        SamplerKind::ALL
            .into_iter()
            .find(|kind| kind.name() == name)
            .ok_or_else(|| {
                let names: Vec<&str> = SamplerKind::ALL.iter().map(|k| k.name()).collect();
                Error::invalid("sampler", name, format!("one of {}", names.join(", ")))
            })
    }
}

/// Builds a sampler from its name: `build_sampler("latin", dims, points, seed)`.
///
/// ```
/// let s = mcint::sampler::build_sampler("independent", 2, 0, 1).unwrap();
/// assert_eq!(s.dims(), 2);
/// ```
pub fn build_sampler(name: &str, dims: usize, points: u64, seed: u64) -> Result<Box<dyn Sampler>> {
    name.parse::<SamplerKind>()?.build(dims, points, seed)
}
