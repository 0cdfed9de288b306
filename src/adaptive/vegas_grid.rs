//! [`VegasGrid`]: the separable adaptive map of VEGAS (Lepage 1978; Lepage 2021, section 2).
//!
//! Each axis of the box is cut into `N` increments whose widths adapt; a coordinate `y` in
//! `[0, 1)` falls in increment `i = floor(y N)` and maps linearly into it, so every increment
//! receives the same share `1/N` of uniform points wherever it lies and however wide it is.
//! The Jacobian `dx/dy` is `N` times the increment's width on each axis. Training makes
//! increments narrow where `(J f)^2`, projected on the axis, is large: the density of
//! points then follows `|f|` as closely as a product of one-dimensional densities can.
//!
//! Adaptation follows the Python `vegas` package: the projections are smoothed with the
//! weights `(1, 6, 1) / 8` (`(7, 1) / 8` at the ends), normalized to `r_i` summing to 1, and
//! damped to `((1 - r_i) / ln(1 / r_i))^alpha`, which compresses their range so that the grid
//! moves cautiously; the new nodes then split the damped weights into `N` equal shares.

use crate::error::{Error, Result};
use crate::pdf::UniformBox;

/// Added to every normalized projection so that increments that saw no weight shrink a lot
/// but keep a positive width (the `TINY` of the Python `vegas` package).
const TINY: f64 = 1e-250;

/// The most the grid's density may fall from one increment to the next (with a density floor
/// set; see [`grade_density`]).
const MAX_DENSITY_RATIO: f64 = 8.0;

/// Most increments per axis accepted, to keep a grid's memory bounded.
const MAX_INCREMENTS: usize = 1 << 20;

/// The adaptive map `y -> x` from `[0, 1)^d` onto a box, one piecewise-linear map per axis.
///
/// ```
/// use mcint::adaptive::VegasGrid;
/// use mcint::pdf::UniformBox;
/// let mut grid = VegasGrid::new(&UniformBox::unit(1).unwrap(), 4).unwrap();
/// // Train on a function that lives in [0, 0.5): the grid moves its nodes there.
/// for i in 0..1000 {
///     let y = (i as f64 + 0.5) / 1000.0;
///     let mut x = [0.0];
///     let jac = grid.map(&[y], &mut x).unwrap();
///     let f = if x[0] < 0.5 { 1.0 } else { 0.0 };
///     grid.add_training(&[y], (jac * f) * (jac * f)).unwrap();
/// }
/// grid.adapt(1.0).unwrap();
/// assert!(grid.nodes(0)[2] < 0.5);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct VegasGrid {
    /// Increments per axis.
    counts: Vec<usize>,
    /// Where each axis lies in the arrays below.
    layout: Vec<AxisLayout>,
    /// Nodes of every axis, from the box's `lo` to its `hi`, axis after axis.
    nodes: Vec<f64>,
    /// Widths of the increments, axis after axis.
    widths: Vec<f64>,
    /// Training data per increment, laid out like `widths` but in pairs: the weighted sum
    /// of the values and the sum of the weights.
    training: Vec<f64>,
}

impl VegasGrid {
    /// The uniform grid on `domain` with `increments` (2 to `2^20`) equal increments per axis.
    ///
    /// ```
    /// use mcint::{adaptive::VegasGrid, pdf::UniformBox};
    /// let b = UniformBox::new(vec![0.0, -1.0], vec![1.0, 1.0]).unwrap();
    /// let grid = VegasGrid::new(&b, 4).unwrap();
    /// assert_eq!(grid.nodes(1), &[-1.0, -0.5, 0.0, 0.5, 1.0]);
    /// assert!(VegasGrid::new(&b, 1).is_err());
    /// ```
    pub fn new(domain: &UniformBox, increments: usize) -> Result<Self> {
        Self::with_increments(domain, &vec![increments; domain.lo().len()])
    }

