//! Node images of nested scrambling kept across the fills of one thread.
//!
//! A pass of an Owen-scrambled Halton column is filled block by block (the Integrator asks for
//! 1024 points at a time), and the node of digit position `k` with prefix `p` serves every
//! index `i = p mod b^k` of the pass, in many blocks. The block kernel looks the images of its
//! positions with at most [`MEMO_RESIDUES`] residues up in tables that live as long as the
//! thread and are reset when the (base, key) of a column changes, so each node is computed once
//! per pass rather than once per block. The tables hold exactly what the kernel would compute,
//! so the values do not depend on what was filled before.

use std::cell::RefCell;
use std::collections::HashMap;

/// Positions whose table has at most this many residues (`b^(k+1)`) are memoized.
pub(super) const MEMO_RESIDUES: u64 = 1 << 16;
/// A table slot not computed yet (images are below `b < 2^17`).
pub(super) const UNSEEN: u32 = u32::MAX;
/// Table slots one thread keeps over all columns (4 bytes each: 8 MiB).
const BUDGET: usize = 1 << 21;

/// The tables of one column: its key, the tables of its positions one after another, and
/// how many slots of each table are computed.
struct Tables {
    key: u64,
    images: Vec<u32>,
    seen: Vec<usize>,
}

/// The tables of the columns this thread filled last, by base, and their total size.
#[derive(Default)]
struct Memo {
    columns: HashMap<u64, Tables>,
    slots: usize,
}

thread_local! {
    static MEMO: RefCell<Memo> = RefCell::new(Memo::default());
}

/// The tables of one column, lent to the block kernel: `images` holds the table of position
/// `k` at `starts[k] .. starts[k + 1]`, slot `r` the image of residue `r` (or [`UNSEEN`]).
pub(super) struct ColumnTables<'a> {
    pub(super) images: &'a mut [u32],
    seen: &'a mut Vec<usize>,
    starts: &'a [usize],
}

impl ColumnTables<'_> {
    /// The table of position `k`.
    pub(super) fn table(&self, k: usize) -> &[u32] {
        &self.images[self.starts[k]..self.starts[k + 1]]
    }

    /// Computes the [`UNSEEN`] slots among `from .. from + count` of position `k`'s table by
    /// runs, `compute(first, run)` writing the images of residues `first, first + 1, ..`
    /// into `run`. A table computed whole is not searched again.
    pub(super) fn complete(
        &mut self,
        k: usize,
        from: usize,
        count: usize,
        mut compute: impl FnMut(u64, &mut [u32]),
    ) {
        let table = &mut self.images[self.starts[k]..self.starts[k + 1]];
        if self.seen[k] == table.len() {
            return;
        }
        let end = from + count;
        let mut at = from;
        while let Some(skip) = find(&table[at..end], |x| x == UNSEEN) {
            let start = at + skip;
            let stop = find(&table[start..end], |x| x != UNSEEN).map_or(end, |run| start + run);
            compute(start as u64, &mut table[start..stop]);
            self.seen[k] += stop - start;
            at = stop;
        }
    }
}

/// The first index whose slot satisfies `pred`, searched 32 slots at a time (a test over a
/// whole group vectorizes; a search that stops at the first hit does not).
fn find(slots: &[u32], pred: impl Fn(u32) -> bool) -> Option<usize> {
    let mut at = 0;
    for group in slots.chunks(32) {
        if group.iter().fold(false, |any, &x| any | pred(x)) {
            return group.iter().position(|&x| pred(x)).map(|j| at + j);
        }
        at += group.len();
    }
    None
}

