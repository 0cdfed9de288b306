//! A uniform background grid on the unit torus `[0,1)^d` for neighbour queries of the
//! blue-noise constructions.
//!
//! Cells have side `1/m >= reach`, where `reach` is the largest distance a query asks about,
//! so every point within `reach` of a box lies in the cells the box's `reach`-neighbourhood
//! overlaps: about `2^d` cells for a box smaller than a cell, at most `3^d` for a single point
//! near cell corners. Each cell holds a linked list of its points (`head` per cell, `next` per
//! point), so any number of points may share a cell. Coordinates wrap around, as distances
//! on the torus do.

use super::torus::MAX_TORUS_DIMS;

/// Marks the end of a cell's list.
const END: u32 = u32::MAX;

/// Points on the unit torus, bucketed by cell.
pub(super) struct TorusGrid {
    dims: usize,
    /// Cells per axis.
    m: usize,
    head: Vec<u32>,
    next: Vec<u32>,
    /// The points, point-major.
    points: Vec<f64>,
}

impl TorusGrid {
    /// A grid whose cells are at least `reach` wide (`0 < reach`), with `m^d` cells.
    pub(super) fn new(dims: usize, reach: f64) -> TorusGrid {
        let m = ((1.0 / reach).floor() as usize).max(1);
        TorusGrid {
            dims,
            m,
            head: vec![END; m.pow(dims as u32)],
            next: Vec::new(),
            points: Vec::new(),
        }
    }

    pub(super) fn dims(&self) -> usize {
        self.dims
    }

    /// Cells per axis.
    pub(super) fn cells_per_axis(&self) -> usize {
        self.m
    }

    pub(super) fn len(&self) -> usize {
        self.next.len()
    }

    pub(super) fn point(&self, i: u32) -> &[f64] {
        let i = i as usize;
        &self.points[i * self.dims..(i + 1) * self.dims]
    }

    /// The points, point-major, in insertion order.
    pub(super) fn into_points(self) -> Vec<f64> {
        self.points
    }

    /// Adds `x` (coordinates in `[0,1)`) and returns its index.
    pub(super) fn insert(&mut self, x: &[f64]) -> u32 {
        let m = self.m;
        let cell = x.iter().rev().fold(0usize, |acc, &v| {
            acc * m + ((v * m as f64) as usize).min(m - 1)
        });
        let index = self.len() as u32;
        self.next.push(self.head[cell]);
        self.head[cell] = index;
        self.points.extend_from_slice(x);
        index
    }

    /// Collects into `out` the indices of every point that can lie within `reach` (toroidal
    /// distance) of the box `[lo, hi]` (and some farther ones). `reach` must not exceed the
    /// grid's.
    pub(super) fn gather(&self, lo: &[f64], hi: &[f64], reach: f64, out: &mut Vec<u32>) {
        out.clear();
        let m = self.m as i64;
        // Per axis: the first cell (possibly negative, wrapped below) and how many follow.
        let mut first = [0i64; MAX_TORUS_DIMS];
        let mut count = [0i64; MAX_TORUS_DIMS];
        for j in 0..self.dims {
            let a = ((lo[j] - reach) * m as f64).floor() as i64;
            let b = ((hi[j] + reach) * m as f64).floor() as i64;
            first[j] = a;
            count[j] = (b - a + 1).min(m);
        }
        let mut step = [0i64; MAX_TORUS_DIMS];
        'cells: loop {
            let cell = (0..self.dims).rev().fold(0usize, |acc, j| {
                acc * self.m + (first[j] + step[j]).rem_euclid(m) as usize
            });
            let mut i = self.head[cell];
            while i != END {
                out.push(i);
                i = self.next[i as usize];
            }
            // Odometer over the per-axis ranges.
            for j in 0..self.dims {
                step[j] += 1;
                if step[j] < count[j] {
                    continue 'cells;
                }
                step[j] = 0;
            }
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every point within `reach` of a box is gathered, across the wrap-around too.
    #[test]
    fn gather_finds_every_near_point() {
        let mut state = 0x1234_5678_u64;
        let mut uniform = move || {
            state = crate::hash::mix64(state.wrapping_add(0x9e37_79b9_7f4a_7c15));
            crate::hash::unit_f64(state)
        };
        for dims in 1..=3 {
            let reach = 0.13;
            let mut grid = TorusGrid::new(dims, reach);
            let pts: Vec<Vec<f64>> = (0..300)
                .map(|_| (0..dims).map(|_| uniform()).collect())
                .collect();
            for p in &pts {
                grid.insert(p);
            }
            let mut out = Vec::new();
            for _ in 0..200 {
                let lo: Vec<f64> = (0..dims).map(|_| uniform() * 0.95).collect();
                let hi: Vec<f64> = lo.iter().map(|v| v + 0.05 * uniform()).collect();
                grid.gather(&lo, &hi, reach, &mut out);
                for (i, p) in pts.iter().enumerate() {
                    let d2: f64 = (0..dims)
                        .map(|j| {
                            let gap = if p[j] < lo[j] {
                                (lo[j] - p[j]).min(1.0 - hi[j] + p[j])
                            } else if p[j] > hi[j] {
                                (p[j] - hi[j]).min(1.0 - p[j] + lo[j])
                            } else {
                                0.0
                            };
                            gap * gap
                        })
                        .sum();
                    if d2 <= reach * reach {
                        assert!(out.contains(&(i as u32)), "dims {dims}: missed point {i}");
                    }
                }
            }
        }
    }
}