    /// The uniform grid with `counts[d]` increments on axis `d`.
    pub(crate) fn with_increments(domain: &UniformBox, counts: &[usize]) -> Result<Self> {
        for &n in counts {
            check_increments(n)?;
        }
        let cells: usize = counts.iter().sum();
        let mut grid = VegasGrid {
            counts: counts.to_vec(),
            layout: Vec::with_capacity(counts.len()),
            nodes: Vec::with_capacity(cells + counts.len()),
            widths: Vec::with_capacity(cells),
            training: vec![0.0; 2 * cells],
        };
        for ((&lo, &hi), &n) in domain.lo().iter().zip(domain.hi()).zip(counts) {
            let start = grid.nodes.len();
            grid.layout.push(AxisLayout {
                node_start: start,
                cell_start: grid.widths.len(),
                // `check_increments` keeps n within u32.
                last: (n - 1) as u32,
                increments: n as f64,
            });
            grid.nodes
                .extend((0..=n).map(|i| lo + (hi - lo) * (i as f64 / n as f64)));
            // The last node is exactly `hi`, whatever the rounding above.
            grid.nodes[start + n] = hi;
            let axis = &grid.nodes[start..];
            grid.widths.extend(axis.windows(2).map(|w| w[1] - w[0]));
        }
        Ok(grid)
    }

    /// Number of axes.
    ///
    /// ```
    /// use mcint::{adaptive::VegasGrid, pdf::UniformBox};
    /// assert_eq!(VegasGrid::new(&UniformBox::unit(3).unwrap(), 10).unwrap().dims(), 3);
    /// ```
    pub fn dims(&self) -> usize {
        self.counts.len()
    }

    /// Number of increments of each axis.
    ///
    /// ```
    /// use mcint::{adaptive::VegasGrid, pdf::UniformBox};
    /// let grid = VegasGrid::new(&UniformBox::unit(2).unwrap(), 10).unwrap();
    /// assert_eq!(grid.increments(), &[10, 10]);
    /// ```
    pub fn increments(&self) -> &[usize] {
        &self.counts
    }

    /// Total number of increments over all axes (half the length of the training data).
    pub(crate) fn cells(&self) -> usize {
        self.widths.len()
    }

    /// The nodes of axis `axis`, increasing from the box's lower to its upper bound (empty
    /// for an axis that does not exist).
    ///
    /// ```
    /// use mcint::{adaptive::VegasGrid, pdf::UniformBox};
    /// let grid = VegasGrid::new(&UniformBox::unit(1).unwrap(), 2).unwrap();
    /// assert_eq!(grid.nodes(0), &[0.0, 0.5, 1.0]);
    /// assert!(grid.nodes(1).is_empty());
    /// ```
    pub fn nodes(&self, axis: usize) -> &[f64] {
        match self.counts.get(axis) {
            Some(&n) => {
                let start = self.layout[axis].node_start;
                &self.nodes[start..=start + n]
            }
            None => &[],
        }
    }

    /// Maps `y` in `[0, 1)^d` to `x` in the box and returns the Jacobian `dx/dy`.
    ///
    /// ```
    /// use mcint::{adaptive::VegasGrid, pdf::UniformBox};
    /// let grid = VegasGrid::new(&UniformBox::new(vec![0.0], vec![2.0]).unwrap(), 4).unwrap();
    /// let mut x = [0.0];
    /// assert_eq!(grid.map(&[0.25], &mut x).unwrap(), 2.0);
    /// assert_eq!(x, [0.5]);
    /// assert!(grid.map(&[0.25, 0.5], &mut x).is_err());
    /// ```
    pub fn map(&self, y: &[f64], x: &mut [f64]) -> Result<f64> {
        self.check_len("y", y.len())?;
        self.check_len("x", x.len())?;
        let mut jacobian = 1.0;
        for (axis, (&y, x)) in y.iter().zip(x.iter_mut()).enumerate() {
            let (value, factor, _) = self.map_axis(axis, y);
            *x = value;
            jacobian *= factor;
        }
        Ok(jacobian)
    }

    /// Adds training data `value` at `y` (for VEGAS, `(J f)^2`): the grid adapts to the
    /// average value in each increment of each axis, as the Python `vegas` package does.
    /// Non-finite or negative values are errors.
    ///
    /// ```
    /// use mcint::{adaptive::VegasGrid, pdf::UniformBox};
    /// let mut grid = VegasGrid::new(&UniformBox::unit(2).unwrap(), 8).unwrap();
    /// assert!(grid.add_training(&[0.1, 0.9], 2.5).is_ok());
    /// assert!(grid.add_training(&[0.1, 0.9], f64::NAN).is_err());
    /// ```
    pub fn add_training(&mut self, y: &[f64], value: f64) -> Result<()> {
        self.check_len("y", y.len())?;
        if !(value.is_finite() && value >= 0.0) {
            return Err(Error::invalid(
                "training value",
                value,
                "a finite value >= 0",
            ));
        }
        for (axis, &y) in y.iter().enumerate() {
            let (_, _, cell) = self.map_axis(axis, y);
            self.training[2 * cell] += value;
            self.training[2 * cell + 1] += 1.0;
        }
        Ok(())
    }