/// Runs `f` on the tables of column (`base`, `key`), position `k`'s at `starts[k] ..
/// starts[k + 1]`: this thread's tables if it filled the same column before (new slots
/// [`UNSEEN`]), or fresh ones. Fresh tables serve when the thread's memo is unavailable (during
/// thread teardown), and a thread that would exceed its budget forgets its other columns
/// first.
pub(super) fn with_tables<R>(
    base: u64,
    key: u64,
    starts: &[usize],
    f: impl FnOnce(&mut ColumnTables<'_>) -> R,
) -> R {
    let (len, positions) = (
        starts.last().copied().unwrap_or(0),
        starts.len().saturating_sub(1),
    );
    let mut f = Some(f);
    let kept = MEMO.try_with(|cell| {
        let Ok(mut memo) = cell.try_borrow_mut() else {
            return None;
        };
        let memo = &mut *memo;
        let column = memo.columns.entry(base).or_insert(Tables {
            key,
            images: Vec::new(),
            seen: Vec::new(),
        });
        if column.key != key {
            memo.slots -= column.images.len();
            column.key = key;
            column.images.clear();
            column.seen.clear();
        }
        let grow = len.saturating_sub(column.images.len());
        if grow > 0 && memo.slots + grow > BUDGET {
            memo.columns.retain(|&b, _| b == base);
            memo.slots = memo.columns.get(&base).map_or(0, |c| c.images.len());
        }
        let column = memo.columns.get_mut(&base).expect("inserted above");
        if grow > 0 {
            column.images.resize(len, UNSEEN);
            memo.slots += grow;
        }
        if column.seen.len() < positions {
            column.seen.resize(positions, 0);
        }
        let f = f.take().expect("called once");
        Some(f(&mut ColumnTables {
            images: &mut column.images[..len],
            seen: &mut column.seen,
            starts,
        }))
    });
    match (kept, f) {
        (Ok(Some(result)), _) => result,
        (_, Some(f)) => f(&mut ColumnTables {
            images: &mut vec![UNSEEN; len],
            seen: &mut vec![0; positions],
            starts,
        }),
        (_, None) => unreachable!("f returned inside the memo"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unseen_runs_are_computed_and_seen_slots_kept() {
        let starts = [0, 2, 12];
        let runs = with_tables(5, 9, &starts, |tables| {
            tables.images[2 + 3] = 7;
            tables.images[2 + 4] = 8;
            tables.seen[1] = 2;
            let mut runs = Vec::new();
            tables.complete(1, 1, 8, |first, run| {
                runs.push((first, run.len()));
                for (j, slot) in run.iter_mut().enumerate() {
                    *slot = 100 + first as u32 + j as u32;
                }
            });
            assert_eq!(
                tables.table(1),
                [UNSEEN, 101, 102, 7, 8, 105, 106, 107, 108, UNSEEN]
            );
            assert_eq!(tables.seen[1], 8);
            runs
        });
        assert_eq!(runs, [(1, 2), (5, 4)]);
        // A table computed whole is not searched.
        with_tables(5, 9, &starts, |tables| {
            tables.complete(0, 0, 2, |_, run| run.fill(1));
            tables.complete(0, 0, 2, |_, _| panic!("computed twice"));
            assert_eq!(tables.table(0), [1, 1]);
        });
    }

    #[test]
    fn tables_persist_per_key_and_reset_when_it_changes() {
        with_tables(7, 1, &[0, 4], |t| t.images[2] = 5);
        let kept = with_tables(7, 1, &[0, 4, 6], |t| t.images.to_vec());
        assert_eq!(kept[..3], [UNSEEN, UNSEEN, 5]);
        assert!(with_tables(7, 2, &[0, 6], |t| t
            .images
            .iter()
            .all(|&x| x == UNSEEN)));
        // Another base keeps its own tables.
        with_tables(11, 3, &[0, 2], |t| t.images[0] = 1);
        assert_eq!(with_tables(11, 3, &[0, 2], |t| t.images[0]), 1);
    }

    #[test]
    fn long_searches_find_the_first_hit() {
        let mut slots = vec![0u32; 100];
        assert_eq!(find(&slots, |x| x == 1), None);
        slots[70] = 1;
        slots[90] = 1;
        assert_eq!(find(&slots, |x| x == 1), Some(70));
        assert_eq!(find(&slots[71..], |x| x == 1), Some(19));
    }
}
