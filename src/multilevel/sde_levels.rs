//! [`SdeLevels`]: the levels of an SDE's time discretization, each sample a fine path and a
//! coarse path driven by the same Brownian increments, and a payoff of both.

use std::sync::OnceLock;

use super::payoff::PathRecord;
use super::sde::Noise;
use super::{Level, Payoff, Scheme, Sde};
use crate::Points;
use crate::error::{Error, Result};
use crate::measure::{BrownianMotion, Construction, standard_normal};

/// The most levels an [`SdeLevels`] builds (level `l` has `base_steps * M^l` time steps).
const LEVELS: usize = 40;

/// The levels of [`Sde`] paths on `[0, T]` under a [`Scheme`], with a [`Payoff`]: level `l`
/// takes `n_l = base_steps * M^l` steps of `h_l = T / n_l`, and its coarse path takes
/// `n_l / M` steps driven by sums of `M` fine Brownian increments (Giles 2008). The Brownian
/// paths are built from the canonical point by a Brownian bridge, noise by noise with their
/// coordinates interleaved, so that the first coordinates carry the most variance (what makes
/// multilevel QMC pay off; the law is the same for independent points).
///
/// ```
/// use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};
/// let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
/// let call = SdeLevels::new(gbm, Scheme::Milstein, Payoff::european_call(100.0).unwrap(), 1.0)
///     .unwrap()
///     .discount((-0.05f64).exp())
///     .unwrap();
/// let run = Multilevel::new(call).rmse(0.05).seed(7).run().unwrap();
/// assert!((run.estimate - 10.450583572185565).abs() < 0.2, "{run}");
/// ```
pub struct SdeLevels {
    sde: Sde,
    scheme: Scheme,
    payoff: Payoff,
    maturity: f64,
    refinement: u32,
    base_steps: usize,
    discount: f64,
    /// The Brownian bridge of each level, built when first used.
    bridges: Vec<OnceLock<Option<BrownianMotion>>>,
}

impl std::fmt::Debug for SdeLevels {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SdeLevels")
            .field("sde", &self.sde)
            .field("scheme", &self.scheme)
            .field("payoff", &self.payoff)
            .field("maturity", &self.maturity)
            .field("refinement", &self.refinement)
            .field("base_steps", &self.base_steps)
            .field("discount", &self.discount)
            .finish()
    }
}

impl SdeLevels {
    /// The levels of `sde` up to `maturity` under `scheme` (Milstein needs the equation's
    /// derivative terms), with `payoff`; refinement factor 2, one step at level 0, no
    /// discounting. The maturity is finite and at least [`SdeLevels::SHORTEST_MATURITY`].
    ///
    /// ```
    /// use mcint::multilevel::{Payoff, Scheme, Sde, SdeLevels};
    /// let ou = Sde::scalar(0.0, |_, x| -x, |_, _| 1.0).unwrap();
    /// let err = SdeLevels::new(ou, Scheme::Milstein, Payoff::lookback(), 1.0).unwrap_err();
    /// assert!(err.to_string().contains("diffusion_derivative"), "{err}");
    /// ```
    pub fn new(sde: Sde, scheme: Scheme, payoff: Payoff, maturity: f64) -> Result<SdeLevels> {
        if !(maturity.is_finite() && maturity >= Self::SHORTEST_MATURITY) {
            return Err(Error::invalid(
                "maturity",
                maturity,
                "a finite time of at least 2^26 * f64::MIN_POSITIVE, about 1.49e-300 (so that \
                 every level's time step is a normal float)",
            ));
        }
        if scheme == Scheme::Milstein && !sde.has_milstein_terms() {
            let setter = match sde.noise {
                Noise::Scalar { .. } => "diffusion_derivative",
                Noise::Diagonal { .. } => "diagonal_derivative",
                Noise::General { .. } => "milstein_terms (for commutative noise)",
            };
            return Err(Error::invalid(
                "scheme",
                "milstein",
                format!("euler, or milstein once the equation has its {setter}"),
            ));
        }
        let (d, m) = (sde.states(), sde.noises());
        let coefficients = milstein_len(&sde.noise, scheme, d, m)
            .zip(d.checked_mul(m))
            .and_then(|(terms, diffusion)| terms.checked_add(diffusion))
            .filter(|&len| len <= MAX_COEFFICIENTS);
        if coefficients.is_none() {
            return Err(Error::invalid(
                "sde",
                format!("{d} states and {m} Brownian motions under {scheme:?}"),
                "at most 2^24 values in one step's coefficients (d * m, plus d * m * m for \
                 Milstein on general noise), which each thread keeps",
            ));
        }
        Ok(SdeLevels {
            sde,
            scheme,
            payoff,
            maturity,
            refinement: 2,
            base_steps: 1,
            discount: 1.0,
            bridges: (0..LEVELS).map(|_| OnceLock::new()).collect(),
        })
    }

