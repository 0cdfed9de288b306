//! Value stability: literal outputs that must not change by accident (as rand's
//! value-stability tests pin its generators).
//!
//! Pinned: the first two points of both the first and the second pass of every named sampler
//! (and every scramble each accepts) for two seeds, and the `mean` / `std_error` bits with the
//! counts of fixed-seed runs of every method: plain, importance, RQMC, stratified, both runs to
//! a tolerance, VEGAS, VEGAS+, MISER (fixed and to a tolerance), TwoStage, SobolG (with its
//! error bound), control variates, a checkpointed run, vector runs (plain, RQMC, VEGAS+: every
//! output, the covariance and a ratio), an expectation under geometric Brownian motion, a
//! convergence study, a mean periodogram and multilevel runs (MLMC and MLQMC).
//!
//! A change that alters any of them must say so in its commit message and update the table on
//! purpose: run
//! `MCINT_PRINT_PINS=1 cargo test --release --test contracts -- value_stability:: --nocapture`
//! and paste the printed table over [`PINS`] (a failing run prints it too).

use mcint::adaptive::{Miser, SobolG, TwoStage, Vegas};
use mcint::measure::{Construction, GeometricBrownianMotion};
use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};
use mcint::pdf::{Pdf1d, ProductPdf, TruncatedNormal, UniformBox};
use mcint::quality::{Convergence, mean_periodogram_with_threads};
use mcint::sampler::{Jittered, PassKind, Sampler, SamplerKind, Scramble, Sobol};
use mcint::stats::{Derived, Estimate, Tolerance};
use mcint::testfns::{Genz, GenzFamily, TestFunction};
use mcint::{Integrator, Result, VectorEstimate};

/// One pinned observation: a label and the values it must keep (f64 as IEEE-754 bits).
type Observation = (String, Vec<u64>);

/// Points per pass for the samplers whose pass size must have a particular form.
fn pass_points(kind: SamplerKind) -> u64 {
    match kind {
        SamplerKind::OaBose => 49,
        SamplerKind::OaBush => 125,
        _ => 64,
    }
}

/// The scrambles a named sampler accepts.
fn scrambles(kind: SamplerKind) -> Vec<Scramble> {
    match kind {
        SamplerKind::Sobol => vec![Scramble::None, Scramble::Xor, Scramble::Lms, Scramble::Owen],
        SamplerKind::Halton | SamplerKind::Hammersley => {
            vec![Scramble::None, Scramble::Permute, Scramble::Owen]
        }
        SamplerKind::Lattice => vec![Scramble::None, Scramble::Shift],
        _ => vec![Scramble::None],
    }
}

/// Index of the first point of the second pass.
fn second_pass(sampler: &dyn Sampler) -> u64 {
    match sampler.passes() {
        PassKind::Fixed { size } => size,
        PassKind::Extensible { max } => max,
        PassKind::Independent => 1 << 20,
    }
}

fn sampler_observations() -> Result<Vec<Observation>> {
    let mut out = Vec::new();
    for kind in SamplerKind::ALL {
        for scramble in scrambles(kind) {
            for seed in [0, 12345] {
                let sampler = kind.build_scrambled(3, pass_points(kind), scramble, seed)?;
                for (pass, start) in [(0, 0), (1, second_pass(sampler.as_ref()))] {
                    let mut bits = Vec::new();
                    for index in start..start + 2 {
                        let mut point = [0.0; 3];
                        sampler.point(index, &mut point)?;
                        bits.extend(point.iter().map(|x| x.to_bits()));
                    }
                    out.push((format!("{kind} {scramble} seed {seed} pass {pass}"), bits));
                }
            }
        }
    }
    Ok(out)
}

/// The bits of an estimate that must not drift (and its error bound, where it has one).
fn estimate_bits(e: &Estimate) -> Vec<u64> {
    let mut bits = vec![
        e.mean.to_bits(),
        e.std_error.map_or(u64::MAX, f64::to_bits),
        e.n,
        e.evaluations,
        e.iterations,
    ];
    bits.extend(e.error_bound.map(f64::to_bits));
    bits
}

fn genz(family: GenzFamily, dims: usize) -> Genz {
    Genz::with_defaults(family, dims).expect("valid Genz parameters")
}

