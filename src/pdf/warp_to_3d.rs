//! `warp_to_3d!`: the [`Pdf`](super::Pdf) of a warp from the unit square to points of 3-D
//! space (directions on a sphere, points of a triangle), written once.
//!
//! A type with `sample_point(DVec2) -> DVec3`, `pdf_point(DVec3) -> f64` and
//! `invert_point(DVec3) -> DVec2` gets `impl Pdf` and `impl Warp3` from
//! `warp_to_3d!(Type, "what x must be")`:
//! two canonical coordinates in, three out, and `invert` refusing a non-finite point with
//! an error that says what a point of its domain is.

/// See the [module documentation](self).
macro_rules! warp_to_3d {
    ($warp:ty, $point:literal) => {
        impl $crate::pdf::Pdf for $warp {
            fn canonical_dims(&self) -> usize {
                2
            }

            fn dims(&self) -> usize {
                3
            }

            fn sample(&self, u: &[f64], x: &mut [f64]) {
                $crate::pdf::debug_assert_len!(self, sample, u, canonical_dims);
                $crate::pdf::debug_assert_len!(self, sample, x, dims);
                self.sample_point(glam::DVec2::new(u[0], u[1]))
                    .write_to_slice(&mut x[..3]);
            }

            fn pdf(&self, x: &[f64]) -> f64 {
                $crate::pdf::debug_assert_len!(self, pdf, x, dims);
                self.pdf_point(glam::DVec3::new(x[0], x[1], x[2]))
            }

            fn invert(&self, x: &[f64], u: &mut [f64]) -> $crate::error::Result<()> {
                $crate::pdf::debug_assert_len!(self, invert, x, dims);
                $crate::pdf::debug_assert_len!(self, invert, u, canonical_dims);
                let x = glam::DVec3::new(x[0], x[1], x[2]);
                if !x.is_finite() {
                    return Err($crate::error::Error::invalid("x", x, $point));
                }
                self.invert_point(x).write_to_slice(&mut u[..2]);
                Ok(())
            }
        }

        impl $crate::pdf::Warp3 for $warp {
            fn sample_point(&self, u: glam::DVec2) -> glam::DVec3 {
                <$warp>::sample_point(self, u)
            }

            fn pdf_point(&self, x: glam::DVec3) -> f64 {
                <$warp>::pdf_point(self, x)
            }

            fn invert_point(&self, x: glam::DVec3) -> glam::DVec2 {
                <$warp>::invert_point(self, x)
            }
        }
    };
}

pub(super) use warp_to_3d;
