//! The uniform density on an axis-aligned box: A.13 in every coordinate.

use super::{Pdf, debug_assert_len};
use crate::error::{Error, Result};

/// Uniform density `1/volume` on the box `[lo_1, hi_1) x ... x [lo_d, hi_d)`.
///
/// ```
/// use mcint::pdf::{Pdf, UniformBox};
/// let b = UniformBox::new(vec![0.0, -1.0], vec![2.0, 1.0]).unwrap();
/// let mut x = [0.0; 2];
/// b.sample(&[0.5, 0.25], &mut x);
/// assert_eq!(x, [1.0, -0.5]);
/// assert_eq!(b.volume(), 4.0);
/// assert_eq!(b.pdf(&x), 0.25);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct UniformBox {
    lo: Vec<f64>,
    hi: Vec<f64>,
    volume: f64,
}

impl UniformBox {
    /// The box with corners `lo` and `hi`: same non-zero length, finite, `lo_i < hi_i`, and
    /// a finite, non-zero volume.
    ///
    /// ```
    /// use mcint::pdf::UniformBox;
    /// assert!(UniformBox::new(vec![0.0], vec![0.0]).is_err());
    /// assert!(UniformBox::new(vec![], vec![]).is_err());
    /// // Sides of 1e-155 give a volume of 1e-310, whose density would be infinite.
    /// assert!(UniformBox::new(vec![0.0; 2], vec![1e-155; 2]).is_err());
    /// ```
    pub fn new(lo: Vec<f64>, hi: Vec<f64>) -> Result<Self> {
        if lo.is_empty() {
            return Err(Error::invalid("lo", "[]", "at least one dimension"));
        }
        if hi.len() != lo.len() {
            return Err(Error::DimensionMismatch {
                what: "hi",
                expected: lo.len(),
                found: hi.len(),
            });
        }
        for (i, (&l, &h)) in lo.iter().zip(&hi).enumerate() {
            if !l.is_finite() || !h.is_finite() || l >= h {
                return Err(Error::invalid(
                    "lo/hi",
                    format!("[{l}, {h}) in dimension {i}"),
                    "finite bounds with lo < hi",
                ));
            }
        }
        let volume: f64 = lo.iter().zip(&hi).map(|(l, h)| h - l).product();
        // The density 1 / volume must be finite too (a subnormal volume would make it inf).
        if !(volume.is_finite() && volume > 0.0 && (1.0 / volume).is_finite()) {
            return Err(Error::invalid(
                "box volume",
                volume,
                "a finite positive volume whose reciprocal, the density, is finite",
            ));
        }
        Ok(UniformBox { lo, hi, volume })
    }

    /// The unit cube `[0,1)^dims`.
    ///
    /// ```
    /// assert_eq!(mcint::pdf::UniformBox::unit(3).unwrap().volume(), 1.0);
    /// let err = mcint::pdf::UniformBox::unit(0).unwrap_err();
    /// assert!(err.to_string().starts_with("invalid dims = 0"), "{err}");
    /// assert!(mcint::pdf::UniformBox::unit(usize::MAX).is_err());
    /// ```
    pub fn unit(dims: usize) -> Result<Self> {
        if dims == 0 {
            return Err(Error::invalid("dims", dims, "at least 1"));
        }
        crate::error::check_vec_len::<f64>("dims", dims)?;
        UniformBox::new(vec![0.0; dims], vec![1.0; dims])
    }

    /// The product of the side lengths.
    ///
    /// ```
    /// assert_eq!(mcint::pdf::UniformBox::new(vec![0.0], vec![3.0]).unwrap().volume(), 3.0);
    /// ```
    pub fn volume(&self) -> f64 {
        self.volume
    }

    /// Lower corner.
    ///
    /// ```
    /// assert_eq!(mcint::pdf::UniformBox::unit(2).unwrap().lo(), &[0.0, 0.0]);
    /// ```
    pub fn lo(&self) -> &[f64] {
        &self.lo
    }

    /// Upper corner.
    ///
    /// ```
    /// assert_eq!(mcint::pdf::UniformBox::unit(2).unwrap().hi(), &[1.0, 1.0]);
    /// ```
    pub fn hi(&self) -> &[f64] {
        &self.hi
    }
}

impl Pdf for UniformBox {
    fn canonical_dims(&self) -> usize {
        self.lo.len()
    }

    fn dims(&self) -> usize {
        self.lo.len()
    }

    fn sample(&self, u: &[f64], x: &mut [f64]) {
        debug_assert_len!(self, sample, u, canonical_dims);
        debug_assert_len!(self, sample, x, dims);
        // Slicing, not zip alone, makes a too-short slice panic in release builds too.
        let n = self.lo.len();
        for (((x, &u), &lo), &hi) in x[..n].iter_mut().zip(&u[..n]).zip(&self.lo).zip(&self.hi) {
            let v = lo + u * (hi - lo);
            *x = if v < hi { v } else { hi.next_down() };
        }
    }

    fn pdf(&self, x: &[f64]) -> f64 {
        debug_assert_len!(self, pdf, x, dims);
        let inside = x[..self.lo.len()]
            .iter()
            .zip(&self.lo)
            .zip(&self.hi)
            .all(|((x, lo), hi)| (*lo..*hi).contains(x));
        if inside { 1.0 / self.volume } else { 0.0 }
    }

    fn invert(&self, x: &[f64], u: &mut [f64]) -> Result<()> {
        debug_assert_len!(self, invert, x, dims);
        debug_assert_len!(self, invert, u, canonical_dims);
        let n = self.lo.len();
        for (((u, &x), &lo), &hi) in u[..n].iter_mut().zip(&x[..n]).zip(&self.lo).zip(&self.hi) {
            *u = ((x - lo) / (hi - lo)).clamp(0.0, 1.0);
        }
        Ok(())
    }
}
