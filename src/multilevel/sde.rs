//! [`Sde`] and [`Scheme`]: stochastic differential equations `dX = a(t, X) dt + b(t, X) dW`
//! from closures, and the schemes that step them.

use std::fmt;
use std::sync::Arc;

use crate::error::{Error, Result};

/// `(t, x, out)`: writes a vector function of time and state into `out`.
type VectorFn = Arc<dyn Fn(f64, &[f64], &mut [f64]) + Send + Sync>;
/// `(t, x)`: a scalar function of time and state.
type ScalarFn = Arc<dyn Fn(f64, f64) -> f64 + Send + Sync>;

/// How the noise enters the equation.
#[derive(Clone)]
pub(super) enum Noise {
    /// One state, one Brownian motion: `b(t, x)` and, for Milstein, `db/dx`.
    Scalar {
        diffusion: ScalarFn,
        derivative: Option<ScalarFn>,
    },
    /// State `i` driven by Brownian motion `i` alone: `b_i(t, x)` and, for Milstein,
    /// `d b_i / d x_i`.
    Diagonal {
        diffusion: VectorFn,
        derivative: Option<VectorFn>,
    },
    /// `d x m` matrix `b_ij(t, x)` (row-major) and, for Milstein under commutative noise, the
    /// `d x m x m` terms `L^j b_ik = sum_r b_rj d b_ik / d x_r` (index `(i m + j) m + k`).
    General {
        noises: usize,
        diffusion: VectorFn,
        milstein: Option<VectorFn>,
    },
}

/// A stochastic differential equation `dX = a(t, X) dt + b(t, X) dW` on `[0, T]` from `X(0)`,
/// with `d` states and `m` independent Brownian motions, as closures. Time steps, payoffs and
/// levels come from [`SdeLevels`](super::SdeLevels).
///
/// ```
/// use mcint::multilevel::Sde;
/// // Geometric Brownian motion by hand, as Sde::gbm builds it.
/// let gbm = Sde::scalar(100.0, |_, x| 0.05 * x, |_, x| 0.2 * x)
///     .unwrap()
///     .diffusion_derivative(|_, _| 0.2)
///     .unwrap();
/// assert_eq!((gbm.states(), gbm.noises()), (1, 1));
/// ```
#[derive(Clone)]
pub struct Sde {
    pub(super) start: Vec<f64>,
    pub(super) drift: VectorFn,
    pub(super) noise: Noise,
}

impl fmt::Debug for Sde {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Sde")
            .field("start", &self.start)
            .field("noises", &self.noises())
            .field("milstein", &self.has_milstein_terms())
            .finish()
    }
}

/// The time-stepping scheme.
///
/// ```
/// use mcint::multilevel::Scheme;
/// assert_eq!("milstein".parse::<Scheme>().unwrap(), Scheme::Milstein);
/// assert!("rk4".parse::<Scheme>().is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scheme {
    /// Euler-Maruyama: strong order 1/2, weak order 1 (multilevel `beta = 1`, `alpha = 1`).
    Euler,
    /// Milstein: strong order 1 for scalar, diagonal and commutative noise (`beta = 2`).
    Milstein,
}

impl std::str::FromStr for Scheme {
    type Err = Error;

    fn from_str(s: &str) -> Result<Scheme> {
        match s {
            "euler" => Ok(Scheme::Euler),
            "milstein" => Ok(Scheme::Milstein),
            _ => Err(Error::invalid("scheme", s, "euler or milstein")),
        }
    }
}

fn check_start(start: &[f64]) -> Result<()> {
    if start.is_empty() {
        return Err(Error::invalid("start", "[]", "at least one state"));
    }
    if let Some(x) = start.iter().find(|x| !x.is_finite()) {
        return Err(Error::invalid("start", x, "finite values"));
    }
    Ok(())
}

