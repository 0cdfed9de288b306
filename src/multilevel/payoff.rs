//! [`Payoff`]: functions of a simulated path, with the Brownian-bridge corrections that keep
//! the multilevel variance decay of the discontinuous and path-extreme payoffs.

use std::fmt;
use std::sync::Arc;

use crate::error::{Error, Result};
use crate::special::normal_cdf;
use crate::stats::scale_for;

/// One path as a [`Payoff::on_path`] closure sees it: the states at the times `k * step`,
/// `k = 0..len()`, on the path's own grid (fine or coarse).
///
/// ```
/// use mcint::multilevel::PathView;
/// let states = [1.0, 10.0, 2.0, 20.0, 3.0, 30.0];
/// let path = PathView::new(0.5, &states, 2).unwrap();
/// assert_eq!((path.len(), path.state(1), path.last()), (3, &[2.0, 20.0][..], &[3.0, 30.0][..]));
/// ```
#[derive(Debug, Clone, Copy)]
pub struct PathView<'a> {
    step: f64,
    states: &'a [f64],
    dims: usize,
}

impl<'a> PathView<'a> {
    /// A view of `states` (row-major, `dims` per time) at spacing `step`.
    ///
    /// ```
    /// assert!(mcint::multilevel::PathView::new(0.1, &[1.0, 2.0, 3.0], 2).is_err());
    /// ```
    pub fn new(step: f64, states: &'a [f64], dims: usize) -> Result<PathView<'a>> {
        if dims == 0 || states.is_empty() || !states.len().is_multiple_of(dims) {
            return Err(Error::invalid(
                "states",
                format!("{} values of {dims} states", states.len()),
                "at least one time, and dims > 0 values per time",
            ));
        }
        Ok(PathView { step, states, dims })
    }

    /// The time step.
    ///
    /// ```
    /// assert_eq!(mcint::multilevel::PathView::new(0.25, &[1.0], 1).unwrap().step(), 0.25);
    /// ```
    pub fn step(&self) -> f64 {
        self.step
    }

    /// The number of times, `X(0)` included.
    ///
    /// ```
    /// assert_eq!(mcint::multilevel::PathView::new(0.5, &[1.0, 2.0], 1).unwrap().len(), 2);
    /// ```
    #[allow(clippy::len_without_is_empty)]
    pub fn len(&self) -> usize {
        self.states.len() / self.dims
    }

    /// The state at time `k * step`.
    ///
    /// ```
    /// assert_eq!(mcint::multilevel::PathView::new(0.5, &[1.0, 2.0], 1).unwrap().state(0), &[1.0]);
    /// ```
    pub fn state(&self, k: usize) -> &'a [f64] {
        &self.states[k * self.dims..(k + 1) * self.dims]
    }

    /// The state at the last time.
    ///
    /// ```
    /// assert_eq!(mcint::multilevel::PathView::new(0.5, &[1.0, 2.0], 1).unwrap().last(), &[2.0]);
    /// ```
    pub fn last(&self) -> &'a [f64] {
        self.state(self.len() - 1)
    }
}

type PathFn = Arc<dyn Fn(&PathView<'_>) -> f64 + Send + Sync>;

#[derive(Clone)]
pub(super) enum Kind {
    European { strike: f64 },
    Asian { strike: f64 },
    Lookback,
    Digital { strike: f64 },
    DownAndOut { strike: f64, barrier: f64 },
    Path(PathFn),
}

/// A payoff of the first state's path `S(t)` (undiscounted; [`SdeLevels::discount`]
/// discounts it). The path-dependent ones follow Giles (2008, "Improved multilevel Monte Carlo
/// convergence using the Milstein scheme"): between time steps the path is a Brownian bridge,
/// the coarse path's bridge is pinned to the fine path's Brownian increments, and the
/// digital's last step is integrated out, so that `P_l - P_{l-1}` stays small and the variance
/// decay `beta` above 1.
///
/// [`SdeLevels::discount`]: super::SdeLevels::discount
///
/// ```
/// use mcint::multilevel::Payoff;
/// assert_eq!("lookback".parse::<Payoff>().unwrap().name(), "lookback");
/// assert!(Payoff::european_call(f64::NAN).is_err());
/// ```
#[derive(Clone)]
pub struct Payoff {
    pub(super) kind: Kind,
}

impl fmt::Debug for Payoff {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Payoff({})", self.name())
    }
}

