//! The grid's training data of an iteration, as the chunks produce them: one array per chunk,
//! kept on the thread that filled it.
//!
//! A chunk's array (two values per grid increment) is only ever written by the thread that
//! runs the chunk: it zeroes an array it filled before and adds its points. Everything after
//! reads: the arrays of each fixed group of chunks are summed, and the groups' sums summed in
//! order, increment by increment, inside the grid's per-axis adaptation. An array written by
//! one thread and then by another would cross between the cores' caches each time (an array
//! zeroed by the thread that folded it cost the next chunk 10-45% of its time on two threads).
//! Over MPI, a group's arrays travel as their sum, computed in the same order, so every rank
//! sums the same values in the same order as one process; where ranks split a group, the
//! arrays of its later part travel as they are, to be added to the first part's sum in order.

use std::sync::{Mutex, OnceLock, PoisonError};

/// One chunk's training data, with the thread that filled it (its reuse stays there).
pub(super) struct TrainingArray {
    /// The rayon worker index of the thread that filled it (`None` off the pool).
    filled_by: Option<usize>,
    pub(super) values: Vec<f64>,
}

/// The training arrays of a group of consecutive chunks, or of a part of one, in chunk order.
#[derive(Default)]
pub(super) struct GroupTraining {
    arrays: Vec<TrainingArray>,
    /// Whether the arrays begin with the group's first chunk, so that they may travel as
    /// their sum (the later part of a group split between ranks may not).
    #[cfg_attr(not(feature = "mpi"), allow(dead_code))]
    starts_group: bool,
}

impl GroupTraining {
    /// The array of one chunk, the first of its group or not.
    pub(super) fn of_chunk(array: TrainingArray, starts_group: bool) -> GroupTraining {
        GroupTraining {
            arrays: vec![array],
            starts_group,
        }
    }

    /// Appends the arrays of the group's next chunks.
    pub(super) fn append(&mut self, next: &mut GroupTraining) {
        self.arrays.append(&mut next.arrays);
    }
}

/// The sum over `range` of `arrays` into `sum`: the arrays added in order; `false` (and
/// `sum` untouched) without arrays.
fn sum_into<'a>(
    arrays: impl IntoIterator<Item = &'a TrainingArray>,
    range: std::ops::Range<usize>,
    sum: &mut [f64],
) -> bool {
    let mut arrays = arrays.into_iter();
    let Some(first) = arrays.next() else {
        return false;
    };
    sum.copy_from_slice(&first.values[range.clone()]);
    for array in arrays {
        for (s, v) in sum.iter_mut().zip(&array.values[range.clone()]) {
            *s += v;
        }
    }
    true
}

/// Sums `groups` of training data element by element over `range` (one axis): each group's
/// arrays in chunk order, then the groups' sums in order. The same bits whether a group
/// arrives as its arrays or as their sum from another rank. (Whole slices at a time, so the
/// additions vectorize; each element is still summed in that order.)
pub(super) fn summed(groups: &[GroupTraining], range: std::ops::Range<usize>) -> Vec<f64> {
    summed_over(groups.iter().map(|g| &g.arrays), range)
}

/// [`summed`] over groups given as their arrays.
fn summed_over<'a, G: IntoIterator<Item = &'a TrainingArray>>(
    groups: impl Iterator<Item = G>,
    range: std::ops::Range<usize>,
) -> Vec<f64> {
    let mut total = vec![0.0; range.len()];
    let mut group_sum = vec![0.0; range.len()];
    for group in groups {
        if sum_into(group, range.clone(), &mut group_sum) {
            for (t, s) in total.iter_mut().zip(&group_sum) {
                *t += s;
            }
        }
    }
    total
}

/// The training arrays of an iteration's chunks, each put in its chunk's slot by the thread
/// that ran it. In one process the grid adapts from them as soon as the iteration's last
/// chunk is done, on the threads that ran the chunks (see `Pass::run_tail`), with the same
/// sums as [`summed`] over groups of the same chunks.
pub(super) struct TrainingSlots(Vec<OnceLock<TrainingArray>>);

impl TrainingSlots {
    /// Empty slots for `chunks` chunks.
    pub(super) fn new(chunks: usize) -> TrainingSlots {
        TrainingSlots((0..chunks).map(|_| OnceLock::new()).collect())
    }

    /// Keeps chunk `chunk`'s array.
    pub(super) fn put(&self, chunk: usize, array: TrainingArray) {
        if let Some(slot) = self.0.get(chunk) {
            // Each chunk runs once an iteration; a second array could only be a repeat.
            let _ = slot.set(array);
        }
    }