impl Sde {
    /// A scalar equation `dX = a(t, X) dt + b(t, X) dW` from `x0` (finite). Milstein needs
    /// [`diffusion_derivative`](Self::diffusion_derivative) too.
    ///
    /// ```
    /// use mcint::multilevel::Sde;
    /// // Ornstein-Uhlenbeck: dX = -X dt + 0.3 dW.
    /// let ou = Sde::scalar(1.0, |_, x| -x, |_, _| 0.3).unwrap();
    /// assert_eq!(ou.start(), &[1.0]);
    /// assert!(Sde::scalar(f64::NAN, |_, x| -x, |_, _| 0.3).is_err());
    /// ```
    pub fn scalar(
        x0: f64,
        drift: impl Fn(f64, f64) -> f64 + Send + Sync + 'static,
        diffusion: impl Fn(f64, f64) -> f64 + Send + Sync + 'static,
    ) -> Result<Sde> {
        check_start(&[x0])?;
        Ok(Sde {
            start: vec![x0],
            drift: Arc::new(move |t, x, out| out[0] = drift(t, x[0])),
            noise: Noise::Scalar {
                diffusion: Arc::new(diffusion),
                derivative: None,
            },
        })
    }

    /// A system whose state `i` is driven by Brownian motion `i` alone:
    /// `dX_i = a_i(t, X) dt + b_i(t, X) dW_i`, from `x0` (finite). Milstein needs
    /// [`diagonal_derivative`](Self::diagonal_derivative), and is of strong order 1 when each
    /// `b_i` depends on `X_i` alone (commutative noise).
    ///
    /// ```
    /// use mcint::multilevel::Sde;
    /// // Two independent GBMs.
    /// let pair = Sde::diagonal(
    ///     vec![100.0, 50.0],
    ///     |_, x, a| { a[0] = 0.05 * x[0]; a[1] = 0.05 * x[1]; },
    ///     |_, x, b| { b[0] = 0.2 * x[0]; b[1] = 0.3 * x[1]; },
    /// ).unwrap();
    /// assert_eq!((pair.states(), pair.noises()), (2, 2));
    /// ```
    pub fn diagonal(
        x0: Vec<f64>,
        drift: impl Fn(f64, &[f64], &mut [f64]) + Send + Sync + 'static,
        diffusion: impl Fn(f64, &[f64], &mut [f64]) + Send + Sync + 'static,
    ) -> Result<Sde> {
        check_start(&x0)?;
        Ok(Sde {
            start: x0,
            drift: Arc::new(drift),
            noise: Noise::Diagonal {
                diffusion: Arc::new(diffusion),
                derivative: None,
            },
        })
    }

    /// A system of `d = x0.len()` states driven by `noises` Brownian motions through the
    /// `d x noises` matrix `b(t, X)`, written row-major. Euler steps it; Milstein needs
    /// [`milstein_terms`](Self::milstein_terms) and commutative noise.
    ///
    /// ```
    /// use mcint::multilevel::Sde;
    /// // dX = 0 dt + (dW_1 + dW_2): one state, two noises.
    /// let sum = Sde::general(vec![0.0], 2, |_, _, a| a[0] = 0.0, |_, _, b| b.fill(1.0)).unwrap();
    /// assert_eq!(sum.noises(), 2);
    /// assert!(Sde::general(vec![0.0], 0, |_, _, _| {}, |_, _, _| {}).is_err());
    /// ```
    pub fn general(
        x0: Vec<f64>,
        noises: usize,
        drift: impl Fn(f64, &[f64], &mut [f64]) + Send + Sync + 'static,
        diffusion: impl Fn(f64, &[f64], &mut [f64]) + Send + Sync + 'static,
    ) -> Result<Sde> {
        check_start(&x0)?;
        if noises == 0 {
            return Err(Error::invalid("noises", 0, "at least 1 Brownian motion"));
        }
        Ok(Sde {
            start: x0,
            drift: Arc::new(drift),
            noise: Noise::General {
                noises,
                diffusion: Arc::new(diffusion),
                milstein: None,
            },
        })
    }