fn check_level(name: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::invalid(name, value, "a finite price"))
    }
}

impl Payoff {
    /// `max(S(T) - K, 0)`.
    ///
    /// ```
    /// assert_eq!(mcint::multilevel::Payoff::european_call(100.0).unwrap().name(), "european");
    /// ```
    pub fn european_call(strike: f64) -> Result<Payoff> {
        let strike = check_level("strike", strike)?;
        Ok(Payoff {
            kind: Kind::European { strike },
        })
    }

    /// `max(A - K, 0)` with `A` the arithmetic average of `S` over `[0, T]`, by the trapezoidal
    /// rule on each path's grid.
    ///
    /// ```
    /// assert_eq!(mcint::multilevel::Payoff::asian_call(100.0).unwrap().name(), "asian");
    /// ```
    pub fn asian_call(strike: f64) -> Result<Payoff> {
        let strike = check_level("strike", strike)?;
        Ok(Payoff {
            kind: Kind::Asian { strike },
        })
    }

    /// The floating-strike lookback `S(T) - min_t S(t)`, the minimum over the continuous path
    /// (sampled from the Brownian bridge of each time step, one extra uniform per fine step).
    ///
    /// ```
    /// assert_eq!(mcint::multilevel::Payoff::lookback().name(), "lookback");
    /// ```
    pub fn lookback() -> Payoff {
        Payoff {
            kind: Kind::Lookback,
        }
    }

    /// The digital call `1{S(T) > K}`, its last time step integrated out (the conditional
    /// probability of ending above `K`), which makes it smooth in the path.
    ///
    /// ```
    /// assert_eq!(mcint::multilevel::Payoff::digital_call(100.0).unwrap().name(), "digital");
    /// ```
    pub fn digital_call(strike: f64) -> Result<Payoff> {
        let strike = check_level("strike", strike)?;
        Ok(Payoff {
            kind: Kind::Digital { strike },
        })
    }

    /// The down-and-out call `max(S(T) - K, 0) 1{min_t S(t) > B}`, the continuous barrier
    /// weighed by each step's Brownian-bridge probability of not crossing it.
    ///
    /// ```
    /// assert_eq!(mcint::multilevel::Payoff::down_and_out_call(100.0, 85.0).unwrap().name(), "barrier");
    /// assert!(mcint::multilevel::Payoff::down_and_out_call(100.0, f64::INFINITY).is_err());
    /// ```
    pub fn down_and_out_call(strike: f64, barrier: f64) -> Result<Payoff> {
        let strike = check_level("strike", strike)?;
        let barrier = check_level("barrier", barrier)?;
        Ok(Payoff {
            kind: Kind::DownAndOut { strike, barrier },
        })
    }

    /// Any function of the discrete path (every state, on the path's own grid; no bridge
    /// correction, so a discontinuous function decays slowly).
    ///
    /// ```
    /// use mcint::multilevel::Payoff;
    /// // The square of the final value.
    /// let square = Payoff::on_path(|p| p.last()[0] * p.last()[0]);
    /// assert_eq!(square.name(), "path");
    /// ```
    pub fn on_path(f: impl Fn(&PathView<'_>) -> f64 + Send + Sync + 'static) -> Payoff {
        Payoff {
            kind: Kind::Path(Arc::new(f)),
        }
    }

    /// The payoff's name, as the `mlmc` CLI spells it.
    ///
    /// ```
    /// assert_eq!(mcint::multilevel::Payoff::lookback().name(), "lookback");
    /// ```
    pub fn name(&self) -> &'static str {
        match self.kind {
            Kind::European { .. } => "european",
            Kind::Asian { .. } => "asian",
            Kind::Lookback => "lookback",
            Kind::Digital { .. } => "digital",
            Kind::DownAndOut { .. } => "barrier",
            Kind::Path(_) => "path",
        }
    }

    /// Whether the payoff reads the path between time steps (its Brownian bridge).
    pub(super) fn needs_bridge(&self) -> bool {
        matches!(self.kind, Kind::Lookback | Kind::DownAndOut { .. })
    }

    /// Whether it samples the minimum of each fine step's bridge (one uniform per step).
    pub(super) fn needs_uniforms(&self) -> bool {
        matches!(self.kind, Kind::Lookback)
    }