    /// Whether every chunk has put its array.
    pub(super) fn complete(&self) -> bool {
        self.0.iter().all(|slot| slot.get().is_some())
    }

    /// The sums over `range` of the arrays, in groups of `group` chunks (see [`summed`]).
    pub(super) fn summed(&self, group: usize, range: std::ops::Range<usize>) -> Vec<f64> {
        summed_over(
            self.0
                .chunks(group)
                .map(|g| g.iter().filter_map(OnceLock::get)),
            range,
        )
    }

    /// Gives the arrays back to `spare`.
    pub(super) fn give_back(self, spare: &SpareTraining) {
        spare.keep(self.0.into_iter().filter_map(OnceLock::into_inner));
    }
}

/// Training arrays kept for reuse, each by the thread that filled it.
#[derive(Default)]
pub(super) struct SpareTraining(Mutex<Vec<TrainingArray>>);

impl SpareTraining {
    /// A zeroed array of `len` values for this thread: one it filled before, zeroed here, or a
    /// new one.
    pub(super) fn take(&self, len: usize) -> TrainingArray {
        let here = rayon::current_thread_index();
        let mine = {
            let mut spare = self.0.lock().unwrap_or_else(PoisonError::into_inner);
            let at = spare
                .iter()
                .position(|a| a.filled_by == here && a.values.len() == len);
            at.map(|at| spare.swap_remove(at))
        };
        match mine {
            Some(mut array) => {
                array.values.fill(0.0);
                array
            }
            None => TrainingArray {
                filled_by: here,
                values: vec![0.0; len],
            },
        }
    }

    /// Keeps the arrays of `groups` for later [`take`](Self::take)s.
    pub(super) fn give(&self, groups: Vec<GroupTraining>) {
        self.keep(groups.into_iter().flat_map(|g| g.arrays));
    }

    /// Keeps `arrays` for later [`take`](Self::take)s.
    fn keep(&self, arrays: impl IntoIterator<Item = TrainingArray>) {
        let mut spare = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        spare.extend(arrays);
    }
}

