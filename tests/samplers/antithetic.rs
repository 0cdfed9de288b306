//! Antithetic variates (Hammersley & Morton 1956) as a sampler wrapper.
//!
//! - Every coordinate stays in `[0, 1)`, including reflections of 0 and of extreme values.
//! - Per-point and batch access give identical bits (random starts, ragged lengths, several
//!   inner samplers), and odd points are exact reflections of the even ones.
//! - Pass structure: pairs are one pass (`Fixed { size: 2 }`), fixed passes double, extensible
//!   ones double their maximum.
//! - The estimate is unbiased; for the monotone `e^x` the variance of a pair mean is the closed
//!   form `(Var f + Cov(f(U), f(1-U))) / 2`, far below the `Var f / 2` of two independent
//!   points; for the symmetric `(x - 1/2)^2` it is `Var f`, twice as bad. Tolerances are
//!   4.5 standard errors of the sample variance, `sqrt((mu_4 - sigma^4) / M)`, with fourth
//!   moments by composite Simpson quadrature.

use crate::common::{ONE_BELOW, config, integrate01};
use mcint::pdf::UniformBox;
use mcint::sampler::{
    Antithetic, Independent, Jittered, LatinHypercube, PassKind, Sampler, Scramble, Sobol, reflect,
};
use mcint::{Error, Integrator, Points};
use proptest::prelude::*;
use std::f64::consts::E;

/// A sampler of awkward coordinates (zero, the largest value below one, subnormals, values off
/// the 2^-53 grid), cycling with the index, with a configurable pass kind.
#[derive(Debug, Clone)]
struct Awkward {
    passes: PassKind,
}

const AWKWARD: [f64; 8] = [0.0, ONE_BELOW, 5e-324, 0.5, 1e-17, 0.1, 1e-300, 0.7];

impl Sampler for Awkward {
    fn name(&self) -> &'static str {
        "awkward"
    }
    fn dims(&self) -> usize {
        2
    }
    fn passes(&self) -> PassKind {
        self.passes
    }
    fn seed(&self) -> u64 {
        0
    }
    fn reseed(&mut self, _seed: u64) {}
    fn point(&self, index: u64, out: &mut [f64]) -> mcint::Result<()> {
        out[0] = AWKWARD[(index % 8) as usize];
        out[1] = AWKWARD[((index + 3) % 8) as usize];
        Ok(())
    }
}

fn inners() -> Vec<Box<dyn Sampler>> {
    vec![
        Box::new(Independent::new(3, 1).unwrap()),
        Box::new(Jittered::new(2, 5, 2).unwrap()),
        Box::new(LatinHypercube::new(3, 7, 3).unwrap()),
        Box::new(Sobol::new(2, Scramble::Owen, 4).unwrap()),
        Box::new(Awkward {
            passes: PassKind::Independent,
        }),
    ]
}

#[test]
fn coordinates_stay_in_the_unit_interval() {
    for inner in inners() {
        let name = inner.name();
        let s = Antithetic::new(inner).unwrap();
        let mut block = Points::new(s.dims(), 4097).unwrap();
        s.fill(1, &mut block).unwrap();
        for dim in 0..s.dims() {
            for &u in block.column(dim) {
                assert!((0.0..1.0).contains(&u), "{name}: {u}");
            }
        }
    }
    for u in AWKWARD {
        let v = reflect(u);
        assert!((0.0..1.0).contains(&v), "reflect({u}) = {v}");
    }
    assert_eq!(reflect(0.0), ONE_BELOW);
    assert_eq!(reflect(ONE_BELOW), 0.0);
}

#[test]
fn pairs_reflect_exactly() {
    // On the 2^-53 grid (independent points) the reflection is exact: u + v = 1 - 2^-53.
    let inner = Independent::new(3, 17).unwrap();
    let s = Antithetic::new(inner.clone()).unwrap();
    let (mut a, mut b, mut original) = ([0.0; 3], [0.0; 3], [0.0; 3]);
    for i in 0..2000u64 {
        s.point(2 * i, &mut a).unwrap();
        s.point(2 * i + 1, &mut b).unwrap();
        inner.point(i, &mut original).unwrap();
        assert_eq!(a.map(f64::to_bits), original.map(f64::to_bits));
        for d in 0..3 {
            assert_eq!(b[d], ONE_BELOW - a[d]);
            assert_eq!(a[d] + b[d], ONE_BELOW);
            assert_eq!(reflect(b[d]), a[d]); // an involution on the grid
        }
    }
    // Off the grid (jittered coordinates), the reflection is 1 - u to within 2^-53.
    let s = Antithetic::new(Jittered::new(2, 8, 5).unwrap()).unwrap();
    for i in 0..64u64 {
        s.point(2 * i, &mut a[..2]).unwrap();
        s.point(2 * i + 1, &mut b[..2]).unwrap();
        for d in 0..2 {
            assert_eq!(b[d], reflect(a[d]));
            assert!((b[d] - (1.0 - a[d])).abs() <= f64::EPSILON);
        }
    }
}

