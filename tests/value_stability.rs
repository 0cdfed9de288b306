//! Value stability: literal outputs that must not change by accident (as rand's
//! value-stability tests pin its generators).
//!
//! Pinned: the first two points of both the first and the second pass of every named sampler
//! (and every scramble each accepts) for two seeds, and the `mean` / `std_error` bits with the
//! counts of fixed-seed runs of every method: plain, importance, RQMC, stratified, both runs to
//! a tolerance, VEGAS, VEGAS+, MISER (fixed and to a tolerance), TwoStage, control
//! variates, a checkpointed run, a convergence study and a mean periodogram.
//!
//! A change that alters any of them must say so in its commit message and update the table on
//! purpose: run `MCINT_PRINT_PINS=1 cargo test --release --test value_stability -- --nocapture`
//! and paste the printed table over [`PINS`] (a failing run prints it too).

use mcint::adaptive::{Miser, TwoStage, Vegas};
use mcint::pdf::{Pdf1d, ProductPdf, TruncatedNormal, UniformBox};
use mcint::quality::{Convergence, mean_periodogram_with_threads};
use mcint::sampler::{Jittered, PassKind, Sampler, SamplerKind, Scramble, Sobol};
use mcint::stats::{Estimate, Tolerance};
use mcint::testfns::{Genz, GenzFamily, TestFunction};
use mcint::{Integrator, Result};

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

