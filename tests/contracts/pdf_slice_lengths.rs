//! The slice-length contract of `Pdf::sample`, `pdf` and `invert`, for every public pdf.
//!
//! `u.len()` must equal `canonical_dims()` and `x.len()` must equal `dims()`. Builds with debug
//! assertions panic on any mismatch, naming the slice; every build panics on a slice that is
//! too short. Run this module both ways (CI does):
//! `cargo test --test contracts -- pdf_slice_lengths::` (debug, checks the assertions) and
//! `cargo test --release --test contracts -- pdf_slice_lengths::`.

use glam::{DVec2, DVec3};
use mcint::pdf::{
    AliasTable, CosineHemisphere, Exponential, Linear, Mixture, Normal, Pdf, Pdf1d,
    PiecewiseConstant1d, PiecewiseConstant2d, PiecewiseLinear1d, ProductPdf, SphericalCap, Tent,
    TruncatedNormal, UniformBox, UniformDisk, UniformHemisphere, UniformInterval, UniformSphere,
    UniformTriangle,
};
use std::cell::Cell;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Once;

/// One pdf of each public type (two mixtures: the second has components that take different
/// numbers of canonical coordinates), with whether it has an inverse.
fn all_pdfs() -> Vec<(&'static str, Box<dyn Pdf>, bool)> {
    let unit = || Box::new(UniformInterval::new(0.0, 1.0).unwrap());
    let table_2d = PiecewiseConstant2d::new([0.0, 0.0], [1.0, 2.0], 2, 2, &[1.0, 2.0, 3.0, 4.0]);
    let product: Vec<Box<dyn Pdf1d>> = vec![
        Box::new(Exponential::new(1.0, 0.0, f64::INFINITY).unwrap()),
        Box::new(Normal::new(0.0, 1.0).unwrap()),
    ];
    let mixed_canonical: Vec<Box<dyn Pdf>> = vec![
        Box::new(UniformSphere),
        Box::new(UniformBox::unit(3).unwrap()),
    ];
    vec![
        (
            "AliasTable",
            Box::new(AliasTable::new(&[1.0, 2.0, 3.0]).unwrap()),
            false,
        ),
        ("CosineHemisphere", Box::new(CosineHemisphere), true),
        (
            "Exponential",
            Box::new(Exponential::new(2.0, 0.0, f64::INFINITY).unwrap()),
            true,
        ),
        (
            "Linear",
            Box::new(Linear::new(0.0, 1.0, 0.0, 2.0).unwrap()),
            true,
        ),
        (
            "Mixture",
            Box::new(Mixture::new(vec![unit(), unit()], vec![1.0, 3.0]).unwrap()),
            false,
        ),
        (
            "Mixture",
            Box::new(Mixture::new(mixed_canonical, vec![1.0, 1.0]).unwrap()),
            false,
        ),
        ("Normal", Box::new(Normal::new(0.0, 1.0).unwrap()), true),
        (
            "PiecewiseConstant1d",
            Box::new(PiecewiseConstant1d::new(0.0, 1.0, &[1.0, 3.0]).unwrap()),
            true,
        ),
        ("PiecewiseConstant2d", Box::new(table_2d.unwrap()), true),
        (
            "PiecewiseLinear1d",
            Box::new(PiecewiseLinear1d::new(&[0.0, 1.0, 2.0], &[1.0, 2.0, 1.0]).unwrap()),
            true,
        ),
        (
            "ProductPdf",
            Box::new(ProductPdf::new(product).unwrap()),
            true,
        ),
        (
            "SphericalCap",
            Box::new(SphericalCap::new(0.5).unwrap()),
            true,
        ),
        ("Tent", Box::new(Tent::new(0.0, 0.5, 1.0).unwrap()), true),
        (
            "TruncatedNormal",
            Box::new(TruncatedNormal::new(0.0, 1.0, -1.0, 2.0).unwrap()),
            true,
        ),
        ("UniformBox", Box::new(UniformBox::unit(3).unwrap()), true),
        (
            "UniformDisk",
            Box::new(UniformDisk::new(DVec2::new(1.0, 2.0), 0.5).unwrap()),
            true,
        ),
        ("UniformHemisphere", Box::new(UniformHemisphere), true),
        ("UniformInterval", unit(), true),
        ("UniformSphere", Box::new(UniformSphere), true),
        (
            "UniformTriangle",
            Box::new(UniformTriangle::new(DVec3::ZERO, DVec3::X, DVec3::Y).unwrap()),
            true,
        ),
    ]
}

thread_local! {
    /// Set while this thread runs code that is meant to panic, so its message is not printed.
    static EXPECTING_PANIC: Cell<bool> = const { Cell::new(false) };
}

/// Runs `f`, which should panic, and returns its panic message (or `None` if it returned).
/// The expected panics are kept off stderr; any other panic is reported as usual.
fn panic_message(f: impl FnOnce()) -> Option<String> {
    static QUIET_HOOK: Once = Once::new();
    QUIET_HOOK.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !EXPECTING_PANIC.with(Cell::get) {
                default(info);
            }
        }));
    });
    EXPECTING_PANIC.with(|e| e.set(true));
    let result = catch_unwind(AssertUnwindSafe(f));
    EXPECTING_PANIC.with(|e| e.set(false));
    let payload = result.err()?;
    Some(if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else {
        String::from("<non-string panic>")
    })
}