    /// The shortest maturity: its time grids of up to 2^26 steps (more than a level can be
    /// sampled with) have normal time steps, so their dates are distinct and every level's
    /// Brownian bridge can be built.
    ///
    /// ```
    /// use mcint::multilevel::{Payoff, Scheme, Sde, SdeLevels};
    /// let call = |t| SdeLevels::new(Sde::gbm(100.0, 0.05, 0.2)?, Scheme::Euler, Payoff::lookback(), t);
    /// assert!(call(SdeLevels::SHORTEST_MATURITY).is_ok());
    /// assert!(call(1e-320).unwrap_err().to_string().contains("maturity"));
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub const SHORTEST_MATURITY: f64 = MAX_BRIDGE_STEPS as f64 * f64::MIN_POSITIVE;

    /// The refinement factor `M` between levels: 2 to 16 (default 2; Giles 2008 used 4).
    ///
    /// ```
    /// use mcint::multilevel::{Level, Payoff, Scheme, Sde, SdeLevels};
    /// let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// let levels = SdeLevels::new(gbm, Scheme::Euler, Payoff::european_call(100.0).unwrap(), 1.0)
    ///     .unwrap();
    /// assert_eq!(levels.refinement_factor(4).unwrap().dims(2), 16);
    /// ```
    pub fn refinement_factor(mut self, m: u32) -> Result<SdeLevels> {
        if !(2..=16).contains(&m) {
            return Err(Error::invalid("refinement", m, "2 to 16 (usually 2 or 4)"));
        }
        self.refinement = m;
        Ok(self)
    }

    /// The time steps of level 0 (at least 1; default 1).
    ///
    /// ```
    /// use mcint::multilevel::{Level, Payoff, Scheme, Sde, SdeLevels};
    /// let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// let levels = SdeLevels::new(gbm, Scheme::Euler, Payoff::european_call(100.0).unwrap(), 1.0)
    ///     .unwrap();
    /// assert_eq!(levels.base_steps(4).unwrap().dims(1), 8);
    /// ```
    pub fn base_steps(mut self, steps: usize) -> Result<SdeLevels> {
        if !(1..=1 << 20).contains(&steps) {
            return Err(Error::invalid("base_steps", steps, "1 to 2^20"));
        }
        self.base_steps = steps;
        Ok(self)
    }

    /// A factor every payoff is multiplied by (`exp(-r T)` for a price; default 1). It must
    /// be finite: a NaN or infinite factor would make every sample non-finite.
    ///
    /// ```
    /// use mcint::multilevel::{Level, Payoff, Scheme, Sde, SdeLevels};
    /// let gbm = Sde::gbm(100.0, 0.05, 0.0).unwrap(); // no noise: S(1) = 105
    /// let call = || SdeLevels::new(gbm.clone(), Scheme::Euler, Payoff::european_call(100.0)?, 1.0);
    /// let levels = call().unwrap().discount(0.5).unwrap();
    /// assert_eq!(levels.sample(0, &[0.5], &mut Vec::new()).0, 2.5);
    /// assert!(call().unwrap().discount(f64::INFINITY).is_err());
    /// ```
    pub fn discount(mut self, factor: f64) -> Result<SdeLevels> {
        if !factor.is_finite() {
            return Err(Error::invalid(
                "discount",
                factor,
                "a finite factor (exp(-r T) for a price)",
            ));
        }
        self.discount = factor;
        Ok(self)
    }

    /// The time steps of level `level`'s fine path (saturating).
    fn steps(&self, level: usize) -> usize {
        u32::try_from(level)
            .ok()
            .and_then(|l| (self.refinement as usize).checked_pow(l))
            .and_then(|p| p.checked_mul(self.base_steps))
            .unwrap_or(usize::MAX)
    }