/// The bits of an estimate that must not drift.
fn estimate_bits(e: &Estimate) -> Vec<u64> {
    vec![
        e.mean.to_bits(),
        e.std_error.map_or(u64::MAX, f64::to_bits),
        e.n,
        e.evaluations,
        e.iterations,
    ]
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

fn observations() -> Vec<Observation> {
    let mut all = sampler_observations().expect("every named sampler builds");
    all.extend(method_observations().expect("every method runs"));
    all.extend(quality_observations().expect("quality measures run"));
    all
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
    ("jittered none seed 0 pass 0", &[0x3fc84278b34c9b39, 0x3f8e70cb56699720, 0x3f9ff137eaf92ad8, 0x3fdf62a82ac0c450, 0x3f899617ac024de0, 0x3faf27225a549300]),
    ("jittered none seed 0 pass 1", &[0x3fca57a9c40876e9, 0x3fc3f22ce99e6e9b, 0x3fcca81f2a996128, 0x3fdbf29b8de518ba, 0x3f9a9fc150ab42d8, 0x3fcea40cf6c844ee]),
    ("jittered none seed 12345 pass 0", &[0x3fa7023f70adec34, 0x3fbfaad4f6669b08, 0x3fc096efdead75b9, 0x3fd4cb0866f5ebd3, 0x3fb128875d7e4b9e, 0x3fb0c5beff7685c2]),
    ("jittered none seed 12345 pass 1", &[0x3fc8417fa3139441, 0x3fc246b2d55e967a, 0x3fc5063edcaa78eb, 0x3fd8150d05ea9266, 0x3fc69c7d59a268d3, 0x3fa7f8857ebeb51c]),
    ("latin none seed 0 pass 0", &[0x3fd3c213c59a64da, 0x3fcc1e70cb566997, 0x3fd91ff137eaf92b, 0x3fc3ec550558188a, 0x3fe9866585eb0093, 0x3fe29f27225a5493]),
    ("latin none seed 0 pass 1", &[0x3fe8e95ea71021dc, 0x3fe74fc8b3a679ba, 0x3fe3f2a07caa6585, 0x3fe25f94dc6f28c6, 0x3fda1a9fc150ab43, 0x3fd3f52067b64227]),
    ("latin none seed 12345 pass 0", &[0x3fef97023f70adec, 0x3fabf55a9eccd361, 0x3fe3c25bbf7ab5d7, 0x3fdb4cb0866f5ebd, 0x3fe3a2510ebafc97, 0x3fc2862df7fbb42e]),
    ("latin none seed 12345 pass 1", &[0x3fede105fe8c4e51, 0x3fe8491acb557a5a, 0x3fe25418fb72a9e4, 0x3fe140a8682f5493, 0x3feeda71f56689a3, 0x3fd72ff10afd7d6a]),
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
    ("multijitter none seed 0 pass 0", &[0x3fddc213c59a64da, 0x3feb879c32d59a66, 0x3fef8ff89bf57c95, 0x3fe77b1541560622, 0x3fe8066585eb0093, 0x3fe59f27225a5493]),
    ("multijitter none seed 0 pass 1", &[0x3fded2bd4e2043b7, 0x3fdc9f91674cf375, 0x3fd9e540f954cb09, 0x3fe05f94dc6f28c6, 0x3fe20d4fe0a855a1, 0x3fe37a9033db2114]),
    ("multijitter none seed 12345 pass 0", &[0x3fb0b811fb856f62, 0x3fd57eab53d99a6c, 0x3fe4c25bbf7ab5d7, 0x3fc899610cdebd7a, 0x3fe9a2510ebafc97, 0x3fef218b7dfeed0c]),
    ("multijitter none seed 12345 pass 1", &[0x3fc78417fa313944, 0x3fd0923596aaf4b4, 0x3fdea831f6e553c7, 0x3fe5c0a8682f5493, 0x3fe5da71f56689a3, 0x3fe417f8857ebeb5]),
    ("cmj none seed 0 pass 0", &[0x3fe46109e2cd326d, 0x3fbc3ce196acd32e, 0x3fbc7fc4dfabe4ab, 0x3f9f62a82ac0c450, 0x3fe9866585eb0093, 0x3fdc3e4e44b4a926]),
    ("cmj none seed 0 pass 1", &[0x3fddd2bd4e2043b7, 0x3fc13f22ce99e6ea, 0x3fe1f2a07caa6585, 0x3fea5f94dc6f28c6, 0x3fdd1a9fc150ab43, 0x3fdaf52067b64227]),
    ("cmj none seed 12345 pass 0", &[0x3fed97023f70adec, 0x3fe2bf55a9eccd36, 0x3fb212ddfbd5aeb7, 0x3fb132c219bd7af5, 0x3fdb44a21d75f92e, 0x3fe2a18b7dfeed0c]),
    ("cmj none seed 12345 pass 1", &[0x3fdfc20bfd189ca2, 0x3fd0923596aaf4b4, 0x3fd6a831f6e553c7, 0x3f802a1a0bd524cb, 0x3fcf69c7d59a268d, 0x3fce5fe215fafad4]),
    ("oa-bose none seed 0 pass 0", &[0x3feb649183d0df27, 0x3fe14888df4f4be5, 0x3fcd484cd46102bd, 0x3feffc088986f18a, 0x3fe3e465a9870750, 0x3fd03c162ca9dcba]),
    ("oa-bose none seed 0 pass 1", &[0x3fe4203c3e9edb63, 0x3fe88d462672cf34, 0x3feef4b2674cd0a5, 0x3fdebdf3d2f1d93b, 0x3fe029789b05643d, 0x3fe39eefe31f3158]),
    ("oa-bose none seed 12345 pass 0", &[0x3fed15670370bc55, 0x3fe5a6fc50148e76, 0x3fe3e4ae608f92ce, 0x3fedbabdf1d8efe6, 0x3fe7476a2602eaaf, 0x3fcce4b81cc37763]),
    ("oa-bose none seed 12345 pass 1", &[0x3f9f021260d648ea, 0x3fc6495a60955101, 0x3fe513e330e12703, 0x3fe64b197a27f50a, 0x3fe86387533334aa, 0x3feb7fa1685daa28]),
    ("oa-bush none seed 0 pass 0", &[0x3fc15a1b769f9327, 0x3fda59a29a9847cb, 0x3feec60fb8a733fb, 0x3fa0496cd766f118, 0x3fe2ce448609ec57, 0x3fd9d1ec05385892]),
    ("oa-bush none seed 0 pass 1", &[0x3fbf7d5fd3b5f308, 0x3fd93ce2881a7249, 0x3fd55569cafd4d5c, 0x3fdabc1cca8670b3, 0x3fe2bfbe1008ee96, 0x3fd97b72f83fb67a]),
    ("oa-bush none seed 12345 pass 0", &[0x3fdf816b62f40863, 0x3fd282eaad5ffd00, 0x3fe392fcad0514af, 0x3fe4deb4f44ee535, 0x3fe7b7a47d7e1245, 0x3fef3f5fddf46f8a]),
    ("oa-bush none seed 12345 pass 1", &[0x3fd479095a876642, 0x3fe6d2365f74c01e, 0x3fc31ded719c6054, 0x3fe946eca30ea308, 0x3fe8c7b51415d2ba, 0x3fdd457fd00d85b9]),
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
    ("stratified", &[0x3fdc98b9d91adbed, 0x3f4135c44dce9fc6, 0x0000000000001000, 0x0000000000001000, 0x0000000000000001]),
    ("plain to tolerance", &[0x3fdc9dd20e6c2d01, 0x3f08700f46c8836a, 0x0000000001e3af41, 0x0000000001e3bf41, 0x0000000000000002]),
    ("rqmc to tolerance", &[0x3fdc9f9ebf173ab3, 0x3e8c8c3a7104b4b2, 0x0000000000040000, 0x0000000000040000, 0x0000000000000005]),
    ("vegas", &[0x3fdca053c9201e03, 0x3f292ab048cbac0d, 0x0000000000009c40, 0x000000000000ea60, 0x000000000000000a]),
    ("vegas+", &[0x3fdca1a23282820f, 0x3f11889f06ac91bc, 0x0000000000008f83, 0x000000000000d6f4, 0x000000000000000a]),
    ("miser", &[0x3fdc6ab0d0ae6488, 0x3f659e229cb4cb14, 0x0000000000004000, 0x0000000000004000, 0x0000000000000001]),
    ("miser to tolerance", &[0x3fdc9f25c41df7e0, 0x3f003e64892a9c26, 0x0000000001000000, 0x0000000001fc0000, 0x0000000000000007]),
    ("two-stage", &[0x3fdc97db99c083bf, 0x3f4348ab5aacba38, 0x0000000000004d20, 0x0000000000004e20, 0x0000000000000002]),
    ("control variates", &[0x3feb7330db9965e5, 0x3f50c84009c1528d, 0x0000000000004e20, 0x00000000000055f0, 0x0000000000000001]),
    ("control variates: coefficients", &[0x3feba2386655738b, 0x3ffbd6001a8b7756]),
    ("convergence study", &[0x3f83db2ba3b88382, 0x3f632d1b69732dc0, 0x3f4cb3794ee57184, 0xbf39756ebee25800, 0x3f2b2b59bc649f42, 0xbf03bbc2e5a02000, 0xbff630bf778d37fa]),
    ("mean periodogram", &[0x3fddbf5bb72d0496, 0x3fe15fd94c5a40c0, 0x3fc61fee5650d016, 0x3f8f65989fbdbc24, 0x3f5260740c4e089c, 0x3f9d36032e4411cd, 0x3fc98da99ed08b5c, 0x3fcb64d768d8d3d5, 0x3fe64d5949c75d38, 0x3fd7453a801ea41d, 0x3fbeaf0787fdd5c7, 0x3fa64abb2e887f36, 0x3fa65ea067b08d2c, 0x3f2f069cfc7651be, 0x3fa022e47efad9d3, 0x3fb018decc905f17, 0x3fba58062f2466bd, 0x3fd0e6313af0288a, 0x3fb7d1f18fbca8ba, 0x3fb670b3a53ce8d1, 0x3f9a9aa1e059df4a, 0x3f7dd3472c84eafd, 0x3f29a9b1ab1f4d9e, 0x3f805afecb8baf1b, 0x3f9552fef6add2da, 0x3faef8f936b75882, 0x3fa31a2a8909a4cf, 0x3fa1fe7e70ece96b, 0x3f8775e756316db7, 0x3f9a09eb7d47a057, 0x3f55404637cb6aad, 0x3f072d255d372ab3, 0x3f567b59b48cc19e, 0x3f994a129d8020e1, 0x3fa2bddc600856a8, 0x3faa5749f92449f1, 0x3f37b9e6a4b21e8e, 0x3f21553e2eb7f961, 0x3f2badb59b9962d6, 0x3f0851acdeaac6cc, 0x4070000000000000, 0x3f0851acdeaac6cc, 0x3f2badb59b9962d6, 0x3f21553e2eb7f961, 0x3f37b9e6a4b21e8e, 0x3faa5749f92449f1, 0x3fa2bddc600856a8, 0x3f994a129d8020e1, 0x3f567b59b48cc19e, 0x3f072d255d372ab3, 0x3f55404637cb6aad, 0x3f9a09eb7d47a057, 0x3f8775e756316db7, 0x3fa1fe7e70ece96b, 0x3fa31a2a8909a4cf, 0x3faef8f936b75882, 0x3f9552fef6add2da, 0x3f805afecb8baf1b, 0x3f29a9b1ab1f4d9e, 0x3f7dd3472c84eafd, 0x3f9a9aa1e059df4a, 0x3fb670b3a53ce8d1, 0x3fb7d1f18fbca8ba, 0x3fd0e6313af0288a, 0x3fba58062f2466bd, 0x3fb018decc905f17, 0x3fa022e47efad9d3, 0x3f2f069cfc7651be, 0x3fa65ea067b08d2c, 0x3fa64abb2e887f36, 0x3fbeaf0787fdd5c7, 0x3fd7453a801ea41d, 0x3fe64d5949c75d38, 0x3fcb64d768d8d3d5, 0x3fc98da99ed08b5c, 0x3f9d36032e4411cd, 0x3f5260740c4e089c, 0x3f8f65989fbdbc24, 0x3fc61fee5650d016, 0x3fe15fd94c5a40c0, 0x3fddbf5bb72d0496]),
];
