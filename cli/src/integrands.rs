//! The test integrands `integrate --integrand` offers: the Genz families (with `--a`, `--u`)
//! and the Keister integrand over `R^d` (by its normal transform to the unit cube).

use mcint::testfns::{Genz, GenzFamily, Keister, TestFunction};

use crate::args::Args;

/// One integrand of the command line.
#[derive(Debug, Clone)]
pub enum Named {
    Genz(Genz),
    Keister(Keister),
}

/// What `--integrand` accepts.
pub const INTEGRAND_NAMES: &str = "keister or a Genz family (oscillatory, product-peak, \
                                   corner-peak, gaussian, continuous, discontinuous)";

impl Named {
    /// The integrands named in `list` (comma-separated) in `dims` dimensions; `--a` and `--u`
    /// apply to the Genz families.
    pub fn parse_list(args: &Args, list: &str, dims: usize) -> Result<Vec<Named>, String> {
        list.split(',')
            .map(|name| Named::parse(args, name.trim(), dims))
            .collect()
    }

    fn parse(args: &Args, name: &str, dims: usize) -> Result<Named, String> {
        if name == "keister" {
            return Keister::new(dims)
                .map(Named::Keister)
                .map_err(crate::args::flag_error);
        }
        let family: GenzFamily = name
            .parse()
            .map_err(|_| format!("invalid --integrand = '{name}': expected {INTEGRAND_NAMES}"))?;
        match (args.list("a")?, args.list("u")?) {
            (None, None) => Genz::with_defaults(family, dims),
            (a, u) => {
                for (flag, values) in [("a", &a), ("u", &u)] {
                    if let Some(values) = values
                        && values.len() != dims
                    {
                        return Err(format!(
                            "invalid --{flag}: {} values for --dims {dims} (one per dimension)",
                            values.len()
                        ));
                    }
                }
                let defaults =
                    Genz::with_defaults(family, dims).map_err(crate::args::flag_error)?;
                Genz::new(
                    family,
                    a.unwrap_or_else(|| defaults.a().to_vec()),
                    u.unwrap_or_else(|| defaults.u().to_vec()),
                )
            }
        }
        .map(Named::Genz)
        .map_err(crate::args::flag_error)
    }

    /// The Genz function, if this is one.
    pub fn genz(&self) -> Option<&Genz> {
        match self {
            Named::Genz(g) => Some(g),
            Named::Keister(_) => None,
        }
    }

    /// The integrand's name in checkpoints: another family or parameters are refused.
    pub fn label(&self) -> String {
        match self {
            Named::Genz(g) => format!("genz {} a={:?} u={:?}", g.family().name(), g.a(), g.u()),
            Named::Keister(k) => format!("keister d={}", k.dims()),
        }
    }
}

impl TestFunction for Named {
    fn dims(&self) -> usize {
        match self {
            Named::Genz(g) => g.dims(),
            Named::Keister(k) => k.dims(),
        }
    }

    fn eval(&self, x: &[f64]) -> f64 {
        match self {
            Named::Genz(g) => g.eval(x),
            Named::Keister(k) => k.eval(x),
        }
    }

    fn eval_batch(&self, points: &mcint::Points, out: &mut [f64]) {
        match self {
            Named::Genz(g) => g.eval_batch(points, out),
            Named::Keister(k) => k.eval_batch(points, out),
        }
    }

    fn exact(&self) -> f64 {
        match self {
            Named::Genz(g) => g.exact(),
            Named::Keister(k) => k.exact(),
        }
    }

    fn name(&self) -> String {
        match self {
            Named::Genz(g) => g.name(),
            Named::Keister(k) => k.name(),
        }
    }
}

/// Parses `--ratio I,J` against `m` outputs.
pub fn parse_ratio(text: &str, m: usize) -> Result<(usize, usize), String> {
    let bad = || {
        format!(
            "invalid --ratio = '{text}': expected two output indices I,J below {m} (positions in \
             the --integrand list, from 0), I != J"
        )
    };
    let (i, j) = text.split_once(',').ok_or_else(bad)?;
    let (i, j): (usize, usize) = (
        i.trim().parse().map_err(|_| bad())?,
        j.trim().parse().map_err(|_| bad())?,
    );
    if i >= m || j >= m || i == j {
        return Err(bad());
    }
    Ok((i, j))
}