    /// Moves the nodes to the training data added since the last call (then clears it),
    /// with damping exponent `alpha` (finite, `>= 0`; `0` leaves the grid unchanged, larger
    /// values adapt faster; VEGAS uses 0.5). An axis whose training data is all zero keeps
    /// its nodes.
    ///
    /// ```
    /// use mcint::{adaptive::VegasGrid, pdf::UniformBox};
    /// let mut grid = VegasGrid::new(&UniformBox::unit(1).unwrap(), 4).unwrap();
    /// let before = grid.clone();
    /// grid.adapt(0.5).unwrap(); // no training data: nothing moves
    /// assert_eq!(grid, before);
    /// assert!(grid.adapt(-1.0).is_err());
    /// assert!(grid.adapt(1e300).is_err()); // damping exponents above 2 are refused
    /// ```
    pub fn adapt(&mut self, alpha: f64) -> Result<()> {
        check_alpha(alpha)?;
        let training = std::mem::take(&mut self.training);
        self.adapt_to(&training, alpha, 0.0);
        self.training = training;
        self.training.fill(0.0);
        Ok(())
    }

    /// Adapts every axis to `training` (pairs of weighted sums of `(J f)^2` and sums of
    /// weights per increment, as [`add_training`](Self::add_training) accumulates them),
    /// with a checked `alpha`, keeping each axis's density at least `floor` times the
    /// uniform one (see [`floor_density`]; 0 is classic VEGAS).
    ///
    /// The weighted average per increment, rather than the sum, is what the grid follows:
    /// it does not carry the fluctuation of the number of points that fell in the increment,
    /// which with about ten points per increment would otherwise dominate the noise.
    pub(crate) fn adapt_to(&mut self, training: &[f64], alpha: f64, floor: f64) {
        for axis in 0..self.dims() {
            let averages = increment_averages(&training[self.training_range(axis)]);
            if let Some(nodes) = self.axis_nodes(axis, &averages, alpha, floor) {
                self.set_axis_nodes(axis, &nodes);
            }
        }
    }

    /// Where axis `axis` lies in the training data: its increments' pairs.
    pub(crate) fn training_range(&self, axis: usize) -> std::ops::Range<usize> {
        let at = self.layout[axis].cell_start;
        2 * at..2 * (at + self.counts[axis])
    }

    /// The nodes axis `axis` moves to for the weighted `averages` of `(J f)^2` over its
    /// increments, or `None` when it keeps its nodes (`alpha = 0`, or averages all zero or
    /// not finite). Axes are independent, so they can be adapted in parallel.
    pub(crate) fn axis_nodes(
        &self,
        axis: usize,
        averages: &[f64],
        alpha: f64,
        floor: f64,
    ) -> Option<Vec<f64>> {
        if alpha == 0.0 {
            return None;
        }
        let n = self.counts[axis];
        let (nodes_at, cells_at) = (self.layout[axis].node_start, self.layout[axis].cell_start);
        let mut weights = vec![0.0; n];
        if !damped_weights(averages, alpha, &mut weights) {
            return None;
        }
        let nodes = &self.nodes[nodes_at..=nodes_at + n];
        let widths = &self.widths[cells_at..cells_at + n];
        if floor > 0.0 {
            grade_density(widths, &mut weights, MAX_DENSITY_RATIO);
        }
        floor_density(nodes, widths, &mut weights, floor);
        let mut new_nodes = vec![0.0; n + 1];
        regrid(nodes, widths, &weights, &mut new_nodes);
        Some(new_nodes)
    }

    /// Moves the nodes of axis `axis` to `new_nodes` (from [`axis_nodes`](Self::axis_nodes)).
    pub(crate) fn set_axis_nodes(&mut self, axis: usize, new_nodes: &[f64]) {
        let (nodes_at, cells_at) = (self.layout[axis].node_start, self.layout[axis].cell_start);
        let n = self.counts[axis];
        self.nodes[nodes_at..=nodes_at + n].copy_from_slice(new_nodes);
        for (width, pair) in self.widths[cells_at..cells_at + n]
            .iter_mut()
            .zip(new_nodes.windows(2))
        {
            *width = pair[1] - pair[0];
        }
    }