    /// The standard Brownian bridge on the fine times of `level`, if it can be built.
    fn bridge(&self, level: usize) -> Option<&BrownianMotion> {
        let cell = self.bridges.get(level)?;
        cell.get_or_init(|| {
            let n = self.steps(level);
            if n > MAX_BRIDGE_STEPS {
                return None;
            }
            let h = self.maturity / n as f64;
            let times = (1..=n).map(|k| k as f64 * h).collect();
            BrownianMotion::new(times, 0.0, 1.0, Construction::Bridge).ok()
        })
        .as_ref()
    }
}

/// The most steps of a level's bridge: more than a sampler gives coordinates
/// ([`Multilevel`](super::Multilevel) samples at most 2^24 per sample).
const MAX_BRIDGE_STEPS: usize = 1 << 26;

/// The most values one step's coefficients may hold (128 MiB of f64 per thread).
const MAX_COEFFICIENTS: usize = 1 << 24;

/// The values of one step's Milstein terms: `d * m * m` for general noise, `d` for diagonal
/// noise, none for scalar noise or Euler; `None` on overflow.
fn milstein_len(noise: &Noise, scheme: Scheme, d: usize, m: usize) -> Option<usize> {
    match (scheme, noise) {
        (Scheme::Milstein, Noise::General { .. }) => d.checked_mul(m)?.checked_mul(m),
        (Scheme::Milstein, Noise::Diagonal { .. }) => Some(d),
        _ => Some(0),
    }
}

/// The coefficients of one step, kept between the step and the payoff's bridge.
struct Coefficients<'a> {
    drift: &'a mut [f64],
    diffusion: &'a mut [f64],
    milstein: &'a mut [f64],
}

impl SdeLevels {
    /// Steps `x` from `t` by `h` with Brownian increments `dw`; the coefficients stay in `c`.
    /// Returns the first state's drift and the volatility of its Brownian part.
    fn step(&self, t: f64, h: f64, x: &mut [f64], dw: &[f64], c: &mut Coefficients) -> (f64, f64) {
        (self.sde.drift)(t, x, c.drift);
        let milstein = self.scheme == Scheme::Milstein;
        match &self.sde.noise {
            Noise::Scalar {
                diffusion,
                derivative,
            } => {
                let b = diffusion(t, x[0]);
                c.diffusion[0] = b;
                let mut dx = c.drift[0] * h + b * dw[0];
                if let (true, Some(db)) = (milstein, derivative) {
                    dx += 0.5 * b * db(t, x[0]) * (dw[0] * dw[0] - h);
                }
                x[0] += dx;
                (c.drift[0], b.abs())
            }
            Noise::Diagonal {
                diffusion,
                derivative,
            } => {
                // One value per state (the arrays hold the general case's d x m).
                let d = x.len();
                diffusion(t, x, &mut c.diffusion[..d]);
                let terms = match (milstein, derivative) {
                    (true, Some(db)) => {
                        db(t, x, &mut c.milstein[..d]);
                        true
                    }
                    _ => false,
                };
                for (i, xi) in x.iter_mut().enumerate() {
                    let b = c.diffusion[i];
                    let mut dx = c.drift[i] * h + b * dw[i];
                    if terms {
                        dx += 0.5 * b * c.milstein[i] * (dw[i] * dw[i] - h);
                    }
                    *xi += dx;
                }
                (c.drift[0], c.diffusion[0].abs())
            }
            Noise::General {
                noises,
                diffusion,
                milstein: terms,
            } => {
                let m = *noises;
                diffusion(t, x, c.diffusion);
                let terms = match (milstein, terms) {
                    (true, Some(l)) => {
                        l(t, x, c.milstein);
                        true
                    }
                    _ => false,
                };
                for (i, xi) in x.iter_mut().enumerate() {
                    let row = &c.diffusion[i * m..(i + 1) * m];
                    let mut dx =
                        c.drift[i] * h + row.iter().zip(dw).map(|(b, w)| b * w).sum::<f64>();
                    if terms {
                        for j in 0..m {
                            for k in 0..m {
                                let square = dw[j] * dw[k] - if j == k { h } else { 0.0 };
                                dx += 0.5 * c.milstein[(i * m + j) * m + k] * square;
                            }
                        }
                    }
                    *xi += dx;
                }
                let row0 = &c.diffusion[..m];
                (c.drift[0], row0.iter().map(|b| b * b).sum::<f64>().sqrt())
            }
        }
    }

