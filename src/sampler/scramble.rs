//! The randomization a low-discrepancy generator applies to each pass.
//!
//! Quasi-Monte Carlo points are deterministic; randomizing them keeps their structure while
//! making each pass an independent, uniformly distributed point set, so replicates give honest
//! error bars (Owen 1995; L'Ecuyer & Lemieux 2002). Not every randomization fits every
//! generator: each constructor says which it accepts.

use crate::error::parse_name;
use crate::error::{Error, Result};
use std::fmt;
use std::str::FromStr;

/// How a quasi-Monte Carlo generator randomizes its passes.
///
/// ```
/// use mcint::sampler::Scramble;
/// assert_eq!("owen".parse::<Scramble>().unwrap(), Scramble::Owen);
/// assert!("nope".parse::<Scramble>().unwrap_err().to_string().contains("xor"));
/// // The name is quoted, so that an empty or blank one shows.
/// let err = "".parse::<Scramble>().unwrap_err().to_string();
/// assert!(err.starts_with(r#"invalid scramble = "": expected one of none"#), "{err}");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Scramble {
    /// No randomization: the deterministic sequence, the same in every pass. Runs report no
    /// standard error, since there is no randomness to measure.
    None,
    /// Random digital shift: every coordinate XORed with a random word per dimension.
    Xor,
    /// Linear matrix scramble plus digital shift (Matoušek 1998; what scipy calls a scrambled
    /// Sobol' sequence).
    Lms,
    /// Owen's nested uniform scramble (Owen 1995), hash-based (Laine & Karras 2011; Burley
    /// 2020).
    Owen,
    /// Random permutations of the digits in each base (for Halton-type sequences).
    Permute,
    /// Cranley-Patterson rotation: a random shift modulo one (for lattices).
    Shift,
}

impl Scramble {
    /// Every randomization, in the order listed in messages.
    pub const ALL: [Scramble; 6] = [
        Scramble::None,
        Scramble::Xor,
        Scramble::Lms,
        Scramble::Owen,
        Scramble::Permute,
        Scramble::Shift,
    ];

    /// The name accepted by [`FromStr`].
    ///
    /// ```
    /// assert_eq!(mcint::sampler::Scramble::Lms.name(), "lms");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            Scramble::None => "none",
            Scramble::Xor => "xor",
            Scramble::Lms => "lms",
            Scramble::Owen => "owen",
            Scramble::Permute => "permute",
            Scramble::Shift => "shift",
        }
    }

    /// Ok when `self` is one of `allowed`; otherwise an error naming them, for `generator`.
    ///
    /// ```
    /// use mcint::sampler::Scramble;
    /// let err = Scramble::Shift.check("sobol", &[Scramble::None, Scramble::Owen]).unwrap_err();
    /// assert!(err.to_string().contains("none, owen"));
    /// ```
    pub fn check(self, generator: &str, allowed: &[Scramble]) -> Result<()> {
        if allowed.contains(&self) {
            return Ok(());
        }
        let names: Vec<&str> = allowed.iter().map(|s| s.name()).collect();
        Err(Error::invalid(
            "scramble",
            self,
            format!("one of {} for {generator}", names.join(", ")),
        ))
    }
}

impl fmt::Display for Scramble {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Scramble {
    type Err = Error;

    fn from_str(name: &str) -> Result<Self> {
        parse_name("scramble", name, &Scramble::ALL, Scramble::name)
    }
}