    /// The image of `y` on axis `axis`, the Jacobian factor `N * width`, and the index of the
    /// increment in the training data.
    #[inline]
    pub(crate) fn map_axis(&self, axis: usize, y: f64) -> (f64, f64, usize) {
        let a = &self.layout[axis];
        let t = y * a.increments;
        // `y < 1` keeps `t < n` except through rounding; clamp rather than index past the end
        // (the saturating cast also sends a negative `t` to increment 0).
        let cell = (t as u32).min(a.last);
        let at = a.cell_start + cell as usize;
        let width = self.widths[at];
        let x = self.nodes[a.node_start + cell as usize] + width * (t - f64::from(cell));
        (x, width * a.increments, at)
    }

    fn check_len(&self, what: &'static str, len: usize) -> Result<()> {
        if len != self.dims() {
            return Err(Error::DimensionMismatch {
                what,
                expected: self.dims(),
                found: len,
            });
        }
        Ok(())
    }
}

/// Where one axis lies in the grid's arrays, and its number of increments.
#[derive(Debug, Clone, PartialEq)]
struct AxisLayout {
    node_start: usize,
    cell_start: usize,
    /// The last increment, `n - 1`.
    last: u32,
    /// `n`, as a float.
    increments: f64,
}

/// Validates a number of increments per axis.
pub(crate) fn check_increments(increments: usize) -> Result<()> {
    if !(2..=MAX_INCREMENTS).contains(&increments) {
        return Err(Error::invalid(
            "grid_increments",
            increments,
            format!("2 to {MAX_INCREMENTS} increments per axis"),
        ));
    }
    Ok(())
}

/// Validates the damping exponent.
pub(crate) fn check_alpha(alpha: f64) -> Result<()> {
    // Larger exponents over-react to the noise of one iteration's projections, with runs
    // many standard errors off (docs/measurements.md); up to 2 the intervals held.
    if !(0.0..=MAX_ALPHA).contains(&alpha) {
        return Err(Error::invalid(
            "alpha",
            alpha,
            format!(
                "a damping exponent in [0, {MAX_ALPHA}] (0 freezes the grid; VEGAS uses 0.5; \
                 larger values make the grid chase noise)"
            ),
        ));
    }
    Ok(())
}

/// Validates the density floor of the grid's adaptation.
pub(crate) fn check_density_floor(floor: f64) -> Result<()> {
    if !(0.0..1.0).contains(&floor) {
        return Err(Error::invalid(
            "density_floor",
            floor,
            "a fraction of the uniform density in [0, 1) (0 is classic VEGAS; default 0.001)",
        ));
    }
    Ok(())
}

/// The largest grid damping exponent accepted (see [`check_alpha`]).
const MAX_ALPHA: f64 = 2.0;

/// The weighted average of `(J f)^2` over each increment of one axis, from its training
/// pairs (weighted sum, sum of weights).
pub(crate) fn increment_averages(pairs: &[f64]) -> Vec<f64> {
    pairs
        .chunks_exact(2)
        .map(|p| if p[1] > 0.0 { p[0] / p[1] } else { 0.0 })
        .collect()
}

/// Smooths, normalizes and damps one axis's projections into `weights`; false when they
/// carry no usable information (all zero, or not finite), in which case the axis stays put.
fn damped_weights(raw: &[f64], alpha: f64, weights: &mut [f64]) -> bool {
    let n = raw.len();
    // Neighbour smoothing (1, 6, 1)/8, and (7, 1)/8 at the two ends.
    weights[0] = (7.0 * raw[0] + raw[1]) / 8.0;
    weights[n - 1] = (7.0 * raw[n - 1] + raw[n - 2]) / 8.0;
    for i in 1..n - 1 {
        weights[i] = (raw[i - 1] + 6.0 * raw[i] + raw[i + 1]) / 8.0;
    }
    let sum: f64 = weights.iter().sum();
    if !(sum.is_finite() && sum > 0.0) {
        return false;
    }
    for w in weights.iter_mut() {
        let r = *w / sum + TINY;
        // ((1 - r) / ln(1/r))^alpha tends to 1 as r -> 1; avoid 0/0 there.
        *w = if r < 1.0 - 1e-8 {
            let damped = (1.0 - r) / -r.ln();
            // The default exponent, by a square root rather than a general power.
            if alpha == 0.5 {
                damped.sqrt()
            } else {
                damped.powf(alpha)
            }
        } else {
            1.0
        };
    }
    true
}

