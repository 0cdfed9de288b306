//! Node images of nested scrambling kept across the fills of one thread.
//!
//! A pass of an Owen-scrambled Halton column is filled block by block (the Integrator asks for
//! 1024 points at a time), and the node of digit position `k` with prefix `p` serves every
//! index `i = p mod b^k` of the pass, in many blocks. The block kernel looks up the nodes of
//! its positions with at most [`MEMO_RESIDUES`] prefixes, and the digit images of those with
//! at most as many residues, in tables that the thread keeps per column (base and key: one pass
//! of one sampler's dimension), so each node is computed once per pass rather than once per
//! block and per digit. The tables
//! hold exactly what the kernel would compute, so the values do not depend on what was filled
//! before; a thread past its budget forgets the other columns' tables.
//!
//! The engine's worker threads live for the process, so the tables are a cache registered in
//! `crate::threads`, which the engine releases on every thread when a run ends: an idle worker
//! then holds none.

use std::cell::RefCell;
use std::collections::HashMap;
use std::sync::atomic::{AtomicUsize, Ordering};

use crate::threads::{ThreadCache, register};

/// Positions with at most this many prefixes (`b^k`) keep their nodes, and those with at most
/// this many residues (`b^(k+1)`) their digit images.
pub(super) const MEMO_RESIDUES: u64 = 1 << 16;
/// A table slot not computed yet (images are below `b < 2^17`).
pub(super) const UNSEEN: u32 = u32::MAX;
/// A node slot not computed yet (a node uses at most the low 52 bits, see the block kernel's
/// `Nodes::parts`).
const UNSEEN_NODE: u64 = u64::MAX;
/// Table slots one thread keeps over all columns (4 bytes each, a node two: 8 MiB).
pub(super) const BUDGET: usize = 1 << 21;

/// The tables of one column: the image tables of its positions one after another, their node
/// tables likewise, and how many slots of each table are computed.
#[derive(Default)]
struct Tables {
    images: Vec<u32>,
    nodes: Vec<u64>,
    seen: Vec<usize>,
    nodes_seen: Vec<usize>,
    /// The thread's fill count at this column's last fill.
    last_use: u64,
}

impl Tables {
    /// Memory, in table slots.
    fn slots(&self) -> usize {
        self.images.len() + 2 * self.nodes.len()
    }
}

/// The tables of the columns this thread filled, by (base, key), and their total size.
#[derive(Default)]
struct Memo {
    columns: HashMap<(u64, u64), Tables>,
    slots: usize,
    /// Fills so far (of admitted or refused columns).
    clock: u64,
    /// The fills between two fills of one column, as recently seen (the longest, decaying):
    /// columns idle for much longer belong to finished passes.
    period: u64,
    /// Whether a column was admitted since the memo was made: counted in [`HOLDERS`].
    holding: bool,
}

impl Memo {
    /// See [`admit`].
    fn admit(&mut self, base: u64, key: u64, slots: usize) -> bool {
        self.clock += 1;
        let clock = self.clock;
        let held = match self.columns.get_mut(&(base, key)) {
            Some(column) => {
                let idle = clock - column.last_use;
                self.period = idle.max(self.period - self.period / 16);
                column.last_use = clock;
                column.slots()
            }
            None => 0,
        };
        let needed = slots.saturating_sub(held);
        if self.slots + needed > BUDGET {
            // Forget the columns of finished passes: idle for more than twice the period.
            let stale = 2 * self.period + 16;
            let mut freed = 0;
            self.columns.retain(|&id, column| {
                let keep = id == (base, key) || clock - column.last_use <= stale;
                if !keep {
                    freed += column.slots();
                }
                keep
            });
            self.slots -= freed;
        }
        if self.slots + needed > BUDGET {
            return false;
        }
        if !self.holding {
            self.holding = true;
            HOLDERS.fetch_add(1, Ordering::Relaxed);
            register(&NODE_TABLES);
        }
        self.columns.entry((base, key)).or_insert_with(|| Tables {
            last_use: clock,
            ..Tables::default()
        });
        true
    }
}

