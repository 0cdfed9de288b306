//! The crate's single error type.
//!
//! Every constructor and [`Integrator::run`](crate::Integrator::run) reports bad input as a
//! value of [`Error`] whose message names what was wrong and what is allowed, so that callers
//! (and the example binaries) can print it as one line.

use std::fmt;

/// What went wrong, with enough detail to fix it.
///
/// ```
/// use mcint::sampler::Jittered;
/// let err = Jittered::with_points(2, 10, 0).unwrap_err();
/// assert!(err.to_string().contains("nearest valid"));
/// ```
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// A parameter has a value outside its allowed range.
    InvalidParameter {
        /// The parameter's name, as the API spells it.
        name: &'static str,
        /// The value that was given, formatted.
        value: String,
        /// What would have been accepted.
        allowed: String,
    },
    /// A buffer or point has the wrong number of dimensions.
    DimensionMismatch {
        /// What was being matched (for example `"point buffer"`).
        what: &'static str,
        /// The number of dimensions required.
        expected: usize,
        /// The number of dimensions given.
        found: usize,
    },
    /// An index or count does not fit the sampler or the integer type that holds it.
    IndexOutOfRange {
        /// What overflowed (for example `"sample index"`).
        what: &'static str,
        /// The largest allowed value.
        limit: u64,
    },
    /// Some contributions `Y_i` were NaN or infinite: the integrand returned such a value, or a
    /// pdf was zero where the integrand was not.
    NonFiniteContribution {
        /// How many contributions were not finite.
        count: u64,
        /// The sample index of the first one (within its replicate).
        first_index: u64,
        /// The replicate it belonged to.
        first_replicate: u64,
        /// The output it belonged to, for an integrand with several outputs.
        first_output: Option<usize>,
        /// Its value (NaN or an infinity).
        first_value: f64,
        /// The canonical point `u` in `[0,1)^k` that produced it.
        first_point: Vec<f64>,
    },
    /// The integrand, or a function the run calls on its behalf (a pdf, a control, a
    /// sampler), panicked; the run stopped and reports the panic here instead of unwinding
    /// through the caller.
    IntegrandPanicked {
        /// The panic message.
        message: String,
        /// The replicate (or iteration, stratum or pass, where the method has those) of the
        /// chunk of work that panicked.
        replicate: u64,
        /// The first sample index of that chunk (within its replicate).
        first_index: u64,
    },
    /// The run stopped (its time limit passed, or it was cancelled) before it had any
    /// estimate to return.
    Interrupted {
        /// Why it stopped.
        stop: crate::stop_reason::StopReason,
        /// Integrand evaluations spent before it stopped.
        evaluations: u64,
    },
    /// A result is not representable in `f64`: every contribution was finite, but a sum
    /// behind the estimate or its standard error overflowed. Every runner handles values up
    /// to `f64::MAX`; the covariance matrix of a vector run holds products of two outputs'
    /// errors, which leave `f64` for outputs beyond about `1e150`.
    Overflow {
        /// What overflowed (for example `"estimate"`).
        what: &'static str,
        /// Its value (an infinity or NaN).
        value: f64,
    },
    /// An operation that this type does not support (for example inverting a warp that has
    /// no inverse).
    Unsupported {
        /// The operation, as the API spells it.
        operation: &'static str,
        /// The type or value that does not support it, and what to use instead if anything.
        reason: String,
    },
    /// Another MPI rank of a run spread over a `Cluster` (the `mpi` feature) failed with this
    /// error, which every rank then reports (the errors that say where an integrand failed,
    /// such as [`IntegrandPanicked`](Error::IntegrandPanicked), arrive as themselves).
    OnRank {
        /// The rank that failed.
        rank: usize,
        /// Its error's message.
        message: String,
    },
}

/// `value`, or the float it spells in exponent form when it is longer than any integer of 64
/// bits (a float's `Display` has no exponent).
fn shortened(value: String) -> String {
    const LONGEST_PLAIN: usize = 24;
    match value.parse::<f64>() {
        Ok(x) if value.len() > LONGEST_PLAIN => format!("{x:e}"),
        _ => value,
    }
}