/// A canonical point inside `[0,1)^n` away from every seam.
fn canonical(n: usize) -> Vec<f64> {
    (0..n).map(|i| 0.3 + 0.1 * i as f64).collect()
}

#[test]
fn every_pdf_takes_slices_of_its_lengths() {
    for (name, pdf, invertible) in all_pdfs() {
        let (k, d) = (pdf.canonical_dims(), pdf.dims());
        let mut x = vec![f64::NAN; d];
        pdf.sample(&canonical(k), &mut x);
        assert!(x.iter().all(|v| v.is_finite()), "{name}: sample gave {x:?}");
        let density = pdf.pdf(&x);
        assert!(
            density.is_finite() && density > 0.0,
            "{name}: pdf({x:?}) = {density}"
        );
        let mut back = vec![f64::NAN; k];
        assert_eq!(pdf.invert(&x, &mut back).is_ok(), invertible, "{name}");
        if invertible {
            assert!(
                back.iter().all(|u| (0.0..=1.0).contains(u)),
                "{name}: invert({x:?}) = {back:?}"
            );
        }
    }
}

/// Asserts that `f` panics with a message that names the method and the slice with its
/// expected and actual lengths.
#[cfg(debug_assertions)]
fn assert_names_slice(name: &str, call: &str, slice: &str, expected: usize, f: impl FnOnce()) {
    let dims = if slice == "u" {
        "canonical_dims"
    } else {
        "dims"
    };
    let message = panic_message(f).unwrap_or_else(|| {
        panic!(
            "{name}: {call} with {slice} of length {} returned",
            expected + 1
        )
    });
    let wanted = format!(
        "{slice}.len() must equal {dims}() = {expected}, but is {}",
        expected + 1
    );
    assert!(
        message.contains(name) && message.contains(call) && message.contains(&wanted),
        "{name}: {call} panicked with {message:?}, which does not say {wanted:?}"
    );
}

#[cfg(debug_assertions)]
#[test]
fn slices_too_long_panic_with_debug_assertions() {
    for (name, pdf, _) in all_pdfs() {
        let (k, d) = (pdf.canonical_dims(), pdf.dims());
        let pdf = &*pdf;
        assert_names_slice(name, "::sample:", "u", k, || {
            pdf.sample(&canonical(k + 1), &mut vec![0.0; d])
        });
        assert_names_slice(name, "::sample:", "x", d, || {
            pdf.sample(&canonical(k), &mut vec![0.0; d + 1])
        });
        assert_names_slice(name, "::pdf:", "x", d, || {
            pdf.pdf(&vec![0.5; d + 1]);
        });
        // Also for pdfs without an inverse, whose default invert would return an error.
        assert_names_slice(name, "::invert:", "x", d, || {
            let _ = pdf.invert(&vec![0.5; d + 1], &mut vec![0.0; k]);
        });
        assert_names_slice(name, "::invert:", "u", k, || {
            let _ = pdf.invert(&vec![0.5; d], &mut vec![0.0; k + 1]);
        });
    }
}

/// A call on a pdf that is expected to panic.
type Call<'a> = Box<dyn FnOnce() + 'a>;

#[test]
fn slices_too_short_panic_in_every_build() {
    for (name, pdf, _) in all_pdfs() {
        let (k, d) = (pdf.canonical_dims(), pdf.dims());
        let pdf = &*pdf;
        let cases: [(&str, Call<'_>); 5] = [
            (
                "sample, short u",
                Box::new(|| pdf.sample(&canonical(k - 1), &mut vec![0.0; d])),
            ),
            (
                "sample, short x",
                Box::new(|| pdf.sample(&canonical(k), &mut vec![0.0; d - 1])),
            ),
            (
                "pdf, short x",
                Box::new(|| {
                    pdf.pdf(&vec![0.5; d - 1]);
                }),
            ),
            (
                "invert, short x",
                Box::new(|| {
                    let _ = pdf.invert(&vec![0.5; d - 1], &mut vec![0.0; k]);
                }),
            ),
            (
                "invert, short u",
                Box::new(|| {
                    let _ = pdf.invert(&vec![0.5; d], &mut vec![0.0; k - 1]);
                }),
            ),
        ];
        for (case, f) in cases {
            assert!(panic_message(f).is_some(), "{name}: {case} returned");
        }
    }
}

/// `Mixture::sample_with_component` keeps the contract of `sample`, also when the component
/// chosen takes fewer canonical coordinates than the mixture (here the sphere, 2 of 3).
#[test]
fn mixture_sample_with_component_checks_lengths() {
    let components: Vec<Box<dyn Pdf>> = vec![
        Box::new(UniformSphere),
        Box::new(UniformBox::unit(3).unwrap()),
    ];
    let mixture = Mixture::new(components, vec![1.0, 1.0]).unwrap();
    let mut x = [0.0; 3];
    assert_eq!(mixture.sample_with_component(&[0.2, 0.5, 0.5], &mut x), 0);
    assert!(
        panic_message(|| {
            mixture.sample_with_component(&[0.2, 0.5], &mut [0.0; 3]);
        })
        .is_some()
    );
    assert!(
        panic_message(|| {
            mixture.sample_with_component(&[0.2, 0.5, 0.5], &mut [0.0; 2]);
        })
        .is_some()
    );
    #[cfg(debug_assertions)]
    assert_names_slice("Mixture", "::sample_with_component:", "u", 3, || {
        mixture.sample_with_component(&[0.2, 0.5, 0.5, 0.5], &mut [0.0; 3]);
    });
}