    /// The coefficient of Brownian motion `j` in the first state's step just taken.
    fn first_row(&self, c: &Coefficients, j: usize) -> f64 {
        match &self.sde.noise {
            Noise::Scalar { .. } => c.diffusion[0],
            Noise::Diagonal { .. } => {
                if j == 0 {
                    c.diffusion[0]
                } else {
                    0.0
                }
            }
            Noise::General { .. } => c.diffusion[j],
        }
    }
}

/// The next `len` values of `rest`.
fn take<'a>(rest: &mut &'a mut [f64], len: usize) -> &'a mut [f64] {
    let (head, tail) = std::mem::take(rest).split_at_mut(len);
    *rest = tail;
    head
}

/// What every sample of one level shares: its sizes, its time steps and its bridge, worked
/// out once for a block of samples.
struct Shape<'a> {
    level: usize,
    bridge: &'a BrownianMotion,
    /// Fine steps, noises, states and the refinement factor.
    n: usize,
    m: usize,
    d: usize,
    big_m: usize,
    /// The values of one step's Milstein terms.
    milstein: usize,
    states: bool,
    with_bridge: bool,
    uniforms: bool,
}

/// A sample's working arrays, cut from the caller's scratch space once per block.
struct Buffers<'a> {
    dw: &'a mut [f64],
    bridge_in: &'a mut [f64],
    bridge_out: &'a mut [f64],
    own_f: &'a mut [f64],
    sigma_f: &'a mut [f64],
    own_c: &'a mut [f64],
    grid_c: &'a mut [f64],
    sigma_c: &'a mut [f64],
    states_f: &'a mut [f64],
    states_c: &'a mut [f64],
    x: &'a mut [f64],
    c: Coefficients<'a>,
    dw_coarse: &'a mut [f64],
}

impl Shape<'_> {
    /// The canonical coordinates of a sample: `n * m` normals (by the inverse cdf), then
    /// the payoff's uniforms, if it takes any.
    fn coordinates(&self) -> usize {
        self.n * self.m + if self.uniforms { self.n } else { 0 }
    }

    /// A sample's coordinates `u` with the inverse normal cdf applied to its noises.
    fn normals_of(&self, u: &[f64], z: &mut [f64]) {
        let noises = self.n * self.m;
        for (z, &u) in z[..noises].iter_mut().zip(&u[..noises]) {
            *z = standard_normal(u);
        }
        let width = z.len();
        z[noises..].copy_from_slice(&u[noises..width]);
    }

    /// Cuts `scratch` into the arrays of one sample of this level, and `extra` values more.
    fn buffers<'s>(&self, scratch: &'s mut Vec<f64>, extra: usize) -> (Buffers<'s>, &'s mut [f64]) {
        let (n, m, d, big_m) = (self.n, self.m, self.d, self.big_m);
        let state_len = if self.states { (n + 1) * d } else { 0 };
        let coarse_states = if self.states { (n / big_m + 1) * d } else { 0 };
        let sizes = [
            n * m,                                        // fine Brownian increments
            2 * n,                                        // bridge input and output
            n + 1,                                        // fine path
            n,                                            // fine volatilities
            n / big_m + 1,                                // coarse path
            if self.with_bridge { 2 * n + 1 } else { 0 }, // coarse path and volatility, fine grid
            state_len + coarse_states,
            d + d + d * m + self.milstein + m, // state and coefficients, coarse increments
        ];
        scratch.resize(sizes.iter().sum::<usize>() + extra, 0.0);
        let mut rest = scratch.as_mut_slice();
        let dw = take(&mut rest, sizes[0]);
        let (bridge_in, bridge_out) = take(&mut rest, sizes[1]).split_at_mut(n);
        let own_f = take(&mut rest, sizes[2]);
        let sigma_f = take(&mut rest, sizes[3]);
        let own_c = take(&mut rest, sizes[4]);
        let (grid_c, sigma_c) =
            take(&mut rest, sizes[5]).split_at_mut(if self.with_bridge { n + 1 } else { 0 });
        let (states_f, states_c) = take(&mut rest, sizes[6]).split_at_mut(state_len);
        let x = take(&mut rest, d);
        let c = Coefficients {
            drift: take(&mut rest, d),
            diffusion: take(&mut rest, d * m),
            milstein: take(&mut rest, self.milstein),
        };
        let dw_coarse = take(&mut rest, m);
        let buffers = Buffers {
            dw,
            bridge_in,
            bridge_out,
            own_f,
            sigma_f,
            own_c,
            grid_c,
            sigma_c,
            states_f,
            states_c,
            x,
            c,
            dw_coarse,
        };
        (buffers, rest)
    }
}