impl Error {
    /// Shorthand for [`Error::InvalidParameter`]. A float that `Display` would write out in
    /// hundreds of digits (`1e300`, `1e-300`) is shown in exponent form.
    ///
    /// ```
    /// let e = mcint::Error::invalid("dims", 0, "at least 1");
    /// assert_eq!(e.to_string(), "invalid dims = 0: expected at least 1");
    /// let e = mcint::Error::invalid("max_cost", 1e-300, "above 0");
    /// assert_eq!(e.to_string(), "invalid max_cost = 1e-300: expected above 0");
    /// ```
    pub fn invalid(
        name: &'static str,
        value: impl fmt::Display,
        allowed: impl Into<String>,
    ) -> Self {
        Error::InvalidParameter {
            name,
            value: shortened(value.to_string()),
            allowed: allowed.into(),
        }
    }

    /// The message, with the parameter names of an [`Error::InvalidParameter`] spelled as a
    /// front end spells them: each word of the name, and each word with an underscore in what
    /// is allowed (`min_level`: a name, never prose), found in `spellings` as `(library name,
    /// front end's name)` is replaced, so that a program can say `--n` where the library says
    /// `samples` (other errors name no parameter and read as [`Display`](fmt::Display)).
    ///
    /// ```
    /// let e = mcint::Error::invalid("samples x replicates", 0, "at least 1 evaluation");
    /// let names = [("samples", "--n"), ("replicates", "--replicates"), ("max_level", "--max")];
    /// assert_eq!(
    ///     e.message_with_names(&names),
    ///     "invalid --n x --replicates = 0: expected at least 1 evaluation"
    /// );
    /// let e = mcint::Error::invalid("max_level", 61, "at most 60 (max_level limits samples)");
    /// assert_eq!(
    ///     e.message_with_names(&names),
    ///     "invalid --max = 61: expected at most 60 (--max limits samples)"
    /// );
    /// ```
    pub fn message_with_names(&self, spellings: &[(&str, &str)]) -> String {
        let Error::InvalidParameter {
            name,
            value,
            allowed,
        } = self
        else {
            return self.to_string();
        };
        let name = respelled(name, spellings, |_| true);
        let allowed = respelled(allowed, spellings, |word| word.contains('_'));
        format!("invalid {name} = {value}: expected {allowed}")
    }
}

/// `text` with each of its words for which `is_name` holds replaced by its spelling in
/// `spellings`, if it has one.
fn respelled(text: &str, spellings: &[(&str, &str)], is_name: impl Fn(&str) -> bool) -> String {
    let mut spelled = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(start) = rest.find(is_name_char) {
        let (before, word_on) = rest.split_at(start);
        let end = word_on.find(|c| !is_name_char(c)).unwrap_or(word_on.len());
        let (word, after) = word_on.split_at(end);
        spelled.push_str(before);
        let spelling = spellings
            .iter()
            .find(|(library, _)| *library == word && is_name(word));
        spelled.push_str(spelling.map_or(word, |(_, front)| front));
        rest = after;
    }
    spelled.push_str(rest);
    spelled
}

/// Whether `c` belongs to a parameter's name (`tol_rel`, `samples`).
fn is_name_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// The value of `all` whose `name_of` is `name`, or an error for the setting `what` that lists
/// every name: the `FromStr` of the crate's named enums.
pub(crate) fn parse_name<T: Copy>(
    what: &'static str,
    name: &str,
    all: &[T],
    name_of: impl Fn(T) -> &'static str,
) -> Result<T> {
    all.iter()
        .copied()
        .find(|&x| name_of(x) == name)
        .ok_or_else(|| {
            let names: Vec<&str> = all.iter().map(|&x| name_of(x)).collect();
            Error::invalid(
                what,
                format!("{name:?}"),
                format!("one of {}", names.join(", ")),
            )
        })
}

