//! Point sets drawn the way scipy.stats.qmc draws them: `random(n)`, `random_base2(m)` and
//! `integers(l, u, n)` of a [`Sampler`], always from the first point of pass 0.

use super::{PassKind, Sampler};
use crate::error::{Error, Result};
use crate::points::{PointBlock, Points};

/// Points `0..n` of pass 0 of `sampler`.
pub(super) fn random(sampler: &(impl Sampler + ?Sized), n: usize) -> Result<Points> {
    match sampler.passes() {
        PassKind::Fixed { size } if n as u64 != size => {
            return Err(Error::invalid(
                "n",
                n,
                format!(
                    "{size}, the {} sampler's pass size (a part of a pass is not stratified; \
                     build the sampler with the size you want)",
                    sampler.name()
                ),
            ));
        }
        PassKind::Extensible { max } if n as u64 > max => {
            return Err(Error::invalid(
                "n",
                n,
                format!("at most {max} points for the {} sampler", sampler.name()),
            ));
        }
        _ => {}
    }
    let mut points = Points::new(sampler.dims(), n)?;
    sampler.fill(0, &mut points)?;
    Ok(points)
}

/// Points `0..2^m` of pass 0 of `sampler`, refused where `2^m` points break its balance.
pub(super) fn random_base2(sampler: &(impl Sampler + ?Sized), m: u32) -> Result<Points> {
    let n = 1u64
        .checked_shl(m)
        .filter(|&n| usize::try_from(n).is_ok())
        .ok_or_else(|| Error::invalid("m", m, "at most 63 (2^m points must be countable)"))?;
    if let Some(base) = sampler.unbalanced_by(n) {
        return Err(Error::invalid(
            "m",
            m,
            format!(
                "a size that keeps the {} sampler's balance (its nets come in powers of {base}, \
                 and 2^{m} is not one)",
                sampler.name()
            ),
        ));
    }
    random(sampler, n as usize)
}

/// The largest magnitude of an integer bound: every integer up to it is a double, so the
/// map below is exact arithmetic up to its one rounding.
const MAX_BOUND: i64 = 1 << 53;

/// Points `0..n` of pass 0 of `sampler` mapped to integers as scipy maps them: coordinate
/// `j` becomes `floor(u_j (upper[j] - lower[j]) + lower[j])`, in `lower[j]..upper[j]`.
pub(super) fn integers(
    sampler: &(impl Sampler + ?Sized),
    lower: &[i64],
    upper: &[i64],
    n: usize,
) -> Result<PointBlock<i64>> {
    for (what, bounds) in [("lower bounds", lower), ("upper bounds", upper)] {
        if bounds.len() != sampler.dims() {
            return Err(Error::DimensionMismatch {
                what,
                expected: sampler.dims(),
                found: bounds.len(),
            });
        }
    }
    for (j, (&l, &u)) in lower.iter().zip(upper).enumerate() {
        let bounded = |b: i64| (-MAX_BOUND..=MAX_BOUND).contains(&b);
        if !(l < u && bounded(l) && bounded(u)) {
            return Err(Error::invalid(
                "integer bounds",
                format!("{l}..{u} in dimension {j}"),
                "lower < upper, both within +-2^53 (the integers a double holds exactly)",
            ));
        }
    }
    let points = random(sampler, n)?;
    let mut out = PointBlock::<i64>::new(sampler.dims(), n)?;
    for (j, (&l, &u)) in lower.iter().zip(upper).enumerate() {
        let (low, width) = (l as f64, (u - l) as f64);
        for (k, &x) in out.column_mut(j).iter_mut().zip(points.column(j)) {
            // The clamp keeps a rounding up at the top edge inside the range.
            *k = ((x * width + low).floor() as i64).clamp(l, u - 1);
        }
    }
    Ok(out)
}