    /// Whether it reads every state of the path.
    pub(super) fn needs_states(&self) -> bool {
        matches!(self.kind, Kind::Path(_))
    }

    /// The payoff of one path (see [`PathRecord`]).
    pub(super) fn value(&self, path: &PathRecord<'_>) -> f64 {
        let last = path.own[path.own.len() - 1];
        match &self.kind {
            Kind::European { strike } => (last - strike).max(0.0),
            Kind::Asian { strike } => {
                let steps = (path.own.len() - 1) as f64;
                let inner: f64 = path.own[1..path.own.len() - 1].iter().sum();
                let average = (0.5 * (path.own[0] + last) + inner) / steps;
                (average - strike).max(0.0)
            }
            Kind::Lookback => {
                let mut low = f64::INFINITY;
                for (k, &s) in path.sigma.iter().enumerate() {
                    // In the units the accumulators use for values this large or small (a power
                    // of two, 1 in the ordinary range), so that the squares neither underflow
                    // nor overflow.
                    let unit = scale_for(path.grid[k].abs().max(path.grid[k + 1].abs()));
                    let (a, b, s) = (path.grid[k] / unit, path.grid[k + 1] / unit, s / unit);
                    let u = path.uniforms[k].max(SMALLEST_UNIFORM);
                    let spread = (b - a) * (b - a) - 2.0 * s * s * path.fine_step * u.ln();
                    low = low.min(0.5 * (a + b - spread.sqrt()) * unit);
                }
                last - low
            }
            Kind::Digital { strike } => {
                let (mean, sd) = path.last_step;
                if sd > 0.0 {
                    normal_cdf((mean - strike) / sd)
                } else if mean > *strike {
                    1.0
                } else {
                    0.0
                }
            }
            Kind::DownAndOut { strike, barrier } => {
                let mut alive = 1.0;
                for (k, &s) in path.sigma.iter().enumerate() {
                    let (a, b) = (path.grid[k] - barrier, path.grid[k + 1] - barrier);
                    if a <= 0.0 || b <= 0.0 {
                        return 0.0;
                    }
                    // In the accumulators' units for the distances, as for the lookback.
                    let unit = scale_for(a.max(b));
                    let (a, b, s) = (a / unit, b / unit, s / unit);
                    let variance = s * s * path.fine_step;
                    if variance > 0.0 {
                        alive *= -(-2.0 * a * b / variance).exp_m1();
                    }
                }
                alive * (last - strike).max(0.0)
            }
            Kind::Path(f) => f(&PathView {
                step: path.own_step,
                states: path.states,
                dims: path.dims,
            }),
        }
    }
}

/// The smallest uniform the bridge minimum reads (`ln 0` would send it to minus infinity).
const SMALLEST_UNIFORM: f64 = 1.0 / (1u64 << 54) as f64;

/// One simulated path, as the payoffs read it.
pub(super) struct PathRecord<'a> {
    /// The first state on the path's own grid (`X(0)` first).
    pub(super) own: &'a [f64],
    pub(super) own_step: f64,
    /// The first state at every fine time (the coarse path's interpolated by its bridge),
    /// and each fine interval's bridge volatility; empty unless the payoff needs the bridge.
    pub(super) grid: &'a [f64],
    pub(super) sigma: &'a [f64],
    pub(super) fine_step: f64,
    /// One uniform per fine step (the lookback's).
    pub(super) uniforms: &'a [f64],
    /// The first state's conditional normal law at `T` given all but the last fine Brownian
    /// increment: `(mean, standard deviation)`.
    pub(super) last_step: (f64, f64),
    /// Every state on the own grid, row-major (for path closures), and their number.
    pub(super) states: &'a [f64],
    pub(super) dims: usize,
}

impl std::str::FromStr for Payoff {
    type Err = Error;

    /// The payoffs at strike 100 (barrier 85), by their CLI names.
    fn from_str(s: &str) -> Result<Payoff> {
        match s {
            "european" => Payoff::european_call(100.0),
            "asian" => Payoff::asian_call(100.0),
            "lookback" => Ok(Payoff::lookback()),
            "digital" => Payoff::digital_call(100.0),
            "barrier" => Payoff::down_and_out_call(100.0, 85.0),
            _ => Err(Error::invalid(
                "payoff",
                s,
                "european, asian, lookback, digital or barrier",
            )),
        }
    }
}