fn method_observations() -> Result<Vec<Observation>> {
    let g = genz(GenzFamily::Gaussian, 3);
    let f = |x: &[f64]| g.eval(x);
    let unit = || UniformBox::unit(3);
    let unit2 = || UniformBox::unit(2);
    let mut out: Vec<Observation> = Vec::new();
    let mut pin = |label: &str, e: &Estimate| out.push((label.to_string(), estimate_bits(e)));

    let plain = Integrator::over_box(f, unit()?)
        .samples(50_000)
        .seed(1)
        .threads(2);
    pin("plain", &plain.run()?);

    // A checkpointed run: two parts merged, then finished.
    let total = plain.total_chunks()?;
    let mut part = plain.run_part(0..1)?;
    plain.resume(&mut part, total)?;
    pin("checkpointed", &plain.finish(&part)?);

    let normal =
        || -> Result<Box<dyn Pdf1d>> { Ok(Box::new(TruncatedNormal::new(0.5, 0.3, 0.0, 1.0)?)) };
    let pdf = ProductPdf::new(vec![normal()?, normal()?, normal()?])?;
    let importance = Integrator::with_pdf(f, pdf).samples(20_000).seed(2);
    pin("importance", &importance.run()?);

    let rqmc = Integrator::over_box(f, unit()?)
        .sampler(Sobol::new(3, Scramble::Owen, 0)?)
        .samples(4096)
        .replicates(8)
        .seed(3);
    pin("rqmc", &rqmc.run()?);

    let stratified = Integrator::over_box(f, unit()?)
        .sampler(Jittered::new(3, 8, 0)?)
        .replicates(8)
        .seed(4);
    pin("stratified", &stratified.run()?);

    let tolerance = Tolerance::absolute(1e-4)?;
    let plain_tol = Integrator::over_box(f, unit()?)
        .tolerance(tolerance)
        .seed(5);
    pin("plain to tolerance", &plain_tol.run()?);
    let rqmc_tol = Integrator::over_box(f, unit()?)
        .sampler(Sobol::new(3, Scramble::Owen, 0)?)
        .tolerance(Tolerance::absolute(1e-6)?)
        .seed(6);
    pin("rqmc to tolerance", &rqmc_tol.run()?);

    let vegas = Vegas::new(f, unit()?)
        .stratified(false)
        .samples(4000)
        .seed(7);
    pin("vegas", &vegas.run()?);
    let vegas_plus = Vegas::new(f, unit()?).samples(4000).seed(8);
    pin("vegas+", &vegas_plus.run()?);

    let miser = Miser::new(f, unit()?).samples(1 << 10).seed(9);
    pin("miser", &miser.run()?);
    let miser_tol = Miser::new(f, unit()?)
        .tolerance(Tolerance::absolute(1e-4)?)
        .seed(10);
    pin("miser to tolerance", &miser_tol.run()?);

    let two_stage = TwoStage::new(f, unit()?, 4)
        .pilot(4)
        .samples(20_000)
        .seed(11);
    pin("two-stage", &two_stage.run()?);

    let sobol_g = SobolG::new(f, unit()?)
        .tolerance(Tolerance::absolute(1e-6)?)
        .seed(13);
    pin("sobol-g to tolerance", &sobol_g.run()?);

    let control = Integrator::with_controls(|x: &[f64]| x[0].exp() * x[1], unit2()?)
        .control(|x: &[f64]| x[0], 0.5)
        .control(|x: &[f64]| x[1], 0.5)
        .pilot(2000)
        .samples(20_000)
        .seed(12);
    pin("control variates", &control.run()?);
    out.push((
        "control variates: coefficients".to_string(),
        control
            .fit()?
            .coefficients
            .iter()
            .map(|c| c.to_bits())
            .collect(),
    ));

    // Vector runs: every output's bits, the covariance and a ratio.
    let two = |x: &[f64], y: &mut [f64]| {
        y[0] = g.eval(x);
        y[1] = x[0] * y[0];
    };
    let mut pin_vector = |label: &str, run: &VectorEstimate| -> Result<()> {
        let mut bits: Vec<u64> = run.outputs.iter().flat_map(estimate_bits).collect();
        bits.extend(run.covariance_matrix.iter().flatten().map(|c| c.to_bits()));
        bits.extend(estimate_bits(&run.derived(&Derived::ratio(1, 0))?));
        out.push((label.to_string(), bits));
        Ok(())
    };
    let plain_vector = Integrator::over_box_vector(2, two, unit()?)
        .samples(50_000)
        .seed(13)
        .threads(2);
    pin_vector("vector plain", &plain_vector.run()?)?;
    let rqmc_vector = Integrator::over_box_vector(2, two, unit()?)
        .sampler(Sobol::new(3, Scramble::Owen, 0)?)
        .samples(4096)
        .replicates(8)
        .seed(14);
    pin_vector("vector rqmc", &rqmc_vector.run()?)?;
    let vegas_vector = Vegas::new_vector(2, two, unit()?).samples(4000).seed(15);
    pin_vector("vector vegas+", &vegas_vector.run()?)?;

    // An expectation under a measure: an Asian payoff over Brownian-bridge paths, by RQMC.
    let times: Vec<f64> = (1..=8).map(|i| f64::from(i) / 8.0).collect();
    let paths = GeometricBrownianMotion::new(100.0, 0.05, 0.2, times, Construction::Bridge)?;
    let asian = |s: &[f64]| (s.iter().sum::<f64>() / 8.0 - 100.0).max(0.0);
    let expectation = Integrator::expectation(asian, paths)
        .sampler(Sobol::new(8, Scramble::Owen, 0)?)
        .samples(1024)
        .replicates(8)
        .seed(16);
    out.push((
        "expectation gbm bridge rqmc".into(),
        estimate_bits(&expectation.run()?),
    ));

    // Multilevel runs: a lookback by MLMC, an Asian call by MLQMC.
    for (label, payoff, qmc) in [
        ("multilevel mc lookback", Payoff::lookback(), false),
        ("multilevel qmc asian", Payoff::asian_call(100.0)?, true),
    ] {
        let levels = SdeLevels::new(Sde::gbm(100.0, 0.05, 0.2)?, Scheme::Milstein, payoff, 1.0)?;
        let run = Multilevel::new(levels).rmse(0.2).qmc(qmc).seed(17).run()?;
        let mut bits = vec![
            run.estimate.to_bits(),
            run.std_error.to_bits(),
            run.bias.to_bits(),
        ];
        bits.extend(run.levels.iter().map(|l| l.samples));
        out.push((label.to_string(), bits));
    }
    Ok(out)
}

fn quality_observations() -> Result<Vec<Observation>> {
    let g = genz(GenzFamily::Oscillatory, 2);
    let study = Convergence::new(&g, &[16, 64, 256])
        .passes(8)
        .seed(13)
        .run(|_, seed| Sobol::new(2, Scramble::Owen, seed))?;
    let mut out = vec![(
        "convergence study".to_string(),
        study
            .points
            .iter()
            .flat_map(|p| [p.rmse.to_bits(), p.mean_error.to_bits()])
            .chain([study.slope.to_bits()])
            .collect(),
    )];
    let sobol = Sobol::new(2, Scramble::Owen, 14)?;
    let spectrum = mean_periodogram_with_threads(&sobol, 256, 4, 4, 2)?;
    out.push((
        "mean periodogram".to_string(),
        spectrum.values().iter().map(|v| v.to_bits()).collect(),
    ));
    Ok(out)
}