proptest! {
    #![proptest_config(config(200, 0xa971))]

    /// `fill` gives the same bits as `point` for any start (near zero or anywhere in the
    /// index range, odd or even) and any length.
    #[test]
    fn point_and_fill_are_bit_identical(
        which in 0usize..5,
        small in any::<bool>(),
        start in any::<u64>(),
        len in 0usize..300,
    ) {
        let s = Antithetic::new(inners().swap_remove(which)).unwrap();
        let start = if small { start % 1000 } else { start.min(u64::MAX - len as u64) };
        let mut block = Points::new(s.dims(), len).unwrap();
        s.fill(start, &mut block).unwrap();
        let mut p = vec![0.0; s.dims()];
        for i in 0..len {
            s.point(start + i as u64, &mut p).unwrap();
            for (d, &u) in p.iter().enumerate() {
                prop_assert_eq!(u.to_bits(), block.get(i, d).to_bits(), "point {} dim {}", i, d);
            }
        }
    }
}

#[test]
fn passes_group_the_pairs() {
    fn pass(s: impl Sampler) -> PassKind {
        Antithetic::new(s).unwrap().passes()
    }
    assert_eq!(
        pass(Independent::new(1, 0).unwrap()),
        PassKind::Fixed { size: 2 }
    );
    assert_eq!(
        pass(Jittered::new(2, 5, 0).unwrap()),
        PassKind::Fixed { size: 50 }
    );
    assert_eq!(
        pass(Sobol::new(2, Scramble::Owen, 0).unwrap()),
        PassKind::Extensible { max: 1 << 33 }
    );
    // A pass size whose double does not fit is rejected, for fixed and extensible passes.
    for passes in [
        PassKind::Fixed {
            size: u64::MAX / 2 + 1,
        },
        PassKind::Extensible { max: u64::MAX },
    ] {
        let err = Antithetic::new(Awkward { passes }).err().unwrap();
        assert!(err.to_string().contains("pass size"), "{err}");
    }
    assert!(
        Antithetic::new(Awkward {
            passes: PassKind::Fixed { size: u64::MAX / 2 }
        })
        .is_ok()
    );
}

#[test]
fn seed_and_randomization_are_delegated() {
    let mut s = Antithetic::new(Independent::new(2, 3).unwrap()).unwrap();
    assert_eq!((s.name(), s.dims(), s.seed()), ("antithetic", 2, 3));
    let mut before = [0.0; 2];
    s.point(0, &mut before).unwrap();
    s.reseed(4);
    assert_eq!(s.seed(), 4);
    let mut after = [0.0; 2];
    s.point(0, &mut after).unwrap();
    assert_ne!(before, after);
    assert_eq!(s.inner(), &Independent::new(2, 4).unwrap());
    assert!(s.is_randomized());
    let plain = Antithetic::new(Sobol::new(2, Scramble::None, 0).unwrap()).unwrap();
    assert!(!plain.is_randomized());
    // Wrong buffer sizes are errors, not panics.
    assert!(matches!(
        s.point(0, &mut [0.0; 3]),
        Err(Error::DimensionMismatch { .. })
    ));
    assert!(s.fill(0, &mut Points::new(1, 4).unwrap()).is_err());
    assert!(s.fill(u64::MAX, &mut Points::new(2, 2).unwrap()).is_err());
}

#[test]
fn the_integrator_needs_whole_pairs() {
    let err = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap())
        .sampler(Antithetic::new(Independent::new(1, 0).unwrap()).unwrap())
        .samples(3)
        .run()
        .err()
        .unwrap();
    assert!(err.to_string().contains("pass size 2"), "{err}");
}

/// Closed forms for `f = e^x` on [0, 1]: `Var f = (e^2 - 1)/2 - (e - 1)^2` and
/// `Cov(e^U, e^(1-U)) = e - (e - 1)^2`.
/// python3 -c "import numpy as np; from scipy.integrate import quad; F=np.e-1; print(quad(lambda x: np.exp(2*x),0,1)[0]-F**2, quad(lambda x: np.e,0,1)[0]-F**2)"
/// -> 0.24203560745276542 -0.23421061355351425
const VAR_EXP: f64 = 0.24203560745276542;
const COV_EXP_ANTITHETIC: f64 = -0.23421061355351425;

/// Sample variance of `pairs` pair means, from the integrator with one pair per replicate (the
/// recipe in `Antithetic`'s documentation), and its mean.
fn pair_mean_variance(f: fn(&[f64]) -> f64, pairs: u64, seed: u64) -> (f64, f64) {
    let e = Integrator::over_box(f, UniformBox::unit(1).unwrap())
        .sampler(Antithetic::new(Independent::new(1, 0).unwrap()).unwrap())
        .samples(2)
        .replicates(pairs)
        .seed(seed)
        .threads(2)
        .run()
        .unwrap();
    assert_eq!(e.n, 2 * pairs);
    (e.mean, e.std_error.unwrap().powi(2) * pairs as f64)
}

