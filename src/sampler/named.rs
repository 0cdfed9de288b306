//! Choosing a sampler by name, as configuration files and the example binaries do.

use super::{
    Halton, Hammersley, Independent, Jittered, LatinHypercube, Lattice, Sampler, Scramble, Sobol,
};
use crate::{Error, Result};
use std::fmt;
use std::str::FromStr;

/// The samplers that can be built from a name, a point count and a randomization.
///
/// ```
/// use mcint::sampler::{SamplerKind, Scramble};
/// let kind: SamplerKind = "latin".parse().unwrap();
/// let sampler = kind.build(3, 100, 7).unwrap();
/// assert_eq!(sampler.name(), "latin");
/// let sobol = SamplerKind::Sobol.build_scrambled(2, 1024, Scramble::Lms, 7).unwrap();
/// assert!(sobol.is_randomized());
/// assert!("sobel".parse::<SamplerKind>().unwrap_err().to_string().contains("sobol"));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SamplerKind {
    /// [`Independent`] uniform points.
    Independent,
    /// [`Jittered`] (stratified) points; the point count must be `k^dims`.
    Jittered,
    /// [`LatinHypercube`] (N-rooks) points.
    Latin,
    /// The [`Sobol`] sequence.
    Sobol,
    /// The [`Halton`] sequence.
    Halton,
    /// The [`Hammersley`] point set (the point count is the set's size).
    Hammersley,
    /// The rank-1 [`Lattice`] rule.
    Lattice,
}

impl SamplerKind {
    /// Every kind, in the order listed in messages.
    pub const ALL: [SamplerKind; 7] = [
        SamplerKind::Independent,
        SamplerKind::Jittered,
        SamplerKind::Latin,
        SamplerKind::Sobol,
        SamplerKind::Halton,
        SamplerKind::Hammersley,
        SamplerKind::Lattice,
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
            SamplerKind::Sobol => "sobol",
            SamplerKind::Halton => "halton",
            SamplerKind::Hammersley => "hammersley",
            SamplerKind::Lattice => "lattice",
        }
    }

    /// The randomization used when none is named: Owen scrambling for Sobol', random digit
    /// permutations for Halton and Hammersley, a random shift for lattices, and `None` for the
    /// samplers whose randomization is built in (independent, jittered, latin).
    ///
    /// ```
    /// use mcint::sampler::{SamplerKind, Scramble};
    /// assert_eq!(SamplerKind::Sobol.default_scramble(), Scramble::Owen);
    /// ```
    pub fn default_scramble(self) -> Scramble {
        match self {
            SamplerKind::Sobol => Scramble::Owen,
            SamplerKind::Halton | SamplerKind::Hammersley => Scramble::Permute,
            SamplerKind::Lattice => Scramble::Shift,
            SamplerKind::Independent | SamplerKind::Jittered | SamplerKind::Latin => Scramble::None,
        }
    }

    /// Builds the sampler in `dims` dimensions with `points` per pass (used by the samplers
    /// with fixed passes: jittered, latin, hammersley) and the default randomization.
    ///
    /// ```
    /// use mcint::sampler::SamplerKind;
    /// assert!(SamplerKind::Jittered.build(2, 16, 0).is_ok());
    /// assert!(SamplerKind::Jittered.build(2, 15, 0).is_err());
    /// ```
    pub fn build(self, dims: usize, points: u64, seed: u64) -> Result<Box<dyn Sampler>> {
        self.build_scrambled(dims, points, self.default_scramble(), seed)
    }

    /// Like [`build`](Self::build) with a chosen randomization. Independent, jittered and
    /// latin samplers carry their own randomization and accept only [`Scramble::None`].
    ///
    /// ```
    /// use mcint::sampler::{SamplerKind, Scramble};
    /// assert!(SamplerKind::Halton.build_scrambled(3, 0, Scramble::Owen, 1).is_ok());
    /// assert!(SamplerKind::Latin.build_scrambled(3, 8, Scramble::Owen, 1).is_err());
    /// ```
    pub fn build_scrambled(
        self,
        dims: usize,
        points: u64,
        scramble: Scramble,
        seed: u64,
    ) -> Result<Box<dyn Sampler>> {
        if self.default_scramble() == Scramble::None && scramble != Scramble::None {
            return Err(Error::invalid(
                "scramble",
                scramble,
                format!(
                    "none for the {} sampler, whose randomization is built in (scrambles apply to \
                     sobol, halton, hammersley and lattice)",
                    self.name()
                ),
            ));
        }
        Ok(match self {
            SamplerKind::Independent => Box::new(Independent::new(dims, seed)?),
            SamplerKind::Jittered => Box::new(Jittered::with_points(dims, points, seed)?),
            SamplerKind::Latin => Box::new(LatinHypercube::new(dims, points, seed)?),
            SamplerKind::Sobol => Box::new(Sobol::new(dims, scramble, seed)?),
            SamplerKind::Halton => Box::new(Halton::new(dims, scramble, seed)?),
            SamplerKind::Hammersley => Box::new(Hammersley::new(dims, points, scramble, seed)?),
            SamplerKind::Lattice => Box::new(Lattice::new(dims, scramble, seed)?),
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

/// Builds a sampler from its name with its default randomization:
/// `build_sampler("latin", dims, points, seed)`.
///
/// ```
/// let s = mcint::sampler::build_sampler("independent", 2, 0, 1).unwrap();
/// assert_eq!(s.dims(), 2);
/// ```
pub fn build_sampler(name: &str, dims: usize, points: u64, seed: u64) -> Result<Box<dyn Sampler>> {
    name.parse::<SamplerKind>()?.build(dims, points, seed)
}