impl SdeLevels {
    /// The shape of level `level`, if its bridge can be built.
    fn shape(&self, level: usize) -> Option<Shape<'_>> {
        Some(Shape {
            level,
            bridge: self.bridge(level)?,
            n: self.steps(level),
            m: self.sde.noises(),
            d: self.sde.states(),
            big_m: self.refinement as usize,
            // Bounded by `new`.
            milstein: milstein_len(
                &self.sde.noise,
                self.scheme,
                self.sde.states(),
                self.sde.noises(),
            )
            .unwrap_or(0),
            states: self.payoff.needs_states(),
            with_bridge: self.payoff.needs_bridge(),
            uniforms: self.payoff.needs_uniforms(),
        })
    }

    /// The fine and coarse payoffs of the sample whose coordinates are `z` (see
    /// [`Shape::normals_of`]).
    fn sample_with(&self, shape: &Shape, z: &[f64], b: &mut Buffers) -> (f64, f64) {
        let (n, m, d, big_m) = (shape.n, shape.m, shape.d, shape.big_m);
        let (states, with_bridge) = (shape.states, shape.with_bridge);
        for j in 0..m {
            for (k, v) in b.bridge_in.iter_mut().enumerate() {
                *v = z[k * m + j];
            }
            shape.bridge.map_normals(b.bridge_in, b.bridge_out);
            let mut previous = 0.0;
            for (k, &w) in b.bridge_out.iter().enumerate() {
                b.dw[k * m + j] = w - previous;
                previous = w;
            }
        }
        let uniforms = if shape.uniforms {
            &z[n * m..n * m + n]
        } else {
            &[][..]
        };

        // The fine path.
        let h = self.maturity / n as f64;
        let x = &mut *b.x;
        x.copy_from_slice(&self.sde.start);
        b.own_f[0] = x[0];
        if states {
            b.states_f[..d].copy_from_slice(x);
        }
        let mut last_f = (0.0, 0.0);
        for k in 0..n {
            let before = x[0];
            let (drift, sigma) = self.step(k as f64 * h, h, x, &b.dw[k * m..(k + 1) * m], &mut b.c);
            b.sigma_f[k] = sigma;
            b.own_f[k + 1] = x[0];
            if states {
                b.states_f[(k + 1) * d..(k + 2) * d].copy_from_slice(x);
            }
            if k + 1 == n {
                last_f = (before + drift * h, sigma * h.sqrt());
            }
        }
        if !x.iter().all(|v| v.is_finite()) {
            // A state that left the reals (a square root of a negative, an overflow): the
            // payoffs' comparisons would read it as out of the money.
            return (f64::NAN, f64::NAN);
        }
        let fine = PathRecord {
            own: b.own_f,
            own_step: h,
            grid: b.own_f,
            sigma: b.sigma_f,
            fine_step: h,
            uniforms,
            last_step: last_f,
            states: b.states_f,
            dims: d,
        };
        let fine = self.discount * self.payoff.value(&fine);
        if shape.level == 0 {
            return (fine, 0.0);
        }

        // The coarse path, on the sums of M fine increments.
        let nc = n / big_m;
        let hc = h * big_m as f64;
        let dw = &*b.dw;
        let dw_coarse = &mut *b.dw_coarse;
        x.copy_from_slice(&self.sde.start);
        b.own_c[0] = x[0];
        if with_bridge {
            b.grid_c[0] = x[0];
        }
        if states {
            b.states_c[..d].copy_from_slice(x);
        }
        let mut last_c = (0.0, 0.0);
        for s in 0..nc {
            let first = s * big_m;
            dw_coarse.fill(0.0);
            for i in 0..big_m {
                for (j, w) in dw_coarse.iter_mut().enumerate() {
                    *w += dw[(first + i) * m + j];
                }
            }
            let before = x[0];
            let (drift, sigma) = self.step(s as f64 * hc, hc, x, dw_coarse, &mut b.c);
            b.own_c[s + 1] = x[0];
            if states {
                b.states_c[(s + 1) * d..(s + 2) * d].copy_from_slice(x);
            }
            if with_bridge {
                // The coarse path at the fine times: its bridge, pinned to the fine increments.
                for i in 1..big_m {
                    let theta = i as f64 / big_m as f64;
                    let mut value = before + theta * (x[0] - before);
                    for j in 0..m {
                        let partial: f64 = (0..i).map(|q| dw[(first + q) * m + j]).sum();
                        value += self.first_row(&b.c, j) * (partial - theta * dw_coarse[j]);
                    }
                    b.grid_c[first + i] = value;
                }
                b.grid_c[first + big_m] = x[0];
                b.sigma_c[first..first + big_m].fill(sigma);
            }
            if s + 1 == nc {
                let mut mean = before + drift * hc;
                for j in 0..m {
                    mean += self.first_row(&b.c, j) * (dw_coarse[j] - dw[(n - 1) * m + j]);
                }
                last_c = (mean, sigma * h.sqrt());
            }
        }
        if !x.iter().all(|v| v.is_finite()) {
            return (fine, f64::NAN);
        }
        let coarse = PathRecord {
            own: b.own_c,
            own_step: hc,
            grid: b.grid_c,
            sigma: b.sigma_c,
            fine_step: h,
            uniforms,
            last_step: last_c,
            states: b.states_c,
            dims: d,
        };
        (fine, self.discount * self.payoff.value(&coarse))
    }
}