#[test]
fn monotone_integrand_variance_per_pair_is_the_closed_form_and_below_independent() {
    assert!((VAR_EXP - ((E * E - 1.0) / 2.0 - (E - 1.0).powi(2))).abs() < 1e-15);
    assert!((COV_EXP_ANTITHETIC - (E - (E - 1.0).powi(2))).abs() < 1e-15);
    let exact = E - 1.0;
    let sigma2 = (VAR_EXP + COV_EXP_ANTITHETIC) / 2.0;
    let mu4 = integrate01(|u| ((u.exp() + (1.0 - u).exp()) / 2.0 - exact).powi(4));
    let pairs = 20_000;
    let (mean, s2) = pair_mean_variance(|x| x[0].exp(), pairs, 1);
    let tolerance = 4.5 * ((mu4 - sigma2 * sigma2) / pairs as f64).sqrt();
    assert!(
        (s2 - sigma2).abs() < tolerance,
        "variance per pair {s2}, closed form {sigma2}, tolerance {tolerance}"
    );
    assert!((mean - exact).abs() < 4.5 * (sigma2 / pairs as f64).sqrt());
    // Two independent points average to variance Var f / 2 = 0.121; a pair gives 0.0039.
    let independent = VAR_EXP / 2.0;
    assert!(s2 + tolerance < independent, "{s2} vs {independent}");
}

#[test]
fn symmetric_integrand_variance_per_pair_is_twice_independent() {
    // f = (x - 1/2)^2 = f(1 - x): a pair is one point counted twice. Var f = 1/80 - 1/144.
    let exact = 1.0 / 12.0;
    let var_f = 1.0 / 80.0 - 1.0 / 144.0;
    let mu4 = integrate01(|u| ((u - 0.5).powi(2) - exact).powi(4));
    let pairs = 20_000;
    let (mean, s2) = pair_mean_variance(|x| (x[0] - 0.5).powi(2), pairs, 2);
    let tolerance = 4.5 * ((mu4 - var_f * var_f) / pairs as f64).sqrt();
    assert!(
        (s2 - var_f).abs() < tolerance,
        "variance per pair {s2}, closed form {var_f}"
    );
    assert!((mean - exact).abs() < 4.5 * (var_f / pairs as f64).sqrt());
    let independent = var_f / 2.0;
    assert!(s2 - tolerance > independent, "{s2} vs {independent}");
}

/// Unbiased in two dimensions, with replicates of many pairs: `f = e^(x+y)`, whose integral is
/// `(e - 1)^2`, with the closed-form per-pair variance `(Var f + Cov(f(U), f(1-U))) / 2`, where
/// `Var f = ((e^2 - 1)/2)^2 - (e - 1)^4` and `Cov = e^2 - (e - 1)^4`.
#[test]
fn antithetic_estimates_are_unbiased() {
    let exact = (E - 1.0).powi(2);
    let var_f = ((E * E - 1.0) / 2.0).powi(2) - exact * exact;
    let sigma2 = (var_f + E * E - exact * exact) / 2.0;
    let (pairs_per_replicate, replicates) = (512u64, 64u64);
    let e = Integrator::over_box(
        |x: &[f64]| (x[0] + x[1]).exp(),
        UniformBox::unit(2).unwrap(),
    )
    .sampler(Antithetic::new(Independent::new(2, 0).unwrap()).unwrap())
    .samples(2 * pairs_per_replicate)
    .replicates(replicates)
    .seed(8)
    .run()
    .unwrap();
    let pairs = (pairs_per_replicate * replicates) as f64;
    assert!((e.mean - exact).abs() < 4.5 * (sigma2 / pairs).sqrt());
    assert_eq!(
        (e.replicates, e.dof),
        (replicates, Some((replicates - 1) as f64))
    );
    // The replicate error bar estimates sqrt(sigma2 / pairs): its square has 63 degrees of
    // freedom, so relative sd about sqrt(2/63) = 0.18; 4.5 of those allow 0.2x to 1.8x.
    let ratio = e.std_error.unwrap().powi(2) / (sigma2 / pairs);
    assert!(
        (ratio - 1.0).abs() < 4.5 * (2.0 / 63.0f64).sqrt(),
        "{ratio}"
    );

    // Around a stratified inner sampler too (jittered passes of 16, doubled to 32).
    let e = Integrator::over_box(|x: &[f64]| x[0].exp(), UniformBox::unit(1).unwrap())
        .sampler(Antithetic::new(Jittered::new(1, 16, 0).unwrap()).unwrap())
        .samples(32)
        .replicates(1000)
        .seed(9)
        .run()
        .unwrap();
    assert!((e.mean - (E - 1.0)).abs() < 4.5 * e.std_error.unwrap());
}