/// A group's training data travel between ranks as the bytes of their sum: exact, summed in
/// the order one process sums them, and far cheaper to encode than one CBOR float at a time.
/// The later part of a group split between ranks travels as its arrays, whose sum must go on
/// from the first part's.
#[cfg(feature = "mpi")]
mod transfer {
    use super::{GroupTraining, TrainingArray};
    use serde::de::{Error, SeqAccess, Visitor};
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    impl Serialize for GroupTraining {
        fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
            let sum = match self.arrays.first() {
                Some(first) if self.starts_group => {
                    let mut sum = vec![0.0; first.values.len()];
                    super::sum_into(&self.arrays, 0..sum.len(), &mut sum);
                    Some(sum)
                }
                _ => None,
            };
            let arrays: Vec<AsBytes> = match &sum {
                Some(sum) => vec![AsBytes(sum)],
                None => self.arrays.iter().map(|a| AsBytes(&a.values)).collect(),
            };
            (self.starts_group, arrays).serialize(s)
        }
    }

    /// Floats to send, as the bytes of their little-endian values.
    struct AsBytes<'a>(&'a [f64]);

    impl Serialize for AsBytes<'_> {
        fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
            let bytes: Vec<u8> = self.0.iter().flat_map(|v| v.to_le_bytes()).collect();
            s.serialize_bytes(&bytes)
        }
    }

    impl<'de> Deserialize<'de> for GroupTraining {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<GroupTraining, D::Error> {
            let (starts_group, arrays) = <(bool, Vec<Floats>)>::deserialize(d)?;
            let arrays = arrays
                .into_iter()
                .map(|Floats(values)| TrainingArray {
                    filled_by: None,
                    values,
                })
                .collect();
            Ok(GroupTraining {
                arrays,
                starts_group,
            })
        }
    }

    /// Floats received as the bytes of their little-endian values.
    struct Floats(Vec<f64>);

    impl<'de> Deserialize<'de> for Floats {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Floats, D::Error> {
            d.deserialize_byte_buf(FloatsVisitor).map(Floats)
        }
    }

    struct FloatsVisitor;

    impl<'de> Visitor<'de> for FloatsVisitor {
        type Value = Vec<f64>;

        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("the bytes of little-endian f64 values")
        }

        fn visit_bytes<E: Error>(self, bytes: &[u8]) -> Result<Vec<f64>, E> {
            if !bytes.len().is_multiple_of(8) {
                return Err(E::invalid_length(bytes.len(), &self));
            }
            Ok(bytes
                .chunks_exact(8)
                .map(|b| {
                    let mut value = [0; 8];
                    value.copy_from_slice(b);
                    f64::from_le_bytes(value)
                })
                .collect())
        }

        fn visit_byte_buf<E: Error>(self, bytes: Vec<u8>) -> Result<Vec<f64>, E> {
            self.visit_bytes(&bytes)
        }

        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<f64>, A::Error> {
            let mut bytes = Vec::new();
            while let Some(b) = seq.next_element::<u8>()? {
                bytes.push(b);
            }
            self.visit_bytes(&bytes)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn part(arrays: &[&[f64]], starts_group: bool) -> GroupTraining {
        GroupTraining {
            arrays: arrays
                .iter()
                .map(|v| TrainingArray {
                    filled_by: None,
                    values: v.to_vec(),
                })
                .collect(),
            starts_group,
        }
    }

    fn group(arrays: &[&[f64]]) -> GroupTraining {
        part(arrays, true)
    }

    #[test]
    fn groups_sum_their_arrays_in_order_then_each_other() {
        // 1e16 + 1 + 1 loses both ones one at a time; (1 + 1) + 1e16 keeps them.
        let groups = [group(&[&[1e16, 1.0], &[1.0, 2.0]]), group(&[&[1.0, 3.0]])];
        let sums = summed(&groups, 0..2);
        assert_eq!(sums, [(1e16 + 1.0) + 1.0, (1.0 + 2.0) + 3.0]);
        assert_eq!(summed(&groups, 1..2), [6.0]);
    }

    #[test]
    fn spare_arrays_come_back_zeroed_to_the_thread_that_filled_them() {
        let spare = SpareTraining::default();
        let mut a = spare.take(4);
        assert_eq!(a.values, [0.0; 4]);
        a.values[2] = 7.0;
        let address = a.values.as_ptr();
        spare.give(vec![GroupTraining::of_chunk(a, true)]);
        let again = spare.take(4);
        assert_eq!(again.values, [0.0; 4]);
        assert_eq!(again.values.as_ptr(), address);
        // Another length is a new array.
        assert_eq!(spare.take(6).values.len(), 6);
    }

    /// Over MPI a group travels as its sum; the total has the same bits as in one process.
    #[cfg(feature = "mpi")]
    #[test]
    fn a_group_sent_as_its_sum_gives_the_same_total() {
        let local = [
            group(&[&[1e16, 0.1], &[1.0, 0.2]]),
            group(&[&[1.0, 0.3], &[1.0, 1e-17]]),
        ];
        let sent = sent(&local[1]);
        assert_eq!(sent.arrays.len(), 1);
        let arrived = [group(&[&[1e16, 0.1], &[1.0, 0.2]]), sent];
        assert_eq!(bits(summed(&local, 0..2)), bits(summed(&arrived, 0..2)));
    }

    /// A group split between two ranks: its first part travels as a sum, its later part as
    /// arrays, and joined they sum to the bits of one process.
    #[cfg(feature = "mpi")]
    #[test]
    fn a_group_split_between_ranks_gives_the_same_total() {
        let whole = [group(&[
            &[1.0, 0.1],
            &[1e16, 0.2],
            &[1.0, 0.3],
            &[1.0, 1e-17],
        ])];
        let mut first = sent(&group(&[&[1.0, 0.1], &[1e16, 0.2]]));
        let mut later = sent(&part(&[&[1.0, 0.3], &[1.0, 1e-17]], false));
        assert_eq!((first.arrays.len(), later.arrays.len()), (1, 2));
        first.append(&mut later);
        assert_eq!(bits(summed(&whole, 0..2)), bits(summed(&[first], 0..2)));
        // Had the later part travelled as its sum, 1e16 + (1 + 1) would keep both ones.
        let mut both = sent(&group(&[&[1.0, 0.3], &[1.0, 1e-17]]));
        let mut first = sent(&group(&[&[1.0, 0.1], &[1e16, 0.2]]));
        first.append(&mut both);
        assert_ne!(bits(summed(&whole, 0..1)), bits(summed(&[first], 0..1)));
    }

    #[cfg(feature = "mpi")]
    fn sent(part: &GroupTraining) -> GroupTraining {
        let mut bytes = Vec::new();
        ciborium::into_writer(part, &mut bytes).unwrap();
        ciborium::from_reader(&bytes[..]).unwrap()
    }

    #[cfg(feature = "mpi")]
    fn bits(v: Vec<f64>) -> Vec<u64> {
        v.iter().map(|x| x.to_bits()).collect()
    }
}