impl Level for SdeLevels {
    fn refinement(&self) -> u32 {
        self.refinement
    }

    fn dims(&self, level: usize) -> usize {
        let per_step = self.sde.noises() + usize::from(self.payoff.needs_uniforms());
        self.steps(level).saturating_mul(per_step)
    }

    fn cost(&self, level: usize) -> f64 {
        let n = self.steps(level) as f64;
        if level == 0 {
            n
        } else {
            n + n / f64::from(self.refinement)
        }
    }

    /// Euler and Milstein both have weak order 1 in the time step.
    fn weak_order(&self) -> Option<f64> {
        Some(1.0)
    }

    fn fine_cost(&self, level: usize) -> f64 {
        self.steps(level) as f64
    }

    fn sample(&self, level: usize, u: &[f64], scratch: &mut Vec<f64>) -> (f64, f64) {
        let Some(shape) = self.shape(level) else {
            return (f64::NAN, f64::NAN);
        };
        let (mut buffers, z) = shape.buffers(scratch, shape.coordinates());
        shape.normals_of(u, z);
        self.sample_with(&shape, z, &mut buffers)
    }

    /// The samples of a block, with the level's shape and working arrays set up once (at the
    /// first levels, where a path takes a step or two, the setup cost as much as the path),
    /// and the block's normals drawn in one pass (independent inverse cdfs that the CPU
    /// overlaps, where one path's wait on each other).
    fn sample_block(
        &self,
        level: usize,
        points: &Points,
        fine: &mut [f64],
        coarse: &mut [f64],
        scratch: &mut Vec<f64>,
    ) {
        let len = points.len().min(fine.len()).min(coarse.len());
        let Some(shape) = self.shape(level) else {
            fine[..len].fill(f64::NAN);
            coarse[..len].fill(f64::NAN);
            return;
        };
        let width = shape.coordinates();
        let (mut buffers, z) = shape.buffers(scratch, width * len);
        let noises = shape.n * shape.m;
        for dim in 0..width {
            let column = &points.column(dim)[..len];
            let rows = z.chunks_exact_mut(width);
            if dim < noises {
                for (row, &u) in rows.zip(column) {
                    row[dim] = standard_normal(u);
                }
            } else {
                for (row, &u) in rows.zip(column) {
                    row[dim] = u;
                }
            }
        }
        for (i, z) in z.chunks_exact(width).enumerate() {
            (fine[i], coarse[i]) = self.sample_with(&shape, z, &mut buffers);
        }
    }
}