impl Drop for Memo {
    fn drop(&mut self) {
        if self.holding {
            HOLDERS.fetch_sub(1, Ordering::Relaxed);
        }
    }
}

/// Threads whose tables have held a column since their last [`release`].
static HOLDERS: AtomicUsize = AtomicUsize::new(0);

/// The tables as a cache of the threads that the engine releases when a run ends.
static NODE_TABLES: ThreadCache = ThreadCache {
    held: any_held,
    release,
};

/// Whether some thread may hold tables.
fn any_held() -> bool {
    HOLDERS.load(Ordering::Relaxed) > 0
}

/// Forgets this thread's tables and frees their memory.
fn release() {
    // Nothing to do on a thread that is exiting (no thread-local left) or that is inside a
    // fill (the tables are borrowed): a fill does not end runs.
    let _ = MEMO.try_with(|cell| {
        if let Ok(mut memo) = cell.try_borrow_mut() {
            *memo = Memo::default();
        }
    });
}

/// Table slots this thread holds.
#[cfg(test)]
pub(crate) fn slots_held() -> usize {
    MEMO.with(|cell| cell.borrow().slots)
}

/// Whether column (`base`, `key`) may keep tables of `slots` slots on this thread: yes if they
/// fit in the budget once the columns of finished passes are forgotten. A refused column is
/// filled without kept tables (so a thread that cycles through more columns than fit keeps the
/// first ones and does not evict a table for every fill).
pub(super) fn admit(base: u64, key: u64, slots: usize) -> bool {
    MEMO.try_with(|cell| {
        cell.try_borrow_mut()
            .is_ok_and(|mut memo| memo.admit(base, key, slots))
    })
    .unwrap_or(false)
}

thread_local! {
    static MEMO: RefCell<Memo> = RefCell::new(Memo::default());
}

/// The tables of one column, lent to the block kernel: `images` holds the image table of
/// position `k` at `starts[k] .. starts[k + 1]`, slot `r` the image of residue `r` (or
/// [`UNSEEN`]); `nodes` holds its node table at `node_starts[k] .. node_starts[k + 1]`, slot `p`
/// the node of prefix `p`.
pub(super) struct ColumnTables<'a> {
    images: &'a mut [u32],
    nodes: &'a mut [u64],
    seen: &'a mut [usize],
    nodes_seen: &'a mut [usize],
    starts: &'a [usize],
    node_starts: &'a [usize],
}

impl ColumnTables<'_> {
    /// The image table of position `k`.
    pub(super) fn table(&self, k: usize) -> &[u32] {
        &self.images[self.starts[k]..self.starts[k + 1]]
    }

    /// The node table of position `k`.
    pub(super) fn nodes(&self, k: usize) -> &[u64] {
        &self.nodes[self.node_starts[k]..self.node_starts[k + 1]]
    }

    /// Whether every slot of position `k`'s image table is computed.
    pub(super) fn is_complete(&self, k: usize) -> bool {
        self.seen[k] == self.starts[k + 1] - self.starts[k]
    }

    /// Computes the [`UNSEEN`] slots among `from .. from + count` of position `k`'s image
    /// table by runs, `compute(nodes, first, run)` writing the images of residues `first,
    /// first + 1, ..` into `run` from the position's node table `nodes`. A table computed whole
    /// is not searched again.
    pub(super) fn complete(
        &mut self,
        k: usize,
        from: usize,
        count: usize,
        mut compute: impl FnMut(&[u64], u64, &mut [u32]),
    ) {
        let table = &mut self.images[self.starts[k]..self.starts[k + 1]];
        let nodes = &self.nodes[self.node_starts[k]..self.node_starts[k + 1]];
        let fill_run = |first: u64, run: &mut [u32]| compute(nodes, first, run);
        complete_runs(table, UNSEEN, &mut self.seen[k], from, count, fill_run);
    }

    /// [`ColumnTables::complete`] for position `k`'s nodes, `compute(first, run)` writing the
    /// nodes of prefixes `first, first + 1, ..`.
    pub(super) fn complete_nodes(
        &mut self,
        k: usize,
        from: usize,
        count: usize,
        compute: impl FnMut(u64, &mut [u64]),
    ) {
        let nodes = &mut self.nodes[self.node_starts[k]..self.node_starts[k + 1]];
        complete_runs(
            nodes,
            UNSEEN_NODE,
            &mut self.nodes_seen[k],
            from,
            count,
            compute,
        );
    }
}