/// The most memory one buffer of the crate may take, 8 GiB: a size that needs more (a point
/// block of `2^40` points, a covariance of a million outputs, a test function in `2^40`
/// dimensions) is refused with an error saying how much was asked for, instead of aborting
/// the process when the allocation fails.
///
/// ```
/// assert_eq!(mcint::MAX_BUFFER_BYTES, 8 << 30);
/// // 2^40 points of one coordinate would take 8 TiB: refused, not an abort.
/// assert!(mcint::Points::new(1, 1 << 40).is_err());
/// ```
pub const MAX_BUFFER_BYTES: u64 = 1 << 33;

/// Ok when a vector of `len` values of `T` fits [`MAX_BUFFER_BYTES`], so that a constructor
/// that builds one from a count reports an absurd count instead of aborting in `vec!`.
pub(crate) fn check_vec_len<T>(name: &'static str, len: usize) -> Result<()> {
    let size = std::mem::size_of::<T>() as u64;
    let most = MAX_BUFFER_BYTES / size.max(1);
    if size > 0 && len as u64 > most {
        return Err(Error::invalid(
            name,
            len,
            format!(
                "at most {most} ({} bytes were asked for; one buffer may take at most 8 GiB)",
                (len as u128) * u128::from(size)
            ),
        ));
    }
    Ok(())
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::InvalidParameter {
                name,
                value,
                allowed,
            } => {
                write!(f, "invalid {name} = {value}: expected {allowed}")
            }
            Error::DimensionMismatch {
                what,
                expected,
                found,
            } => {
                write!(f, "{what} has {found} dimensions, expected {expected}")
            }
            Error::IndexOutOfRange { what, limit } => {
                write!(f, "{what} out of range: at most {limit} allowed")
            }
            Error::NonFiniteContribution {
                count,
                first_index,
                first_replicate,
                first_output,
                first_value,
                first_point,
            } => write!(
                f,
                "{count} non-finite contribution(s); the first, {first_value}, {}at sample \
                 {first_index} of replicate {first_replicate}, canonical point {first_point:?} \
                 (the integrand is not finite there, the pdf is zero where the integrand is not, or \
                 the integrand times the volume, times the measure's weight or over the pdf \
                 overflowed)",
                first_output.map_or(String::new(), |k| format!("in output {k}, "))
            ),
            Error::IntegrandPanicked {
                message,
                replicate,
                first_index,
            } => write!(
                f,
                "the integrand panicked in the work starting at sample {first_index} of \
                 replicate {replicate}: {message}"
            ),
            Error::Interrupted { stop, evaluations } => write!(
                f,
                "the run stopped ({stop:?}) after {evaluations} evaluations, before it had an \
                 estimate: allow more time, or fewer points per stage"
            ),
            Error::Overflow { what, value } => write!(
                f,
                "the {what} is {value}: a sum behind it overflowed f64 (largest 1.8e308; the \
                 covariance matrix of a vector run holds products of two outputs' errors, so it \
                 needs outputs below about 1e150): divide the integrand by a known factor and \
                 multiply the result by it"
            ),
            Error::Unsupported { operation, reason } => {
                write!(f, "{operation} is not supported: {reason}")
            }
            Error::OnRank { rank, message } => write!(f, "on MPI rank {rank}: {message}"),
        }
    }
}

impl std::error::Error for Error {}

/// Result alias used throughout the crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;

#[cfg(test)]
mod tests {
    #[test]
    fn vector_lengths_beyond_isize_are_errors() {
        assert!(super::check_vec_len::<f64>("d", 1 << 30).is_ok());
        assert!(super::check_vec_len::<f64>("d", 1 << 40).is_err());
        let err = super::check_vec_len::<f64>("d", usize::MAX / 4).unwrap_err();
        assert!(err.to_string().starts_with("invalid d = "), "{err}");
        assert!(super::check_vec_len::<()>("d", usize::MAX).is_ok());
    }
}
