//! Choosing a sampler by name, as configuration files and the example binaries do.

use super::number_theory::prime_root;
use super::{
    BestCandidate, CorrelatedMultiJittered, Halton, Hammersley, Independent, Jittered,
    LatinHypercube, Lattice, MultiJittered, MultiStageNRooks, OaOffset, OrthogonalArray, Pmj02,
    PoissonDisk, Sampler, Scramble, Sobol,
};
use crate::error::parse_name;
use crate::error::{Error, Result};
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
    /// [`MultiJittered`] points (`N = m n`).
    MultiJitter,
    /// [`CorrelatedMultiJittered`] points (`N = m n`).
    Cmj,
    /// An [`OrthogonalArray`] of strength 2 by Bose's construction (`N = p^2`, `p` prime), with
    /// multi-jittered offsets.
    OaBose,
    /// An [`OrthogonalArray`] of strength `t` by Bush's construction (`N = p^t`, `p` prime),
    /// with multi-jittered offsets.
    OaBush,
    /// [`MultiStageNRooks`] points (`N = n^k`).
    NRooksMultistage,
    /// [`PoissonDisk`] blue noise.
    Poisson,
    /// Mitchell's [`BestCandidate`] blue noise.
    BestCandidate,
    /// The progressive multi-jittered (0,2) sequence [`Pmj02`].
    Pmj02,
}

impl SamplerKind {
    /// Every kind, in the order listed in messages.
    pub const ALL: [SamplerKind; 15] = [
        SamplerKind::Independent,
        SamplerKind::Jittered,
        SamplerKind::Latin,
        SamplerKind::Sobol,
        SamplerKind::Halton,
        SamplerKind::Hammersley,
        SamplerKind::Lattice,
        SamplerKind::MultiJitter,
        SamplerKind::Cmj,
        SamplerKind::OaBose,
        SamplerKind::OaBush,
        SamplerKind::NRooksMultistage,
        SamplerKind::Poisson,
        SamplerKind::BestCandidate,
        SamplerKind::Pmj02,
    ];

    /// The strength used by `oa-bush` when none is given.
    pub const DEFAULT_STRENGTH: u32 = 3;

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
            SamplerKind::MultiJitter => "multijitter",
            SamplerKind::Cmj => "cmj",
            SamplerKind::OaBose => "oa-bose",
            SamplerKind::OaBush => "oa-bush",
            SamplerKind::NRooksMultistage => "nrooks-multistage",
            SamplerKind::Poisson => "poisson",
            SamplerKind::BestCandidate => "best-candidate",
            SamplerKind::Pmj02 => "pmj02",
        }
    }

    /// The randomization used when none is named: Owen scrambling for Sobol', random digit
    /// permutations for Halton and Hammersley, a random shift for lattices, and `None` for the
    /// samplers whose randomization is built in (all the others).
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
            _ => Scramble::None,
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
        self.build_with(dims, points, scramble, None, seed)
    }

    /// The most general form: also takes the strength of `oa-bush` (default
    /// [`DEFAULT_STRENGTH`](Self::DEFAULT_STRENGTH); `oa-bose` accepts only 2, and other kinds
    /// none).
    ///
    /// ```
    /// use mcint::sampler::{SamplerKind, Scramble};
    /// let oa = SamplerKind::OaBush.build_with(3, 125, Scramble::None, Some(3), 1).unwrap();
    /// assert_eq!(oa.name(), "oa-bush");
    /// assert!(SamplerKind::OaBush.build_with(3, 100, Scramble::None, Some(3), 1).is_err());
    /// // 64 = 4^3, but 4 is not prime: the error is about the points given, not about p = 4.
    /// let err = SamplerKind::OaBush.build_with(3, 64, Scramble::None, Some(3), 1).err().unwrap();
    /// assert!(err.to_string().starts_with("invalid points = 64"), "{err}");
    /// assert!(SamplerKind::Latin.build_with(3, 100, Scramble::None, Some(3), 1).is_err());
    /// ```
    pub fn build_with(
        self,
        dims: usize,
        points: u64,
        scramble: Scramble,
        strength: Option<u32>,
        seed: u64,
    ) -> Result<Box<dyn Sampler>> {
        let takes_strength = matches!(self, SamplerKind::OaBose | SamplerKind::OaBush);
        if let Some(t) = strength.filter(|_| !takes_strength) {
            return Err(Error::invalid(
                "strength",
                t,
                format!(
                    "no strength for the {} sampler (only oa-bose and oa-bush have one)",
                    self.name()
                ),
            ));
        }
        if self == SamplerKind::OaBose && strength.is_some_and(|t| t != 2) {
            return Err(Error::invalid(
                "strength",
                strength.unwrap_or(2),
                "2 for oa-bose (use oa-bush for other strengths)",
            ));
        }
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
            SamplerKind::MultiJitter => Box::new(MultiJittered::with_points(dims, points, seed)?),
            SamplerKind::Cmj => Box::new(CorrelatedMultiJittered::with_points(dims, points, seed)?),
            SamplerKind::OaBose => Box::new(OrthogonalArray::with_points(
                dims,
                points,
                2,
                OaOffset::MultiJittered,
                seed,
            )?),
            SamplerKind::OaBush => Box::new(bush_with_points(
                dims,
                points,
                strength.unwrap_or(Self::DEFAULT_STRENGTH),
                seed,
            )?),
            SamplerKind::NRooksMultistage => Box::new(MultiStageNRooks::new(dims, points, seed)?),
            SamplerKind::Poisson => Box::new(PoissonDisk::new(dims, points, seed)?),
            SamplerKind::BestCandidate => Box::new(BestCandidate::new(dims, points, seed)?),
            SamplerKind::Pmj02 => Box::new(Pmj02::new(dims, seed)?),
        })
    }
}

/// A Bush array of `points = p^t` (always Bush's construction, also for `t = 2`), or the error
/// of [`OrthogonalArray::with_points`] naming the nearest valid sizes (also when `points` is
/// a power of a number that is not prime: the caller gave `points`, not `p`).
fn bush_with_points(dims: usize, points: u64, strength: u32, seed: u64) -> Result<OrthogonalArray> {
    let offset = OaOffset::MultiJittered;
    if strength > 0
        && let Some(p) = prime_root(points, strength)
    {
        return OrthogonalArray::bush(dims, p, strength, offset, seed);
    }
    OrthogonalArray::with_points(dims, points, strength, offset, seed)
}

impl fmt::Display for SamplerKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for SamplerKind {
    type Err = Error;

    fn from_str(name: &str) -> Result<Self> {
        parse_name("sampler", name, &SamplerKind::ALL, SamplerKind::name)
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