/// Computes the `unseen` slots among `from .. from + count` by runs, unless all `seen` of
/// them are computed.
fn complete_runs<T: Copy + Eq>(
    slots: &mut [T],
    unseen: T,
    seen: &mut usize,
    from: usize,
    count: usize,
    mut compute: impl FnMut(u64, &mut [T]),
) {
    if *seen == slots.len() {
        return;
    }
    let end = from + count;
    let mut at = from;
    while let Some(skip) = find(&slots[at..end], |x| x == unseen) {
        let start = at + skip;
        let stop = find(&slots[start..end], |x| x != unseen).map_or(end, |run| start + run);
        compute(start as u64, &mut slots[start..stop]);
        *seen += stop - start;
        at = stop;
    }
}

/// The first index whose slot satisfies `pred`, searched 32 slots at a time (a test over a
/// whole group vectorizes; a search that stops at the first hit does not).
fn find<T: Copy>(slots: &[T], pred: impl Fn(T) -> bool) -> Option<usize> {
    let mut at = 0;
    for group in slots.chunks(32) {
        if group.iter().fold(false, |any, &x| any | pred(x)) {
            return group.iter().position(|&x| pred(x)).map(|j| at + j);
        }
        at += group.len();
    }
    None
}

/// Runs `f` on the tables of column (`base`, `key`), position `k`'s images at `starts[k] ..
/// starts[k + 1]` and its nodes at `node_starts[k] .. node_starts[k + 1]`: this thread's
/// tables if the column was [`admit`]ted (new slots unseen), or fresh ones.
pub(super) fn with_tables<R>(
    base: u64,
    key: u64,
    admitted: bool,
    starts: &[usize],
    node_starts: &[usize],
    f: impl FnOnce(&mut ColumnTables<'_>) -> R,
) -> R {
    let last = |starts: &[usize]| starts.last().copied().unwrap_or(0);
    let (len, positions) = (last(starts), starts.len().saturating_sub(1));
    let (nodes, node_positions) = (last(node_starts), node_starts.len().saturating_sub(1));
    let mut f = Some(f);
    let kept = admitted.then(|| {
        MEMO.try_with(|cell| {
            let Ok(mut memo) = cell.try_borrow_mut() else {
                return None;
            };
            let memo = &mut *memo;
            let column = memo.columns.get_mut(&(base, key))?;
            let before = column.slots();
            column.images.resize(len.max(column.images.len()), UNSEEN);
            column
                .nodes
                .resize(nodes.max(column.nodes.len()), UNSEEN_NODE);
            column.seen.resize(positions.max(column.seen.len()), 0);
            let node_positions_kept = node_positions.max(column.nodes_seen.len());
            column.nodes_seen.resize(node_positions_kept, 0);
            memo.slots = memo.slots - before + column.slots();
            let f = f.take().expect("called once");
            Some(f(&mut ColumnTables {
                images: &mut column.images[..len],
                nodes: &mut column.nodes[..nodes],
                seen: &mut column.seen[..positions],
                nodes_seen: &mut column.nodes_seen[..node_positions],
                starts,
                node_starts,
            }))
        })
    });
    match (kept, f) {
        (Some(Ok(Some(result))), _) => result,
        (_, Some(f)) => f(&mut ColumnTables {
            images: &mut vec![UNSEEN; len],
            nodes: &mut vec![UNSEEN_NODE; nodes],
            seen: &mut vec![0; positions],
            nodes_seen: &mut vec![0; node_positions],
            starts,
            node_starts,
        }),
        (_, None) => unreachable!("f returned inside the memo"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unseen_runs_are_computed_from_the_nodes_and_seen_slots_kept() {
        let (starts, node_starts) = ([0, 2, 12], [0, 1, 3]);
        let runs = with_tables(5, 9, admit(5, 9, 99), &starts, &node_starts, |tables| {
            tables.images[2 + 3] = 7;
            tables.images[2 + 4] = 8;
            tables.seen[1] = 2;
            tables.complete_nodes(1, 0, 2, |first, run| {
                for (j, node) in run.iter_mut().enumerate() {
                    *node = 100 + first + j as u64;
                }
            });
            let mut runs = Vec::new();
            tables.complete(1, 1, 8, |nodes, first, run| {
                runs.push((first, run.len()));
                for (j, slot) in run.iter_mut().enumerate() {
                    let residue = first as usize + j;
                    *slot = nodes[residue % 2] as u32 + 10 * (residue / 2) as u32;
                }
            });
            assert_eq!(
                tables.table(1),
                [UNSEEN, 101, 110, 7, 8, 121, 130, 131, 140, UNSEEN]
            );
            assert_eq!(tables.nodes(1), [100, 101]);
            assert!(!tables.is_complete(1));
            runs
        });
        assert_eq!(runs, [(1, 2), (5, 4)]);
        // A table computed whole is not searched again; neither are its nodes.
        with_tables(5, 9, admit(5, 9, 99), &starts, &node_starts, |tables| {
            tables.complete(0, 0, 2, |_, _, run| run.fill(1));
            tables.complete(0, 0, 2, |_, _, _| panic!("computed twice"));
            assert!(tables.is_complete(0));
            tables.complete_nodes(1, 0, 2, |_, _| panic!("computed twice"));
        });
    }

    #[test]
    fn tables_persist_per_column() {
        with_tables(7, 1, admit(7, 1, 0), &[0, 4], &[], |t| t.images[2] = 5);
        let kept = with_tables(7, 1, admit(7, 1, 0), &[0, 4, 6], &[], |t| t.images.to_vec());
        assert_eq!(kept[..3], [UNSEEN, UNSEEN, 5]);
        // Another key of the same base (another pass or sampler) has tables of its own, and
        // filling it leaves the first one's.
        assert!(with_tables(7, 2, admit(7, 2, 0), &[0, 6], &[], |t| t
            .images
            .iter()
            .all(|&x| x == UNSEEN)));
        assert_eq!(
            with_tables(7, 1, admit(7, 1, 0), &[0, 4], &[], |t| t.images[2]),
            5
        );
        with_tables(11, 3, admit(11, 3, 0), &[0, 2], &[0, 1], |t| t.nodes[0] = 1);
        assert_eq!(
            with_tables(11, 3, admit(11, 3, 0), &[0, 2], &[0, 1], |t| t.nodes[0]),
            1
        );
    }

    #[test]
    fn a_full_thread_refuses_new_columns_until_the_old_ones_are_finished() {
        let (half, size) = ([0, BUDGET / 2 + 1], BUDGET / 2 + 1);
        assert!(admit(3, 1, size));
        with_tables(3, 1, true, &half, &[], |t| t.images[0] = 9);
        // A second column does not fit: it is filled without kept tables, and the first keeps
        // its own.
        assert!(!admit(3, 2, size));
        assert!(with_tables(3, 2, false, &half, &[], |t| t.images[0]) == UNSEEN);
        assert_eq!(
            with_tables(3, 1, admit(3, 1, size), &half, &[], |t| t.images[0]),
            9
        );
        // Once the first has been idle for far longer than columns are reused (its pass is
        // over), it is forgotten and the second admitted.
        for _ in 0..100 {
            admit(5, 5, 0);
        }
        assert!(admit(3, 2, size));
        with_tables(3, 2, true, &half, &[], |t| t.images[0] = 8);
        assert!(!admit(3, 1, size));
    }

    #[test]
    fn release_forgets_this_threads_tables() {
        with_tables(13, 4, admit(13, 4, 0), &[0, 4], &[], |t| t.images[1] = 6);
        assert!(slots_held() >= 4);
        release();
        assert_eq!(slots_held(), 0);
        assert!(with_tables(13, 4, admit(13, 4, 0), &[0, 4], &[], |t| t.images[1]) == UNSEEN);
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
