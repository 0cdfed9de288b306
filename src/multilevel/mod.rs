//! Multilevel Monte Carlo and multilevel QMC for expectations of SDE paths (Giles 2008, 2015;
//! Giles and Waterhouse 2009).
//!
//! Most SDEs have no exact solution: a time step `h` adds a bias, and plain Monte Carlo to a
//! root-mean-square error `eps` then costs `O(eps^-3)` (steps `~ eps`, paths `~ eps^-2`).
//! Multilevel Monte Carlo writes the finest approximation as a telescoping sum,
//! `E[P_L] = E[P_0] + sum_l E[P_l - P_{l-1}]`, and samples each difference from a fine and a
//! coarse path driven by the same Brownian increments: their difference has a small variance,
//! so few samples of the expensive levels are needed, and the cost falls to `O(eps^-2)` when
//! the variance decays faster than the cost grows (`beta > gamma`, Milstein), or
//! `O(eps^-2 log^2 eps)` when they match (`beta = gamma`, Euler).
//!
//! * [`Level`]: what a run needs of a model: one sample of `(P_l, P_{l-1})` from a canonical
//!   point, and its cost.
//! * [`Sde`], [`Scheme`], [`Payoff`], [`SdeLevels`]: scalar and vector SDEs from drift and
//!   diffusion closures (scalar, diagonal and general noise), Euler-Maruyama and Milstein,
//!   refinement factor `M`, and payoffs on the path (European, Asian, lookback, digital,
//!   barrier, any closure), with Giles' Brownian-bridge treatment of the discontinuous ones.
//! * [`Multilevel`]: Giles' adaptive algorithm on the engine, with multilevel QMC as an
//!   option, and Giles' `mlmc_test` survey of the levels ([`Multilevel::survey`]).
//!
//! ```
//! use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};
//! // A European call under geometric Brownian motion, to an RMSE of 0.02.
//! let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
//! let call = SdeLevels::new(gbm, Scheme::Milstein, Payoff::european_call(100.0).unwrap(), 1.0)
//!     .unwrap()
//!     .discount((-0.05f64).exp())
//!     .unwrap();
//! let run = Multilevel::new(call).rmse(0.02).seed(1).run().unwrap();
//! assert!((run.estimate - 10.450583572185565).abs() < 0.08, "{run}");
//! assert!(run.cost * 10.0 < run.standard_mc_cost);
//! ```

mod checkpoint;
mod estimate;
mod fit;
mod level;
mod payoff;
mod runner;
mod sde;
mod sde_levels;
mod sums;

pub use checkpoint::MultilevelCheckpoint;
pub use estimate::{LevelSummary, MultilevelEstimate};
pub use level::Level;
pub use payoff::{PathView, Payoff};
pub use runner::Multilevel;
pub use sde::{Scheme, Sde};
pub use sde_levels::SdeLevels;