/// The three groups run side by side (each run is deterministic on its own), so that a debug
/// build, where this is the slowest test, does not hold one core for all of them.
fn observations() -> Vec<Observation> {
    std::thread::scope(|scope| {
        let samplers = scope.spawn(|| sampler_observations().expect("every named sampler builds"));
        let quality = scope.spawn(|| quality_observations().expect("quality measures run"));
        let methods = method_observations().expect("every method runs");
        let mut all = samplers
            .join()
            .unwrap_or_else(|p| std::panic::resume_unwind(p));
        all.extend(methods);
        all.extend(
            quality
                .join()
                .unwrap_or_else(|p| std::panic::resume_unwind(p)),
        );
        all
    })
}

fn print_table(observed: &[Observation]) {
    println!("const PINS: &[(&str, &[u64])] = &[");
    for (label, bits) in observed {
        let values: Vec<String> = bits.iter().map(|b| format!("{b:#018x}")).collect();
        println!("    ({label:?}, &[{}]),", values.join(", "));
    }
    println!("];");
}

#[test]
fn outputs_match_the_pinned_values() {
    let observed = observations();
    if std::env::var_os("MCINT_PRINT_PINS").is_some() {
        print_table(&observed);
    }
    let mut differ = Vec::new();
    for (label, bits) in &observed {
        match PINS.iter().find(|(l, _)| l == label) {
            Some((_, pinned)) if pinned == &bits.as_slice() => {}
            Some(_) => differ.push(format!("changed: {label}")),
            None => differ.push(format!("not pinned: {label}")),
        }
    }
    for (label, _) in PINS {
        if !observed.iter().any(|(l, _)| l == label) {
            differ.push(format!("no longer observed: {label}"));
        }
    }
    if !differ.is_empty() {
        print_table(&observed);
        panic!(
            "{} pinned outputs differ (the table above is the new one):\n{}",
            differ.len(),
            differ.join("\n")
        );
    }
}