/// Raises the weight of every increment to at least `floor` times the weight it would have
/// if the axis's density were uniform, so that no increment is wider than about `1 / floor`
/// times the average.
///
/// Without a floor, an increment whose training data come from a rare region (the sliver of
/// a wide increment that lies before a jump of the integrand, everything beyond it zero)
/// averages to nearly nothing, widens, and makes the region rarer still: the iterations then
/// agree with one another while all of them miss part of the integral. The floor binds
/// only where the density has fallen below it, so grids that never get that thin are unchanged.
fn floor_density(nodes: &[f64], widths: &[f64], weights: &mut [f64], floor: f64) {
    if floor == 0.0 {
        return;
    }
    let total: f64 = weights.iter().sum();
    let length = nodes[nodes.len() - 1] - nodes[0];
    for (weight, width) in weights.iter_mut().zip(widths) {
        *weight = weight.max(floor * total * width / length);
    }
}

/// Raises weights so that the density (weight per unit length) falls by at most `ratio`
/// from one increment to the next, in either direction.
///
/// Without it, an increment the floor leaves wide (beyond a jump of the integrand, where it
/// is zero) can straddle the jump with a sliver of the nonzero side. Its weight per increment
/// is about its neighbour's, so it stays wide; the points that fall in the sliver are rare
/// and carry weights a thousand times the others', most runs miss them, and their iterations
/// agree while all of them miss the sliver's share of the integral. Graded, the density
/// falls over a few increments instead, and the sliver gets its share of points. Grids whose
/// density never falls that fast are unchanged to the bit.
fn grade_density(widths: &[f64], weights: &mut [f64], ratio: f64) {
    let n = weights.len();
    for i in 1..n {
        let least = weights[i - 1] / widths[i - 1] * widths[i] / ratio;
        weights[i] = weights[i].max(least);
    }
    // Raising an increment from the right never breaks the bound with its right neighbour.
    for i in (0..n.saturating_sub(1)).rev() {
        let least = weights[i + 1] / widths[i + 1] * widths[i] / ratio;
        weights[i] = weights[i].max(least);
    }
}