    /// Geometric Brownian motion `dS = r S dt + sigma S dW` from `s0 > 0`, with the
    /// derivative Milstein needs.
    ///
    /// ```
    /// use mcint::multilevel::Sde;
    /// assert!(Sde::gbm(100.0, 0.05, 0.2).unwrap().has_milstein_terms());
    /// assert!(Sde::gbm(-1.0, 0.05, 0.2).is_err());
    /// ```
    pub fn gbm(s0: f64, rate: f64, sigma: f64) -> Result<Sde> {
        if !(s0.is_finite() && s0 > 0.0) {
            return Err(Error::invalid("s0", s0, "a finite price above 0"));
        }
        if !rate.is_finite() {
            return Err(Error::invalid("rate", rate, "a finite rate"));
        }
        if !(sigma.is_finite() && sigma >= 0.0) {
            return Err(Error::invalid(
                "sigma",
                sigma,
                "a finite volatility, at least 0",
            ));
        }
        Sde::scalar(s0, move |_, x| rate * x, move |_, x| sigma * x)?
            .diffusion_derivative(move |_, _| sigma)
    }

    /// Heston's stochastic volatility model, state `(S, v)`:
    /// `dS = r S dt + sqrt(v) S dW_1`, `dv = kappa (theta - v) dt + xi sqrt(v) dW_2` with
    /// `corr(dW_1, dW_2) = rho`, stepped with full truncation (`v` enters the coefficients as
    /// `max(v, 0)`, Lord, Koekkoek and van Dijk 2010). Euler only: its noise does not commute.
    ///
    /// ```
    /// use mcint::multilevel::Sde;
    /// let h = Sde::heston(100.0, 0.04, 0.05, 2.0, 0.04, 0.3, -0.7).unwrap();
    /// assert_eq!((h.states(), h.noises(), h.has_milstein_terms()), (2, 2, false));
    /// assert!(Sde::heston(100.0, 0.04, 0.05, 2.0, 0.04, 0.3, -1.5).is_err());
    /// ```
    #[allow(clippy::too_many_arguments)]
    pub fn heston(
        s0: f64,
        v0: f64,
        rate: f64,
        kappa: f64,
        theta: f64,
        xi: f64,
        rho: f64,
    ) -> Result<Sde> {
        if !(s0.is_finite() && s0 > 0.0) {
            return Err(Error::invalid("s0", s0, "a finite price above 0"));
        }
        for (name, value) in [("v0", v0), ("kappa", kappa), ("theta", theta), ("xi", xi)] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(Error::invalid(name, value, "a finite value, at least 0"));
            }
        }
        if !rate.is_finite() {
            return Err(Error::invalid("rate", rate, "a finite rate"));
        }
        if !(-1.0..=1.0).contains(&rho) {
            return Err(Error::invalid("rho", rho, "a correlation in [-1, 1]"));
        }
        let orthogonal = (1.0 - rho * rho).sqrt();
        Sde::general(
            vec![s0, v0],
            2,
            move |_, x, a| {
                a[0] = rate * x[0];
                a[1] = kappa * (theta - x[1].max(0.0));
            },
            move |_, x, b| {
                let vol = x[1].max(0.0).sqrt();
                b[0] = vol * x[0];
                b[1] = 0.0;
                b[2] = xi * vol * rho;
                b[3] = xi * vol * orthogonal;
            },
        )
    }

    /// The derivative `db/dx` of a scalar equation's diffusion, which Milstein needs.
    ///
    /// ```
    /// use mcint::multilevel::Sde;
    /// let cir = Sde::scalar(0.04, |_, x| 2.0 * (0.04 - x), |_, x| 0.3 * x.max(0.0).sqrt()).unwrap();
    /// assert!(!cir.has_milstein_terms());
    /// let pair = Sde::diagonal(vec![1.0], |_, _, a| a[0] = 0.0, |_, _, b| b[0] = 1.0).unwrap();
    /// assert!(pair.diffusion_derivative(|_, _| 0.0).is_err()); // not scalar
    /// ```
    pub fn diffusion_derivative(
        mut self,
        derivative: impl Fn(f64, f64) -> f64 + Send + Sync + 'static,
    ) -> Result<Sde> {
        match &mut self.noise {
            Noise::Scalar { derivative: d, .. } => *d = Some(Arc::new(derivative)),
            _ => return Err(wrong_noise("diffusion_derivative", "Sde::scalar")),
        }
        Ok(self)
    }

    /// The derivatives `d b_i / d x_i` of a diagonal system's diffusions, which Milstein
    /// needs.
    ///
    /// ```
    /// use mcint::multilevel::Sde;
    /// let pair = Sde::diagonal(vec![1.0, 2.0], |_, _, a| a.fill(0.0), |_, x, b| {
    ///     b[0] = 0.2 * x[0];
    ///     b[1] = 0.3 * x[1];
    /// })
    /// .unwrap()
    /// .diagonal_derivative(|_, _, d| { d[0] = 0.2; d[1] = 0.3; })
    /// .unwrap();
    /// assert!(pair.has_milstein_terms());
    /// ```
    pub fn diagonal_derivative(
        mut self,
        derivative: impl Fn(f64, &[f64], &mut [f64]) + Send + Sync + 'static,
    ) -> Result<Sde> {
        match &mut self.noise {
            Noise::Diagonal { derivative: d, .. } => *d = Some(Arc::new(derivative)),
            _ => return Err(wrong_noise("diagonal_derivative", "Sde::diagonal")),
        }
        Ok(self)
    }

    /// The terms `L^j b_ik = sum_r b_rj(t, x) d b_ik / d x_r (t, x)` of a general system, as a
    /// `d x m x m` array (index `(i m + j) m + k`), which Milstein needs. Milstein's scheme
    /// without Levy areas is of strong order 1 only when the noise commutes
    /// (`L^j b_ik = L^k b_ij`); the caller vouches for that.
    ///
    /// ```
    /// use mcint::multilevel::Sde;
    /// // dX = X (0.1 dW_1 + 0.2 dW_2): commutative, L^j b_k = b_j b_k / X.
    /// let two = Sde::general(vec![1.0], 2, |_, _, a| a[0] = 0.0, |_, x, b| {
    ///     b[0] = 0.1 * x[0];
    ///     b[1] = 0.2 * x[0];
    /// })
    /// .unwrap()
    /// .milstein_terms(|_, x, l| {
    ///     let s = [0.1, 0.2];
    ///     for j in 0..2 { for k in 0..2 { l[j * 2 + k] = s[j] * s[k] * x[0]; } }
    /// })
    /// .unwrap();
    /// assert!(two.has_milstein_terms());
    /// ```
    pub fn milstein_terms(
        mut self,
        terms: impl Fn(f64, &[f64], &mut [f64]) + Send + Sync + 'static,
    ) -> Result<Sde> {
        match &mut self.noise {
            Noise::General { milstein, .. } => *milstein = Some(Arc::new(terms)),
            _ => return Err(wrong_noise("milstein_terms", "Sde::general")),
        }
        Ok(self)
    }

    /// The number of states `d`.
    ///
    /// ```
    /// assert_eq!(mcint::multilevel::Sde::gbm(1.0, 0.0, 0.2).unwrap().states(), 1);
    /// ```
    pub fn states(&self) -> usize {
        self.start.len()
    }

    /// The number of independent Brownian motions `m`.
    ///
    /// ```
    /// assert_eq!(mcint::multilevel::Sde::gbm(1.0, 0.0, 0.2).unwrap().noises(), 1);
    /// ```
    pub fn noises(&self) -> usize {
        match &self.noise {
            Noise::Scalar { .. } => 1,
            Noise::Diagonal { .. } => self.start.len(),
            Noise::General { noises, .. } => *noises,
        }
    }

    /// `X(0)`.
    ///
    /// ```
    /// assert_eq!(mcint::multilevel::Sde::gbm(90.0, 0.0, 0.2).unwrap().start(), &[90.0]);
    /// ```
    pub fn start(&self) -> &[f64] {
        &self.start
    }

    /// Whether Milstein's scheme can step this equation (its derivative terms were given).
    ///
    /// ```
    /// let ou = mcint::multilevel::Sde::scalar(0.0, |_, x| -x, |_, _| 1.0).unwrap();
    /// assert!(!ou.has_milstein_terms());
    /// ```
    pub fn has_milstein_terms(&self) -> bool {
        match &self.noise {
            Noise::Scalar { derivative, .. } => derivative.is_some(),
            Noise::Diagonal { derivative, .. } => derivative.is_some(),
            Noise::General { milstein, .. } => milstein.is_some(),
        }
    }
}

fn wrong_noise(setter: &str, builder: &str) -> Error {
    Error::Unsupported {
        operation: "this derivative",
        reason: format!("{setter} applies to an equation built by {builder}"),
    }
}