/// One line per observation: `(label, values)`.
#[rustfmt::skip]
const PINS: &[(&str, &[u64])] = &[
    ("independent none seed 0 pass 0", &[0x3fd50a82581f3ed0, 0x3fc9a5d476c9ee6c, 0x3fe7f77b91a3f5ac, 0x3fe3a841bbd1ae8d, 0x3fee3ef74565501c, 0x3fe921c91ff3060a]),
    ("independent none seed 0 pass 1", &[0x3fdbf9759ce38f70, 0x3fe6aa8fd155ef81, 0x3fd35486bf00daca, 0x3fe0144b8aa234b1, 0x3fe691f165c202dc, 0x3fe24fb4c0b2242c]),
    ("independent none seed 12345 pass 0", &[0x3feeafd63309bec9, 0x3fca0b37828ceef0, 0x3fde0467b047a53c, 0x3fd0c7a4f2d873ba, 0x3fd81c4ef07608b6, 0x3fc81824e067f3f8]),
    ("independent none seed 12345 pass 1", &[0x3fe125affb0cbf39, 0x3fc4697b504ece88, 0x3fe2f1916ecc52da, 0x3fcf71bcd9a736c8, 0x3fe6cea04d91f978, 0x3fc5aa8253e42e58]),
    ("jittered none seed 0 pass 0", &[0x3fb3b614bc2e6aa4, 0x3fbe0108917df760, 0x3fcff23bdc7ccc3a, 0x3fddf0aea28574f9, 0x3fac7e41e05d3c70, 0x3f703586b47872c0]),
    ("jittered none seed 0 pass 1", &[0x3fbbd8f6ad6c5bd8, 0x3f7bdaf9618f8d60, 0x3fca27783e72a2cb, 0x3fdfad371fdb04e6, 0x3fc26822308dc138, 0x3fbcbb9eefc938cc]),
    ("jittered none seed 12345 pass 0", &[0x3fbdebbaeabcbdc4, 0x3fb0d5390dd98cbc, 0x3fcc15fc2b794eac, 0x3fd1f6d9b6c94b60, 0x3f960ad2717b7f58, 0x3f82648cbbf181c0]),
    ("jittered none seed 12345 pass 1", &[0x3fcf1a8667055953, 0x3fced2a99c7bf9aa, 0x3fb2b7c8cf564ede, 0x3fd809758d7e12cc, 0x3fa31bcf1bd46f40, 0x3fb403fa470221f2]),
    ("latin none seed 0 pass 0", &[0x3fd31893e58945d1, 0x3fcc2c27ce377c20, 0x3fd92b4d0b17dd93, 0x3fc2ba928f82da6c, 0x3fe9a39a20ea7aef, 0x3fe2c681a636863e]),
    ("latin none seed 0 pass 1", &[0x3fe8e209f098b06b, 0x3fe76c0cbc2dba3f, 0x3fe39d4ebe4b8a75, 0x3fe20d703cfb8f6a, 0x3fda61d056706d00, 0x3fd3e956619022ac]),
    ("latin none seed 12345 pass 0", &[0x3fef9c0d5f73a6c6, 0x3fad6f3d1224564f, 0x3fe3f51698e3ecf0, 0x3fdb20b95d69105d, 0x3fe3acc2402f3533, 0x3fc22640a562811e]),
    ("latin none seed 12345 pass 1", &[0x3fedff4f8935d45b, 0x3fe8645f5f9dba4b, 0x3fe265fc7474a932, 0x3fe157c766c8cd97, 0x3feecc1314629ace, 0x3fd78fc02611f26a]),
    ("sobol none seed 0 pass 0", &[0x0000000000000000, 0x0000000000000000, 0x0000000000000000, 0x3fe0000000000000, 0x3fe0000000000000, 0x3fe0000000000000]),
    ("sobol none seed 0 pass 1", &[0x0000000000000000, 0x0000000000000000, 0x0000000000000000, 0x3fe0000000000000, 0x3fe0000000000000, 0x3fe0000000000000]),
    ("sobol none seed 12345 pass 0", &[0x0000000000000000, 0x0000000000000000, 0x0000000000000000, 0x3fe0000000000000, 0x3fe0000000000000, 0x3fe0000000000000]),
    ("sobol none seed 12345 pass 1", &[0x0000000000000000, 0x0000000000000000, 0x0000000000000000, 0x3fe0000000000000, 0x3fe0000000000000, 0x3fe0000000000000]),
    ("sobol xor seed 0 pass 0", &[0x3f73ecf3cfaed880, 0x3fc237d3991374a4, 0x3fe428637c973bc7, 0x3fe027d9e79f5db1, 0x3fe48df4e644dd29, 0x3fc0a18df25cef1c]),
    ("sobol xor seed 0 pass 1", &[0x3fb83297eb20bea8, 0x3fdf7dc0c3d683e6, 0x3fcfb23df3a18338, 0x3fe30652fd6417d5, 0x3fefbee061eb41f3, 0x3fe7ec8f7ce860ce]),
    ("sobol xor seed 12345 pass 0", &[0x3feecb2b23dc83b7, 0x3fe63873031b990f, 0x3fe14e0bd324b89f, 0x3fdd965647b9076e, 0x3fc8e1cc0c6e643c, 0x3fa4e0bd324b89f0]),
    ("sobol xor seed 12345 pass 1", &[0x3fd794498a190654, 0x3fcba526b56aa4c4, 0x3f9facf69d0807a0, 0x3febca24c50c832a, 0x3fe6e949ad5aa931, 0x3fe0fd67b4e8403d]),
    ("sobol lms seed 0 pass 0", &[0x3fec771c4c5450d6, 0x3fea416109f78ba2, 0x3feb02403d893a39, 0x3fdaf17b4c4488fa, 0x3fd1df23e8a71aee, 0x3fcffd2961975b94]),
    ("sobol lms seed 0 pass 1", &[0x3fe9cfe81e6ffeb0, 0x3fd76a3a1e2b2f0c, 0x3fc6bb4ec3b9a7ec, 0x3fdf60903d2b3d3c, 0x3fed39cb4cc6373b, 0x3fe7a1e42c1bfee4]),
    ("sobol lms seed 12345 pass 0", &[0x3fe523a9a0e773aa, 0x3fe6f767313c2230, 0x3fee6b1e3234f397, 0x3fd5253733eba024, 0x3fbbcdad616f9e88, 0x3fd856bab9d9d662]),
    ("sobol lms seed 12345 pass 1", &[0x3fb05a9e3a9bed00, 0x3fef1bf1ce9ce23c, 0x3fee893337a3be1e, 0x3fea2ca928fe9281, 0x3fc9ca913cd21da4, 0x3fd3ac0ac3f74d6c]),
    ("sobol owen seed 0 pass 0", &[0x3fe6fb9dfba60b9a, 0x3fe5ce326e124727, 0x3fd0296bb3b0fd74, 0x3fd3813faf3f42ba, 0x3fb1a27edb9f43f0, 0x3feb70ffa87d1788]),
    ("sobol owen seed 0 pass 1", &[0x3fd2c37f5c07c7b0, 0x3fe053af745dd695, 0x3fd14e4ceb6b58e4, 0x3fe1969e9f794757, 0x3fd58546d89ae3e2, 0x3fef0f00a672bff6]),
    ("sobol owen seed 12345 pass 0", &[0x3fd6c9d785e26f7c, 0x3fe9dde801b3e3c2, 0x3fcd4c900f4bf6cc, 0x3feed9f4e6f12f8b, 0x3fd2a5742ace6f7e, 0x3feae057d6b0629a]),
    ("sobol owen seed 12345 pass 1", &[0x3fe7967b3dc31e46, 0x3fd088723c6e8228, 0x3fef1a7298a1ea8f, 0x3fa9c269a0f2a440, 0x3fe7bd3908e450dc, 0x3fbe437f47356ca0]),
    ("halton none seed 0 pass 0", &[0x0000000000000000, 0x0000000000000000, 0x0000000000000000, 0x3fe0000000000000, 0x3fd5555555555555, 0x3fc999999999999a]),
    ("halton none seed 0 pass 1", &[0x0000000000000000, 0x0000000000000000, 0x0000000000000000, 0x3fe0000000000000, 0x3fd5555555555555, 0x3fc999999999999a]),
    ("halton none seed 12345 pass 0", &[0x0000000000000000, 0x0000000000000000, 0x0000000000000000, 0x3fe0000000000000, 0x3fd5555555555555, 0x3fc999999999999a]),
    ("halton none seed 12345 pass 1", &[0x0000000000000000, 0x0000000000000000, 0x0000000000000000, 0x3fe0000000000000, 0x3fd5555555555555, 0x3fc999999999999a]),
    ("halton permute seed 0 pass 0", &[0x3fd34e2c1d5443ea, 0x3feba7acba0ed820, 0x3fea4689bc015496, 0x3fe9a7160eaa21f5, 0x3fc9495d92e60b2b, 0x3fcc4d5a2338858b]),
    ("halton permute seed 0 pass 1", &[0x3fea87bf33e55798, 0x3fd3bb43ee2bd582, 0x3fe192a3984d2687, 0x3fd50f7e67caaf30, 0x3fe4884ca1c0956c, 0x3fe7f909feb38ced]),
    ("halton permute seed 12345 pass 0", &[0x3fe5eaba1c6a12d9, 0x3fc452ec07e7b789, 0x3f6f4dd484693dcf, 0x3fc7aae871a84b64, 0x3fdf7ecb5949311a, 0x3fe9b8e76e1e02d7]),
    ("halton permute seed 12345 pass 1", &[0x3fd566ee836f5a28, 0x3fc79aa6410bb586, 0x3fe21c21ce464d2c, 0x3feab37741b7ad14, 0x3feb3bfee59842b7, 0x3fe8828834acb392]),
    ("halton owen seed 0 pass 0", &[0x3fd34e2c1d5443ea, 0x3feba7acba0ed820, 0x3fea4689bc015496, 0x3fe620ba8eda51e7, 0x3fca984393709883, 0x3fcb381321160228]),
    ("halton owen seed 0 pass 1", &[0x3fea87bf33e55798, 0x3fd3bb43ee2bd582, 0x3fe192a3984d2687, 0x3fb390c3a81c8990, 0x3fdf80288990b87e, 0x3fe794dfa81bb167]),
    ("halton owen seed 12345 pass 0", &[0x3fe5eaba1c6a12d9, 0x3fc452ec07e7b789, 0x3f6f4dd484693dcf, 0x3f8a5fca1e683280, 0x3fe1d998caee6cf2, 0x3fee008cdd8e39dd]),
    ("halton owen seed 12345 pass 1", &[0x3fd566ee836f5a28, 0x3fc79aa6410bb586, 0x3fe21c21ce464d2c, 0x3feb20865c7985c1, 0x3fefd2937446b1c1, 0x3fe85e1c5bcee27e]),
    ("hammersley none seed 0 pass 0", &[0x0000000000000000, 0x0000000000000000, 0x0000000000000000, 0x3f90000000000000, 0x3fe0000000000000, 0x3fd5555555555555]),
    ("hammersley none seed 0 pass 1", &[0x0000000000000000, 0x0000000000000000, 0x0000000000000000, 0x3f90000000000000, 0x3fe0000000000000, 0x3fd5555555555555]),
    ("hammersley none seed 12345 pass 0", &[0x0000000000000000, 0x0000000000000000, 0x0000000000000000, 0x3f90000000000000, 0x3fe0000000000000, 0x3fd5555555555555]),
    ("hammersley none seed 12345 pass 1", &[0x0000000000000000, 0x0000000000000000, 0x0000000000000000, 0x3f90000000000000, 0x3fe0000000000000, 0x3fd5555555555555]),
    ("hammersley permute seed 0 pass 0", &[0x3fec6faab00bd93b, 0x3fa7e28d54148030, 0x3fe66f3113cf90e1, 0x3fecefaab00bd93b, 0x3fe17e28d5414803, 0x3fd7890cd249cc6d]),
    ("hammersley permute seed 0 pass 1", &[0x3fee95ded6e11e75, 0x3f79f700e1ce7900, 0x3fa1d7637a0010f8, 0x3fef15ded6e11e75, 0x3fe033ee01c39cf2, 0x3fe672cb8cf55665]),
    ("hammersley permute seed 12345 pass 0", &[0x3fb11ed72ac0c03c, 0x3fea6c3381d9a671, 0x3fe08b121cbe7d80, 0x3fb51ed72ac0c03c, 0x3fd4d86703b34ce2, 0x3fc7819dc84f4b56]),
    ("hammersley permute seed 12345 pass 1", &[0x3feeb92a004d8848, 0x3fe5cf30ccb5ba21, 0x3fec54325c9fdfa9, 0x3fef392a004d8848, 0x3fc73cc332d6e884, 0x3fe1a987b1f534ff]),
    ("hammersley owen seed 0 pass 0", &[0x3fec6faab00bd93b, 0x3fa7e28d54148030, 0x3fe66f3113cf90e1, 0x3fecefaab00bd93b, 0x3fe82492ac2ae8ad, 0x3fd70b9f358fb378]),
    ("hammersley owen seed 0 pass 1", &[0x3fee95ded6e11e75, 0x3f79f700e1ce7900, 0x3fa1d7637a0010f8, 0x3fef15ded6e11e75, 0x3fe173d9bbcf0c4b, 0x3fe83cf62771c5fb]),
    ("hammersley owen seed 12345 pass 0", &[0x3fb11ed72ac0c03c, 0x3fea6c3381d9a671, 0x3fe08b121cbe7d80, 0x3fb51ed72ac0c03c, 0x3fd60f71c2e35bae, 0x3fd4b3a1467ecd48]),
    ("hammersley owen seed 12345 pass 1", &[0x3feeb92a004d8848, 0x3fe5cf30ccb5ba21, 0x3fec54325c9fdfa9, 0x3fef392a004d8848, 0x3fbd5459cfda1b90, 0x3fe1058b5abe7a53]),
    ("lattice none seed 0 pass 0", &[0x0000000000000000, 0x0000000000000000, 0x0000000000000000, 0x3fe0000000000000, 0x3fe0000000000000, 0x3fe0000000000000]),
    ("lattice none seed 0 pass 1", &[0x0000000000000000, 0x0000000000000000, 0x0000000000000000, 0x3fe0000000000000, 0x3fe0000000000000, 0x3fe0000000000000]),
    ("lattice none seed 12345 pass 0", &[0x0000000000000000, 0x0000000000000000, 0x0000000000000000, 0x3fe0000000000000, 0x3fe0000000000000, 0x3fe0000000000000]),
    ("lattice none seed 12345 pass 1", &[0x0000000000000000, 0x0000000000000000, 0x0000000000000000, 0x3fe0000000000000, 0x3fe0000000000000, 0x3fe0000000000000]),
    ("lattice shift seed 0 pass 0", &[0x3fb3c3ff24a6f9f0, 0x3fe011ec05474078, 0x3fe2124f2f677da7, 0x3fe2787fe494df3e, 0x3f61ec0547407800, 0x3fb092797b3bed38]),
    ("lattice shift seed 0 pass 1", &[0x3fe0a8ba0a5ace01, 0x3fbbe3bab59aa770, 0x3fd80c2a81913b1c, 0x3f9517414b59c020, 0x3fe37c7756b354ee, 0x3fec061540c89d8e]),
    ("lattice shift seed 12345 pass 0", &[0x3fe1775e4efc079f, 0x3fe40798300d11ec, 0x3feb707e3e246ac4, 0x3fa775e4efc079f0, 0x3fc01e60c03447b0, 0x3fd6e0fc7c48d588]),
    ("lattice shift seed 12345 pass 1", &[0x3fd233a24746c67c, 0x3fc0556e72951004, 0x3f9e199d16e514e0, 0x3fe919d123a3633e, 0x3fe4155b9ca54401, 0x3fe0f0cce8b728a7]),
    ("multijitter none seed 0 pass 0", &[0x3fddcfdce7b43483, 0x3febdc3d3ae8b576, 0x3fef93748c18dca2, 0x3fe71fd5255b9a64, 0x3fe80940aea49e7d, 0x3fe5cc02d7bf2d6e]),
    ("multijitter none seed 0 pass 1", &[0x3fdeb78aaca045f4, 0x3fdcf5dde7b0b243, 0x3fd9f1461d597ece, 0x3fe033d329fde9b3, 0x3fe24e35a02c0e8d, 0x3fe34a62f75dea00]),
    ("multijitter none seed 12345 pass 0", &[0x3fb0cf04e6cfe609, 0x3fd58c4eb4020e26, 0x3fe49aa14dde1920, 0x3fc9f35ea0bf8a1d, 0x3fe9b5b9d284ff95, 0x3fef6b70ef764e28]),
    ("multijitter none seed 12345 pass 1", &[0x3fc62288f1ee5f92, 0x3fd06272f65ddf48, 0x3fde246d077566bf, 0x3fe582c9ba3c5f2b, 0x3fe58a78458b0905, 0x3fe44db3087de8f8]),
    ("cmj none seed 0 pass 0", &[0x3fe466a00ff0f3bf, 0x3fbd037e90d7c84d, 0x3fbc65ddd4620aa9, 0x3f9cb5b3cdd33c0e, 0x3fe9c1b54087826d, 0x3fdcc180e4f6c099]),
    ("cmj none seed 0 pass 1", &[0x3fddb39cefff92f3, 0x3fc1af5cf68d57dd, 0x3fe1c6c6e60dac3d, 0x3fea62fa95e395c0, 0x3fdd7e1dfeb480b1, 0x3fda253a07392e08]),
    ("cmj none seed 12345 pass 0", &[0x3fed9789c6fe564b, 0x3fe2f3d8746d9162, 0x3fb0e020737597c6, 0x3fb1158475c1a5f5, 0x3fdb25d6e5e77bde, 0x3fe2c54dd3d965cf]),
    ("cmj none seed 12345 pass 1", &[0x3fdfb2d464872fa6, 0x3fd0b94e1be66d42, 0x3fd697c49a04cd4f, 0x3f8266ac894ae600, 0x3fcf08aa71aec8fe, 0x3fcf4cdb98da5420]),
    ("oa-bose none seed 0 pass 0", &[0x3fecf4314b99c15f, 0x3f7b8b9f9497e1f0, 0x3feb3c649eaae1d1, 0x3fb6b6b9ee584f70, 0x3fd14fab10ea898d, 0x3fe5972df92a5511]),
    ("oa-bose none seed 0 pass 1", &[0x3fdc7a79eb73040c, 0x3fecc71c9fa88712, 0x3fdb83ef8ec4aa45, 0x3fe90250e24668fc, 0x3fe0ff4ae7d2bd3b, 0x3fd68b3ea45cfdd1]),
    ("oa-bose none seed 12345 pass 0", &[0x3fb1f33fcdce9fca, 0x3fc24e6c88b13190, 0x3fe55421862b12b3, 0x3fecc747e32b45e3, 0x3fe016969c3e3f19, 0x3fb29337efe2f011]),
    ("oa-bose none seed 12345 pass 1", &[0x3fc39fc0a8a5870e, 0x3fd4d2ce0df19414, 0x3fd6482c0e1be594, 0x3fd627ef68b03c21, 0x3fe2cbdc978f3e65, 0x3fee9b49f9bc462b]),
    ("oa-bush none seed 0 pass 0", &[0x3fe37b6a8ece6180, 0x3fef9c4103b24ece, 0x3fbfca734b2e1517, 0x3fda758ca0d7251b, 0x3fb4666acd283bfc, 0x3fedf3dc896fec26]),
    ("oa-bush none seed 0 pass 1", &[0x3fdb423ad994f1fc, 0x3fdd3555a523cc10, 0x3fea93a2158ab438, 0x3fc712e5ac1ff233, 0x3fdc83c502b116b2, 0x3fcbc14d8541288c]),
    ("oa-bush none seed 12345 pass 0", &[0x3fe10b059c5522df, 0x3feb9e8c00bfbab7, 0x3feaabd318772e46, 0x3feb8f1675439b7d, 0x3fd0c9d7b04f60db, 0x3feb23eecbabba70]),
    ("oa-bush none seed 12345 pass 1", &[0x3fe5ee9acfe255be, 0x3fdc4095b24016f8, 0x3fee2fccd9d998a8, 0x3fca31b20cf5981b, 0x3fee611369e7e69a, 0x3fe835d5f0f4d1bc]),
    ("nrooks-multistage none seed 0 pass 0", &[0x3fa85bd1ee28b362, 0x3fcfcd29156bcc04, 0x3fe6b4c1e8f4668a, 0x3fef95e4dfdef5f4, 0x3fef2d4756356b06, 0x3fdafb8fad671607]),
    ("nrooks-multistage none seed 0 pass 1", &[0x3fe7e32e403b9183, 0x3fce408de46a4ada, 0x3fddc04ce9654bdc, 0x3fd9569991d6ceb4, 0x3fecfdae5feb4a4d, 0x3fe82d409901b480]),
    ("nrooks-multistage none seed 12345 pass 0", &[0x3fe137067b244e3a, 0x3fe4d6b1727b0ff8, 0x3feadd709a238828, 0x3fb3b43f2d4b937b, 0x3fbb422b30d3a6dd, 0x3fdb770cfba2eb48]),
    ("nrooks-multistage none seed 12345 pass 1", &[0x3fdab447b5042c61, 0x3fda1be7db8b6542, 0x3fed484fdac7abec, 0x3fe35f43f351c553, 0x3fe358b6a3d078f0, 0x3fb3af06d656ee52]),
    ("poisson none seed 0 pass 0", &[0x3feeaf0d2f42de22, 0x3fd241ab5f8802a0, 0x3fe2b648e6912ed6, 0x3fecc4910b4cfe42, 0x3fe4716a07ef2d2e, 0x3fe1aa4548457c20]),
    ("poisson none seed 0 pass 1", &[0x3fd0389e70b93ecc, 0x3fe93b7159028aee, 0x3fcf8ef803382ed8, 0x3fc8aee9abefdaa8, 0x3fe2ecb327be683b, 0x3fd34c0751b47510]),
    ("poisson none seed 12345 pass 0", &[0x3fe0f8419d0135b2, 0x3fef2b71321ba3d5, 0x3fd7d78cf95f27b0, 0x3fcea2141aa67ae0, 0x3fe685cefb0336fc, 0x3fe82df6dccbb2e6]),
    ("poisson none seed 12345 pass 1", &[0x3fd15901aa7e4cc0, 0x3f8b2fb5f507a400, 0x3fe29370ce9d755a, 0x3feae6164d97b1e5, 0x3fde1ed66870461a, 0x3fedbfd79d98c35f]),
    ("best-candidate none seed 0 pass 0", &[0x3fb5f0916c651970, 0x3fd2671606e6fe00, 0x3febed5435e3ae8d, 0x3fc3154bd6961898, 0x3fef15f47600d444, 0x3fc089c97e51f8f0]),
    ("best-candidate none seed 0 pass 1", &[0x3fde82d23abd726c, 0x3fd9802ccbcdcd5c, 0x3fe750a19bec2f34, 0x3fe9f021b822095f, 0x3fe9c4b7473f1d6a, 0x3fd16029dbb9aae0]),
    ("best-candidate none seed 12345 pass 0", &[0x3fecee2ce9ee7ba4, 0x3fee29b7b10232cd, 0x3fe580bc0be27679, 0x3fcd9f37d0f1afa8, 0x3fd0b1e1fa0df390, 0x3fc3422118375968]),
    ("best-candidate none seed 12345 pass 1", &[0x3feafe6b93189b8a, 0x3fe5647c78081a5b, 0x3fb41fe57f47f840, 0x3fdf3b5f52042914, 0x3fefcf070cd04488, 0x3fe6b933e1ce9f7c]),
    ("pmj02 none seed 0 pass 0", &[0x3fefd257ee9a9650, 0x3fbc461261bc7930, 0x3fd688099f7c09c2, 0x3fd6a185864f422c, 0x3fe7e5b23fe3ec4d, 0x3fe979c2173ea111]),
    ("pmj02 none seed 0 pass 1", &[0x3fe91fc9a45bc20e, 0x3fedc65d3d4a1e24, 0x3fe738225881fa65, 0x3fc56aa8e4b0175c, 0x3fd6b57ba51211c4, 0x3fc7e316c39af114]),
    ("pmj02 none seed 12345 pass 0", &[0x3fde14e27bf02a36, 0x3fd35fdd8742e106, 0x3fe1fe4e693a47b2, 0x3fe54a05361b5763, 0x3fe299f6ae37cd11, 0x3fd3a0429eb415ce]),
    ("pmj02 none seed 12345 pass 1", &[0x3f5d9057f4b3fa00, 0x3fd3175d07c7d172, 0x3fe550aeac569b2f, 0x3fef4c8fd0c015fd, 0x3feecf13b976e9c8, 0x3fd295d09fa51d8a]),
    ("plain", &[0x3fdc9ba3d7700c72, 0x3f533f2ebcf5c5dc, 0x000000000000c350, 0x000000000000c350, 0x0000000000000001]),
    ("checkpointed", &[0x3fdc9ba3d7700c72, 0x3f533f2ebcf5c5dc, 0x000000000000c350, 0x000000000000c350, 0x0000000000000001]),
    ("importance", &[0x3fdcdc40fe5f7400, 0x3f6773d53134f759, 0x0000000000004e20, 0x0000000000004e20, 0x0000000000000001]),
    ("rqmc", &[0x3fdc9f9bc1edc425, 0x3ec57c5f27cb2b15, 0x0000000000008000, 0x0000000000008000, 0x0000000000000001]),
    ("stratified", &[0x3fdc962206cc9a91, 0x3f41e43f4baa7ab9, 0x0000000000001000, 0x0000000000001000, 0x0000000000000001]),
    ("plain to tolerance", &[0x3fdc9dd20e6c2d01, 0x3f08700f46c8836a, 0x0000000001e3af41, 0x0000000001e3bf41, 0x0000000000000002]),
    ("rqmc to tolerance", &[0x3fdc9f9dcfdab694, 0x3e8e5a117663c64e, 0x0000000000020000, 0x0000000000020000, 0x0000000000000005]),
    ("vegas", &[0x3fdca03758e6d472, 0x3f2930caa96fb9ad, 0x0000000000009c40, 0x000000000000ea60, 0x000000000000000a]),
    ("vegas+", &[0x3fdca19d8c88e943, 0x3f1259a1a643997a, 0x0000000000008f94, 0x000000000000d701, 0x000000000000000a]),
    ("miser", &[0x3fdc6ab0d0ae6488, 0x3f659e229cb4cb14, 0x0000000000004000, 0x0000000000004000, 0x0000000000000001]),
    ("miser to tolerance", &[0x3fdc9f25c41df7e0, 0x3f003e64892a9c26, 0x0000000001000000, 0x0000000001fc0000, 0x0000000000000007]),
    ("two-stage", &[0x3fdc97db99c083bf, 0x3f4348ab5aacba38, 0x0000000000004d20, 0x0000000000004e20, 0x0000000000000002]),
    ("sobol-g to tolerance", &[0x3fdc9f9ff5145c5b, 0xffffffffffffffff, 0x0000000000020000, 0x0000000000020000, 0x0000000000000008, 0x3eaff95de2bd12a0]),
    ("control variates", &[0x3feb7330db9965e5, 0x3f50c84009c1528d, 0x0000000000004e20, 0x00000000000055f0, 0x0000000000000001]),
    ("control variates: coefficients", &[0x3feba2386655738b, 0x3ffbd6001a8b7756]),
    ("vector plain", &[0x3fdcb47e04c30ae3, 0x3f5349bdf3a1271f, 0x000000000000c350, 0x000000000000c350, 0x0000000000000001, 0x3fca009a299e75da, 0x3f467dd1f0c88748, 0x000000000000c350, 0x000000000000c350, 0x0000000000000001, 0x3eb7407700bcf5ac, 0x3e9b943ec2d66a01, 0x3e9b943ec2d66a01, 0x3e9f9ddec13c61e6, 0x3fdcfcb0b736a190, 0x3f569c9b8008e45a, 0x000000000000c350, 0x000000000000c350, 0x0000000000000001]),
    ("vector rqmc", &[0x3fdc9f9ecd95b18e, 0x3eae6fb90b66ca26, 0x0000000000008000, 0x0000000000008000, 0x0000000000000001, 0x3fc9f60e7fe20f3f, 0x3ebb910285e910d1, 0x0000000000008000, 0x0000000000008000, 0x0000000000000001, 0x3d6cf301054ddffa, 0x3d16ab8ce50d59b7, 0x3d16ab8ce50d59b7, 0x3d87bf4560d70f77, 0x3fdd0609ad2cfd27, 0x3ecfab0724a16645, 0x0000000000008000, 0x0000000000008000, 0x0000000000000001]),
    ("vector vegas+", &[0x3fdc9e9ecc1a0063, 0x3f1cfbfa74e20907, 0x0000000000008f69, 0x000000000000d6ca, 0x000000000000000a, 0x3fc9f85460db2873, 0x3f1412238eff9352, 0x0000000000008f69, 0x000000000000d6ca, 0x000000000000000a, 0x3e4a40b6753d6db1, 0xbe109b18c41667d4, 0xbe109b18c41667d4, 0x3e392d6d75cfb5f5, 0x3fdd0997e7280ea2, 0x3f2c32e7680e18ef, 0x0000000000008f69, 0x000000000000d6ca, 0x000000000000000a]),
    ("expectation gbm bridge rqmc", &[0x401ab87b5c3daafc, 0x3f6e68e92d523f12, 0x0000000000002000, 0x0000000000002000, 0x0000000000000001]),
    ("convergence study", &[0x3f83db2ba3b88382, 0x3f632d1b69732dc0, 0x3f4cb3794ee57184, 0xbf39756ebee25800, 0x3f2b2b59bc649f42, 0xbf03bbc2e5a02000, 0xbff630bf778d37fa]),
    ("mean periodogram", &[0x3fddbf5bb72d0496, 0x3fe15fd94c5a40c0, 0x3fc61fee5650d016, 0x3f8f65989fbdbc24, 0x3f5260740c4e089c, 0x3f9d36032e4411cd, 0x3fc98da99ed08b5c, 0x3fcb64d768d8d3d5, 0x3fe64d5949c75d38, 0x3fd7453a801ea41d, 0x3fbeaf0787fdd5c7, 0x3fa64abb2e887f36, 0x3fa65ea067b08d2c, 0x3f2f069cfc7651be, 0x3fa022e47efad9d3, 0x3fb018decc905f17, 0x3fba58062f2466bd, 0x3fd0e6313af0288a, 0x3fb7d1f18fbca8ba, 0x3fb670b3a53ce8d1, 0x3f9a9aa1e059df4a, 0x3f7dd3472c84eafd, 0x3f29a9b1ab1f4d9e, 0x3f805afecb8baf1b, 0x3f9552fef6add2da, 0x3faef8f936b75882, 0x3fa31a2a8909a4cf, 0x3fa1fe7e70ece96b, 0x3f8775e756316db7, 0x3f9a09eb7d47a057, 0x3f55404637cb6aad, 0x3f072d255d372ab3, 0x3f567b59b48cc19e, 0x3f994a129d8020e1, 0x3fa2bddc600856a8, 0x3faa5749f92449f1, 0x3f37b9e6a4b21e8e, 0x3f21553e2eb7f961, 0x3f2badb59b9962d6, 0x3f0851acdeaac6cc, 0x4070000000000000, 0x3f0851acdeaac6cc, 0x3f2badb59b9962d6, 0x3f21553e2eb7f961, 0x3f37b9e6a4b21e8e, 0x3faa5749f92449f1, 0x3fa2bddc600856a8, 0x3f994a129d8020e1, 0x3f567b59b48cc19e, 0x3f072d255d372ab3, 0x3f55404637cb6aad, 0x3f9a09eb7d47a057, 0x3f8775e756316db7, 0x3fa1fe7e70ece96b, 0x3fa31a2a8909a4cf, 0x3faef8f936b75882, 0x3f9552fef6add2da, 0x3f805afecb8baf1b, 0x3f29a9b1ab1f4d9e, 0x3f7dd3472c84eafd, 0x3f9a9aa1e059df4a, 0x3fb670b3a53ce8d1, 0x3fb7d1f18fbca8ba, 0x3fd0e6313af0288a, 0x3fba58062f2466bd, 0x3fb018decc905f17, 0x3fa022e47efad9d3, 0x3f2f069cfc7651be, 0x3fa65ea067b08d2c, 0x3fa64abb2e887f36, 0x3fbeaf0787fdd5c7, 0x3fd7453a801ea41d, 0x3fe64d5949c75d38, 0x3fcb64d768d8d3d5, 0x3fc98da99ed08b5c, 0x3f9d36032e4411cd, 0x3f5260740c4e089c, 0x3f8f65989fbdbc24, 0x3fc61fee5650d016, 0x3fe15fd94c5a40c0, 0x3fddbf5bb72d0496]),
    ("multilevel mc lookback", &[0x40322d58f08fea00, 0x3fc15a3b0c24e0a1, 0x3fc060acc121309a, 0x0000000000003aec, 0x00000000000003e8, 0x00000000000003e8, 0x000000000000007d, 0x0000000000000032]),
    ("multilevel qmc asian", &[0x40173250a102ce3e, 0x3fc17c6f6804fd72, 0x3fb79fd676ff0ea3, 0x0000000000000200, 0x0000000000000100, 0x0000000000000100, 0x0000000000000100]),
];
