//! [`NearestPoint`]: which point of a set is nearest to a query, by a k-d tree, with the
//! answer (and the squared distance, to the bit) of a scan of every point in index order.
//!
//! Lloyd relaxation asks this of every probe point at every step; a scan costs `N` distances
//! per query, the tree about `log N` in few dimensions (and never more than the scan's work
//! by much in many, where every branch may have to be visited).

use crate::points::Points;

/// Ranges of at most this many points are scanned rather than split.
const LEAF: usize = 8;

/// A k-d tree over a fixed point set: the points' indices, arranged so that each range's
/// middle entry splits it on the axis `depth mod d` (smaller or equal coordinates before it,
/// larger or equal after).
pub(crate) struct NearestPoint {
    dims: usize,
    /// The points row by row (`dims` coordinates each), for distances a point at a time.
    rows: Vec<f64>,
    order: Vec<usize>,
}

impl NearestPoint {
    pub(crate) fn new(points: &Points) -> NearestPoint {
        let (n, dims) = (points.len(), points.dims());
        let mut rows = vec![0.0; n * dims];
        for k in 0..dims {
            for (i, &x) in points.column(k).iter().enumerate() {
                rows[i * dims + k] = x;
            }
        }
        let mut tree = NearestPoint {
            dims,
            rows,
            order: (0..n).collect(),
        };
        let mut order = std::mem::take(&mut tree.order);
        tree.arrange(&mut order, 0);
        tree.order = order;
        tree
    }

    fn arrange(&self, order: &mut [usize], depth: usize) {
        if order.len() <= LEAF {
            return;
        }
        let k = depth % self.dims;
        let mid = order.len() / 2;
        order.select_nth_unstable_by(mid, |&a, &b| {
            self.coordinate(a, k).total_cmp(&self.coordinate(b, k))
        });
        let (before, after) = order.split_at_mut(mid);
        self.arrange(before, depth + 1);
        self.arrange(&mut after[1..], depth + 1);
    }

    fn coordinate(&self, point: usize, k: usize) -> f64 {
        self.rows[point * self.dims + k]
    }

    /// The squared distance from `query` to `point`, summed over the axes in order: the
    /// same bits as a scan that accumulates axis by axis.
    fn distance(&self, point: usize, query: &[f64]) -> f64 {
        let row = &self.rows[point * self.dims..(point + 1) * self.dims];
        row.iter().zip(query).fold(0.0, |sum, (&x, &q)| {
            let t = q - x;
            sum + t * t
        })
    }

    /// The nearest point to `query` (the lowest index among equally near ones) and its
    /// squared distance; `None` for an empty set.
    pub(crate) fn nearest(&self, query: &[f64]) -> Option<(usize, f64)> {
        let mut best = None;
        self.search(&self.order, 0, query, &mut best);
        best.map(|(distance, point)| (point, distance))
    }

    fn offer(&self, point: usize, query: &[f64], best: &mut Option<(f64, usize)>) {
        let distance = self.distance(point, query);
        if best.is_none_or(|(d, p)| distance < d || (distance == d && point < p)) {
            *best = Some((distance, point));
        }
    }

    fn search(
        &self,
        order: &[usize],
        depth: usize,
        query: &[f64],
        best: &mut Option<(f64, usize)>,
    ) {
        if order.len() <= LEAF {
            for &point in order {
                self.offer(point, query, best);
            }
            return;
        }
        let k = depth % self.dims;
        let mid = order.len() / 2;
        let split = order[mid];
        self.offer(split, query, best);
        let gap = query[k] - self.coordinate(split, k);
        let (near, far) = if gap < 0.0 {
            (&order[..mid], &order[mid + 1..])
        } else {
            (&order[mid + 1..], &order[..mid])
        };
        self.search(near, depth + 1, query, best);
        // Every point of the far side is at least `gap` away along axis k (rounding is
        // monotone, so in floating point too); an equally near point is still visited, for
        // the tie rule.
        if best.is_none_or(|(d, _)| gap * gap <= d) {
            self.search(far, depth + 1, query, best);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampler::{Independent, Sampler};

    /// The scan the tree stands for: every point in index order, the first of the nearest.
    fn scan(points: &Points, query: &[f64]) -> (usize, f64) {
        let mut best = (usize::MAX, f64::INFINITY);
        for i in 0..points.len() {
            let mut distance = 0.0;
            for (k, &q) in query.iter().enumerate() {
                let t = q - points.column(k)[i];
                distance += t * t;
            }
            if distance < best.1 {
                best = (i, distance);
            }
        }
        best
    }

    #[test]
    fn the_tree_answers_as_the_scan_with_its_ties() {
        for (dims, n) in [(1, 1), (1, 40), (2, 500), (3, 9), (5, 300), (12, 200)] {
            let mut points = Independent::new(dims, 1).unwrap().random(n).unwrap();
            // Repeated points and a coarse grid make exact ties.
            for k in 0..dims {
                let column = points.column_mut(k);
                for i in 0..n {
                    column[i] = if i % 3 == 0 {
                        column[i / 3]
                    } else {
                        (column[i] * 4.0).floor() / 4.0
                    };
                }
            }
            let tree = NearestPoint::new(&points);
            let queries = Independent::new(dims, 2).unwrap().random(300).unwrap();
            let mut query = vec![0.0; dims];
            for j in 0..300 {
                for (k, q) in query.iter_mut().enumerate() {
                    // Half the queries on the grid, where ties are common.
                    let x = queries.column(k)[j];
                    *q = if j % 2 == 0 {
                        (x * 4.0).floor() / 4.0
                    } else {
                        x
                    };
                }
                let (point, distance) = tree.nearest(&query).unwrap();
                let (expected, expected_distance) = scan(&points, &query);
                assert_eq!(point, expected, "{dims}-D, {n} points, query {j}");
                assert_eq!(distance.to_bits(), expected_distance.to_bits());
            }
        }
        let empty = Points::new(2, 0).unwrap();
        assert!(NearestPoint::new(&empty).nearest(&[0.5, 0.5]).is_none());
    }
}
