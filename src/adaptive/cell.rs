//! [`Cell`]: an axis-aligned sub-box of the unit cube, the region an adaptive method works on.

use crate::pdf::{Pdf, UniformBox};
use crate::points::Points;

/// An axis-aligned sub-box of the unit cube: the region an adaptive method is working on, in
/// coordinates relative to the domain.
#[derive(Debug, Clone, PartialEq)]
pub(in crate::adaptive) struct Cell {
    pub(in crate::adaptive) lo: Vec<f64>,
    pub(in crate::adaptive) hi: Vec<f64>,
}

impl Cell {
    /// The whole unit cube.
    pub(in crate::adaptive) fn unit(dims: usize) -> Cell {
        Cell {
            lo: vec![0.0; dims],
            hi: vec![1.0; dims],
        }
    }

    /// Volume as a fraction of the domain's.
    pub(in crate::adaptive) fn volume(&self) -> f64 {
        self.lo.iter().zip(&self.hi).map(|(l, h)| h - l).product()
    }

    /// Maps point `i` of a block of canonical points into the cell (`unit`, relative to the
    /// domain) and on into the domain (`x`).
    pub(in crate::adaptive) fn place(
        &self,
        points: &Points,
        i: usize,
        domain: &UniformBox,
        unit: &mut [f64],
        x: &mut [f64],
    ) {
        for (dim, ((u, &lo), &hi)) in unit.iter_mut().zip(&self.lo).zip(&self.hi).enumerate() {
            *u = lo + points.get(i, dim) * (hi - lo);
        }
        domain.sample(unit, x);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_place_points_inside_and_measure_their_volume() {
        let cell = Cell {
            lo: vec![0.5, 0.0],
            hi: vec![1.0, 0.25],
        };
        assert_eq!(cell.volume(), 0.125);
        let domain = UniformBox::new(vec![0.0, 0.0], vec![2.0, 4.0]).unwrap();
        let mut points = Points::new(2, 1).unwrap();
        points.column_mut(0)[0] = 0.5;
        points.column_mut(1)[0] = 0.5;
        let (mut unit, mut x) = ([0.0; 2], [0.0; 2]);
        cell.place(&points, 0, &domain, &mut unit, &mut x);
        assert_eq!((unit, x), ([0.75, 0.125], [1.5, 0.5]));
    }
}
