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

/// The tables of one column: its key and the tables of its positions, one after another.
struct Tables {
    key: u64,
    images: Vec<u32>,
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

/// Runs `f` on the tables of column (`base`, `key`), at least `len` slots long: this thread's
/// tables if it filled the same column before (new slots [`UNSEEN`]), or fresh ones. Fresh
/// tables serve when the thread's memo is unavailable (during thread teardown), and a thread
/// that would exceed its budget forgets its other columns first.
pub(super) fn with_tables<R>(base: u64, key: u64, len: usize, f: impl FnOnce(&mut [u32]) -> R) -> R {
    let mut f = Some(f);
    let kept = MEMO.try_with(|cell| {
        let Ok(mut memo) = cell.try_borrow_mut() else {
            return None;
        };
        let memo = &mut *memo;
        let column = memo.columns.entry(base).or_insert(Tables {
            key,
            images: Vec::new(),
        });
        if column.key != key {
            memo.slots -= column.images.len();
            column.key = key;
            column.images.clear();
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
        let f = f.take().expect("called once");
        Some(f(&mut column.images[..len]))
    });
    match (kept, f) {
        (Ok(Some(result)), _) => result,
        (_, Some(f)) => f(&mut vec![UNSEEN; len]),
        (_, None) => unreachable!("f returned inside the memo"),
    }
}

/// Computes the [`UNSEEN`] slots of `table[from .. from + count]` by runs, `compute(first,
/// run)` writing the images of residues `first, first + 1, ..` into `run`.
pub(super) fn fill_unseen(
    table: &mut [u32],
    from: usize,
    count: usize,
    mut compute: impl FnMut(u64, &mut [u32]),
) {
    let end = from + count;
    let mut at = from;
    while let Some(skip) = table[at..end].iter().position(|&x| x == UNSEEN) {
        let start = at + skip;
        let run = table[start..end].iter().position(|&x| x != UNSEEN);
        let stop = run.map_or(end, |run| start + run);
        compute(start as u64, &mut table[start..stop]);
        at = stop;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unseen_runs_are_computed_and_seen_slots_kept() {
        let mut table = vec![UNSEEN; 10];
        table[3] = 7;
        table[4] = 8;
        let mut runs = Vec::new();
        fill_unseen(&mut table, 1, 8, |first, run| {
            runs.push((first, run.len()));
            for (j, slot) in run.iter_mut().enumerate() {
                *slot = 100 + first as u32 + j as u32;
            }
        });
        assert_eq!(runs, [(1, 2), (5, 4)]);
        assert_eq!(
            table,
            [UNSEEN, 101, 102, 7, 8, 105, 106, 107, 108, UNSEEN]
        );
    }

    #[test]
    fn tables_persist_per_key_and_reset_when_it_changes() {
        with_tables(7, 1, 4, |t| t[2] = 5);
        assert_eq!(with_tables(7, 1, 6, |t| t.to_vec())[..3], [UNSEEN, UNSEEN, 5]);
        assert!(with_tables(7, 2, 6, |t| t.iter().all(|&x| x == UNSEEN)));
        // Another base keeps its own tables.
        with_tables(11, 3, 2, |t| t[0] = 1);
        assert_eq!(with_tables(11, 3, 2, |t| t[0]), 1);
    }
}