/// New nodes that split `weights` (spread uniformly over each old increment) into equal
/// shares: the inverse of the piecewise-linear cumulative weight.
fn regrid(nodes: &[f64], widths: &[f64], weights: &[f64], new_nodes: &mut [f64]) {
    let n = weights.len();
    let total: f64 = weights.iter().sum();
    let share = total / n as f64;
    new_nodes[0] = nodes[0];
    new_nodes[n] = nodes[n];
    let mut j = 0; // old increment holding the current target
    let mut below = 0.0; // cumulative weight of increments 0..j
    for i in 1..n {
        let target = share * i as f64;
        while j < n - 1 && below + weights[j] < target {
            below += weights[j];
            j += 1;
        }
        let fraction = ((target - below) / weights[j]).clamp(0.0, 1.0);
        let node = nodes[j] + widths[j] * fraction;
        // Rounding must never make an increment negative.
        new_nodes[i] = node.clamp(new_nodes[i - 1], nodes[n]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_weights_keep_the_nodes() {
        let grid = VegasGrid::new(&UniformBox::unit(1).unwrap(), 5).unwrap();
        let mut new_nodes = vec![0.0; 6];
        regrid(grid.nodes(0), &grid.widths, &[1.0; 5], &mut new_nodes);
        for (a, b) in new_nodes.iter().zip(grid.nodes(0)) {
            assert!((a - b).abs() < 1e-15);
        }
    }

    #[test]
    fn regrid_inverts_the_cumulative_weight() {
        // Weight 3 on [0, 0.5) and 1 on [0.5, 1): half the total lies below 1/3.
        let mut new_nodes = vec![0.0; 5];
        regrid(
            &[0.0, 0.5, 1.0],
            &[0.5, 0.5],
            &[3.0, 1.0],
            &mut new_nodes[..3],
        );
        assert!((new_nodes[1] - 1.0 / 3.0).abs() < 1e-15);
        // The same on quarters: quarters of the total at 1/6, 1/3 and 1/2.
        let nodes = [0.0, 0.25, 0.5, 0.75, 1.0];
        regrid(&nodes, &[0.25; 4], &[3.0, 3.0, 1.0, 1.0], &mut new_nodes);
        let expected = [0.0, 1.0 / 6.0, 1.0 / 3.0, 0.5, 1.0];
        for (a, b) in new_nodes.iter().zip(expected) {
            assert!((a - b).abs() < 1e-15, "{new_nodes:?}");
        }
    }

    /// Training data as `add_training` leaves them: the average `(J f)^2` of each increment
    /// of a one-axis grid, over one point each.
    fn one_axis_training(averages: &[f64]) -> Vec<f64> {
        averages.iter().flat_map(|&a| [a, 1.0]).collect()
    }

    /// The widest increment of axis 0 after repeated adaptation to the same averages.
    fn widest_after(averages: &[f64], floor: f64) -> f64 {
        let mut grid = VegasGrid::new(&UniformBox::unit(1).unwrap(), averages.len()).unwrap();
        for _ in 0..20 {
            grid.adapt_to(&one_axis_training(averages), 0.5, floor);
        }
        grid.widths.iter().copied().fold(0.0, f64::max)
    }

    #[test]
    fn the_density_floor_bounds_every_width() {
        // All the weight in the first of 100 increments: without a floor the grid piles up
        // there and leaves one increment for almost all the axis.
        let n = 100;
        let mut averages = vec![0.0; n];
        averages[0] = 1.0;
        assert!(widest_after(&averages, 0.0) > 0.9);
        // With one, the density stays at least floor / (1 + floor) times uniform, so no
        // increment is wider than (1 + floor) / (floor n).
        for floor in [0.005, 0.05, 0.5] {
            let widest = widest_after(&averages, floor);
            let bound = (1.0 + floor) / (floor * n as f64);
            assert!(
                widest <= bound * (1.0 + 1e-12),
                "floor {floor}: {widest} > {bound}"
            );
        }
    }

    #[test]
    fn graded_densities_fall_at_most_the_ratio_per_increment() {
        // A step: density 1000 on two narrow increments, then 1 on wide ones.
        let widths = [0.01, 0.01, 0.2, 0.2, 0.29, 0.29];
        let densities = [1000.0, 1000.0, 1.0, 1.0, 1.0, 1.0];
        let mut weights: Vec<f64> = widths.iter().zip(densities).map(|(h, d)| h * d).collect();
        let before = weights.clone();
        grade_density(&widths, &mut weights, 8.0);
        for i in 1..widths.len() {
            let (left, right) = (weights[i - 1] / widths[i - 1], weights[i] / widths[i]);
            assert!(right >= left / 8.0 * (1.0 - 1e-12), "{weights:?}");
            assert!(left >= right / 8.0 * (1.0 - 1e-12), "{weights:?}");
        }
        // Weights are only raised, and only as far as the bound needs: 1000 / 8 = 125 next
        // to the step, then 125 / 8 and 125 / 64.
        assert!(weights.iter().zip(&before).all(|(w, b)| w >= b));
        let graded: Vec<f64> = weights.iter().zip(widths).map(|(w, h)| w / h).collect();
        let expected = [1000.0, 1000.0, 125.0, 125.0 / 8.0, 125.0 / 64.0, 1.0];
        for (g, e) in graded.iter().zip(expected) {
            assert!((g - e).abs() <= 1e-12 * e, "{graded:?}");
        }
        // A graded density is left as it is.
        let again = weights.clone();
        grade_density(&widths, &mut weights, 8.0);
        assert_eq!(weights, again);
    }

    #[test]
    fn the_density_floor_leaves_moderate_grids_alone() {
        // Averages within a factor of 4: the damped density never falls near 0.005 of
        // uniform, so the floor changes no bit.
        let averages: Vec<f64> = (0..50).map(|i| 1.0 + 3.0 * f64::from(i) / 49.0).collect();
        let mut with = VegasGrid::new(&UniformBox::unit(1).unwrap(), 50).unwrap();
        let mut without = with.clone();
        for _ in 0..20 {
            with.adapt_to(&one_axis_training(&averages), 0.5, 0.005);
            without.adapt_to(&one_axis_training(&averages), 0.5, 0.0);
        }
        assert_eq!(with, without);
    }

    #[test]
    fn damping_compresses_the_range_of_weights() {
        let mut w = [0.0; 4];
        assert!(damped_weights(&[1.0, 0.0, 0.0, 100.0], 0.5, &mut w));
        let (lo, hi) = w
            .iter()
            .fold((f64::MAX, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
        assert!(lo > 0.0 && hi / lo < 100.0, "{w:?}");
        assert!(!damped_weights(&[0.0; 4], 0.5, &mut w));
        assert!(!damped_weights(
            &[f64::INFINITY, 0.0, 0.0, 1.0],
            0.5,
            &mut w
        ));
    }
}
