//! [`Executor`]: the crate's one parallel executor.
//!
//! Work is cut into numbered chunks that do not depend on the thread count. Chunks run on a
//! rayon pool of the requested size, a window at a time, and their outputs are handed to the
//! caller's fold strictly in chunk order, so every sum (and hence every bit of a result) is
//! the same for any number of threads. A panic in a chunk is caught there and becomes one
//! [`Error::IntegrandPanicked`] naming the chunk's first sample and the panic message; of
//! several errors in a window, the one of the lowest chunk is reported, so errors too are
//! independent of the thread count.
//!
//! Nested use (an integrand that itself integrates) runs on the pool it is already on:
//! rayon's work stealing then shares the outer run's threads instead of starting more.
//!
//! With a [`Cluster`] (the `mpi` feature), each window is dealt to the MPI ranks and the
//! outputs of every rank are gathered to all before the fold (see `distributed`), so every
//! rank folds the same outputs in the same order as one process would.

use std::cell::Cell;
use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

use rayon::prelude::*;
use rayon::{ThreadPool, ThreadPoolBuilder};

use super::Limits;
#[cfg(feature = "mpi")]
use super::cluster::Cluster;
use crate::error::{Error, Result};
use crate::panics::guarded;
use crate::stats::StopReason;
use crate::threads::{available_threads, caches_held, release_caches};

/// Work cut into numbered chunks, each evaluated with a per-thread scratch space.
pub(crate) trait ChunkJob: Sync {
    /// Buffers a thread reuses from chunk to chunk.
    type Scratch;
    /// What one chunk produces.
    type Output: Send + Transfer;

    /// A fresh scratch space.
    fn scratch(&self) -> Result<Self::Scratch>;

    /// Evaluates chunk `chunk`; `None` when a limit was reached midway and the chunk's work
    /// was dropped (a long chunk checks `limits` between its blocks, so that a run stops
    /// within a block of work whatever its chunks cost; the chunk then counts as not started).
    fn run(
        &self,
        scratch: &mut Self::Scratch,
        chunk: u64,
        limits: &Limits,
    ) -> Result<Option<Self::Output>>;

    /// Where a chunk starts, as `(replicate, first sample index)` (an iteration, stratum or
    /// pass in place of the replicate where the method has those): named by the error of a
    /// panic in the chunk.
    fn origin(&self, chunk: u64) -> (u64, u64);

    /// How many consecutive chunks a thread claims at once (at least 1; 1 by default). A job
    /// whose chunks share an expensive resource built on first use (a Poisson-disk pass) claims
    /// the chunks of one such resource together, so that threads build different ones in
    /// parallel instead of waiting on the same one. Outputs are folded in chunk order either
    /// way, so the claim size changes no bits.
    fn claim(&self) -> u64 {
        1
    }

    /// The number of tail tasks of the (non-empty) window `chunks`: work that needs every
    /// chunk of the window finished (a VEGAS grid's adaptation, one task per axis). The
    /// window's threads claim them as they run out of chunks, so that none of them goes to
    /// sleep and has to be woken for that work. Tail tasks run in one process only: over a
    /// cluster each rank's window is its share of the chunks, and the job does its tail work
    /// after the exchange. None by default.
    fn tail_tasks(&self, _chunks: &Range<u64>) -> usize {
        0
    }

    /// Runs tail task `task`, once every chunk of the window is done (chunks a limit skipped
    /// or that failed included); what it computes is the job's to keep.
    fn run_tail(&self, _task: usize) {}
}

/// What a chunk's output needs to travel between MPI ranks: serde's traits with the `mpi`
/// feature, nothing without it.
#[cfg(feature = "mpi")]
pub(crate) trait Transfer: serde::Serialize + serde::de::DeserializeOwned {}
#[cfg(feature = "mpi")]
impl<T: serde::Serialize + serde::de::DeserializeOwned> Transfer for T {}
/// What a chunk's output needs to travel between MPI ranks: nothing without the `mpi`
/// feature.
#[cfg(not(feature = "mpi"))]
pub(crate) trait Transfer {}
#[cfg(not(feature = "mpi"))]
impl<T> Transfer for T {}

/// The outputs of a window of work units, as each share of it (one per MPI rank, or the whole
/// window in one process) with that share's outputs in order (`None` where a limit skipped
/// work), and the limit reached, if one was.
pub(super) type WindowOutputs<T> = (Vec<(Range<u64>, Vec<Option<T>>)>, Option<StopReason>);

/// The chunks one thread ran in a window, as `(offset in the window, output)`.
type Claimed<T> = Vec<(usize, Result<Option<T>>)>;

/// How [`Executor::run_grouped`] cuts chunks into groups and groups into windows.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Grouping {
    /// Chunks per group (at least 1).
    chunks: u64,
    /// Groups evaluated at once, at most (at least 1): bounds the outputs held in memory.
    window: u64,
}

impl Grouping {
    /// Groups of `chunks` chunks, `window` groups at a time (each at least 1).
    pub(crate) fn new(chunks: u64, window: u64) -> Grouping {
        Grouping {
            chunks: chunks.max(1),
            window: window.max(1),
        }
    }

    /// The first chunk of group `group` of `chunks` (past their end for the last group's
    /// successors).
    fn first_chunk(&self, chunks: &Range<u64>, group: u64) -> u64 {
        chunks.start + group * self.chunks
    }

    /// The chunks of `groups`, within `chunks`. A rank's share of a window may be empty and
    /// start past the last group, whose first chunk lies beyond the last chunk: both ends
    /// are clamped.
    fn chunks_of(&self, chunks: &Range<u64>, groups: Range<u64>) -> Range<u64> {
        let at = |group| self.first_chunk(chunks, group).min(chunks.end);
        at(groups.start)..at(groups.end)
    }
}

/// The most threads started per available core, whatever a run asks for.
const MAX_THREADS_PER_CORE: usize = 4;

/// Runs [`ChunkJob`]s on a fixed number of threads.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Executor {
    threads: usize,
    /// The MPI ranks that share the work, if the run is spread over several.
    #[cfg(feature = "mpi")]
    cluster: Option<Cluster>,
}

impl Executor {
    /// An executor for a `.threads(..)` setting: at least 1; `None` means all available.
    /// More than [`MAX_THREADS_PER_CORE`] per available core are not started (the result is
    /// the same for any count, and more would only contend).
    pub(crate) fn new(threads: Option<usize>) -> Result<Executor> {
        let threads = match threads {
            Some(0) => return Err(Error::invalid("threads", 0, "at least 1")),
            Some(t) => t.min(MAX_THREADS_PER_CORE * available_threads()),
            None => available_threads(),
        };
        Ok(Executor {
            threads,
            #[cfg(feature = "mpi")]
            cluster: None,
        })
    }

    /// This executor, spreading its work over `cluster` (when it has more than one rank).
    #[cfg(feature = "mpi")]
    pub(crate) fn spread_over(mut self, cluster: Option<Cluster>) -> Executor {
        self.cluster = cluster.filter(|c| c.size() > 1);
        self
    }

    /// Why the run must stop now, if it must: the reading of `limits` on this process, or,
    /// over a cluster, the first reading in rank order, so that every rank agrees.
    pub(crate) fn reached(&self, limits: &Limits) -> Result<Option<StopReason>> {
        #[cfg(feature = "mpi")]
        if let Some(cluster) = self.cluster {
            return super::distributed::agreed(cluster, limits.reached());
        }
        Ok(limits.reached())
    }

    /// Whether the work is spread over the ranks of a cluster.
    pub(crate) fn spread(&self) -> bool {
        #[cfg(feature = "mpi")]
        if self.cluster.is_some() {
            return true;
        }
        false
    }

    /// The number of threads.
    pub(crate) fn threads(&self) -> usize {
        self.threads
    }

    /// Evaluates chunks `chunks` of `job`, at most `window` at a time (which bounds the
    /// outputs held in memory), and hands each output to `fold` in chunk order. Stops at the
    /// first error, in chunk order, of a job or of `fold`.
    ///
    /// `limits` are checked before every chunk: once one is reached, no chunk starts, the
    /// chunks finished before the first one skipped are folded, and the reason is returned
    /// (`None` when every chunk was folded).
    pub(crate) fn run<J: ChunkJob>(
        &self,
        job: &J,
        chunks: Range<u64>,
        window: u64,
        limits: &Limits,
        fold: impl FnMut(u64, J::Output) -> Result<()>,
    ) -> Result<Option<StopReason>> {
        let unmerged = |_: &mut J::Output, _: J::Output| {};
        self.run_grouped(
            job,
            chunks,
            Grouping::new(1, window),
            limits,
            unmerged,
            fold,
        )
    }

    /// [`run`](Self::run) with the outputs of each group of `grouping.chunks` consecutive
    /// chunks (counted from `chunks.start`) merged into one, left to right, before `fold`
    /// gets it with the group's first chunk. Groups are fixed by chunk numbers alone, so the
    /// merged outputs have the same bits for any thread or rank count. Over a cluster the
    /// ranks share each window by chunks, evenly (shares of whole groups would leave one rank
    /// idle for a group's time in every window that has an odd number of them); each rank
    /// merges the chunks it ran group by group before the exchange, and a group split between
    /// two ranks is merged after it, left to right as in one process: a job whose output
    /// travels shortened (VEGAS's training data, as their sum) must send the part that
    /// continues a group as it is.
    pub(crate) fn run_grouped<J: ChunkJob>(
        &self,
        job: &J,
        chunks: Range<u64>,
        grouping: Grouping,
        limits: &Limits,
        merge: impl Fn(&mut J::Output, J::Output),
        mut fold: impl FnMut(u64, J::Output) -> Result<()>,
    ) -> Result<Option<StopReason>> {
        let size = grouping.chunks;
        let groups = (chunks.end.saturating_sub(chunks.start)).div_ceil(size);
        let local = |share: Range<u64>| {
            let outputs = self.window(job, share.clone(), limits)?;
            Ok(Executor::merged(
                outputs,
                share.start - chunks.start,
                size,
                &merge,
            ))
        };
        let mut start = 0;
        while start < groups {
            if let Some(reason) = self.reached(limits)? {
                return Ok(Some(reason));
            }
            let end = start.saturating_add(grouping.window).min(groups);
            let window = grouping.chunks_of(&chunks, start..end);
            let (shares, stop) = self.outputs(window, &local, limits)?;
            let outputs = Executor::joined(shares, chunks.start, size, &merge);
            for (group, output) in (start..end).zip(outputs) {
                match output {
                    Some(output) => fold(grouping.first_chunk(&chunks, group), output)?,
                    None => return Ok(Some(stop.unwrap_or(StopReason::Cancelled))),
                }
            }
            start = end;
        }
        Ok(None)
    }

    /// The `outputs` of consecutive chunks, from `offset` chunks after the run's first on,
    /// merged in order by the groups of `size` they fall in (the first and last group may be
    /// parts); `None` for a group with a chunk a limit skipped. Merging is meant to be cheap
    /// against the chunks' work (an addition of arrays), so it is done here rather than
    /// handed to other threads.
    fn merged<T>(
        outputs: Vec<Option<T>>,
        offset: u64,
        size: u64,
        merge: &impl Fn(&mut T, T),
    ) -> Vec<Option<T>> {
        if size == 1 {
            return outputs;
        }
        let mut outputs = outputs.into_iter();
        let mut groups = Vec::new();
        let mut take = size - offset % size;
        loop {
            let mut group = outputs.by_ref().take(take as usize);
            take = size;
            let Some(first) = group.next() else {
                break;
            };
            let merged = first.and_then(|first| {
                group.try_fold(first, |mut merged, output| {
                    merge(&mut merged, output?);
                    Some(merged)
                })
            });
            // Drain the rest of a group cut short, so that the next group starts in place.
            group.for_each(drop);
            groups.push(merged);
        }
        groups
    }

    /// The groups of a window, in order, from each share's [`merged`](Self::merged) outputs:
    /// a group split between two shares is the first share's part merged with the second's
    /// (`None` if either is). `first` is the run's first chunk.
    fn joined<T>(
        shares: Vec<(Range<u64>, Vec<Option<T>>)>,
        first: u64,
        size: u64,
        merge: &impl Fn(&mut T, T),
    ) -> Vec<Option<T>> {
        let mut groups: Vec<(u64, Option<T>)> = Vec::new();
        for (share, parts) in shares {
            let first_group = (share.start - first) / size;
            for (group, part) in (first_group..).zip(parts) {
                match groups.last_mut() {
                    Some((last, joined)) if *last == group => {
                        *joined = match (joined.take(), part) {
                            (Some(mut joined), Some(part)) => {
                                merge(&mut joined, part);
                                Some(joined)
                            }
                            _ => None,
                        };
                    }
                    _ => groups.push((group, part)),
                }
            }
        }
        groups.into_iter().map(|(_, output)| output).collect()
    }

    /// `f` of each of `items`, in order, computed in parallel where threads allow: for work
    /// that splits into independent pieces (the axes of a grid), whose results do not depend
    /// on the thread count.
    pub(crate) fn map_each<T: Send, R: Send>(
        &self,
        items: Vec<T>,
        f: impl Fn(T) -> R + Sync,
    ) -> Vec<R> {
        if self.threads == 1 || items.len() < 2 {
            return items.into_iter().map(f).collect();
        }
        let len = items.len();
        let items: Vec<Slot<T>> = items.into_iter().map(|t| Mutex::new(Some(t))).collect();
        let results: Vec<Slot<R>> = (0..len).map(empty).collect();
        self.each_worker(len, &|i| {
            let result = lock(&items[i]).take().map(&f);
            *lock(&results[i]) = result;
        });
        results.into_iter().filter_map(into_inner).collect()
    }

    /// The outputs `local` computes from the chunks `units` (`None` for work a limit
    /// skipped), and the limit reached if one was: computed here from the whole range, or by
    /// the ranks of the cluster, each from its share, and gathered, share by share.
    fn outputs<T: Send + Transfer>(
        &self,
        units: Range<u64>,
        local: &impl Fn(Range<u64>) -> Result<Vec<Option<T>>>,
        limits: &Limits,
    ) -> Result<WindowOutputs<T>> {
        #[cfg(feature = "mpi")]
        if let Some(cluster) = self.cluster {
            return super::distributed::gathered(cluster, units, local, limits);
        }
        let outputs = local(units.clone())?;
        Ok((vec![(units, outputs)], limits.reached()))
    }

    /// The outputs of chunks `chunks`, in order; `None` for the chunks not started because a
    /// limit was reached. The job's tail tasks have run when it returns.
    fn window<J: ChunkJob>(
        &self,
        job: &J,
        chunks: Range<u64>,
        limits: &Limits,
    ) -> Result<Vec<Option<J::Output>>> {
        let one = |scratch: &mut J::Scratch, chunk: u64| {
            if limits.reached().is_some() {
                return Ok(None);
            }
            guarded(job.origin(chunk), || job.run(scratch, chunk, limits))
        };
        let first = chunks.start;
        let len = usize::try_from(chunks.end - first).map_err(|_| Error::IndexOutOfRange {
            what: "chunks in one window",
            limit: usize::MAX as u64,
        })?;
        let tails = if self.spread() || chunks.is_empty() {
            0
        } else {
            job.tail_tasks(&chunks)
        };
        // A panic in a tail task is reported as one in the window's last chunk.
        let last = chunks.end.saturating_sub(1);
        let tail = |task| {
            guarded(job.origin(last), || {
                job.run_tail(task);
                Ok(())
            })
        };
        if self.threads == 1 {
            let mut scratch = job.scratch()?;
            let outputs = chunks.map(|chunk| one(&mut scratch, chunk)).collect();
            (0..tails).try_for_each(tail)?;
            return outputs;
        }
        // Each thread claims the next chunk when it is free, so a thread that wakes late takes
        // less of the window instead of an even share; outputs go back to chunk order after.
        // A thread out of chunks waits, spinning a little, for the window's last chunks and
        // then claims tail tasks; one that waits longer gives up (the thread of a last chunk
        // may be waiting on it, in nested parallel work) and the tasks left run here after.
        let size = usize::try_from(job.claim())
            .unwrap_or(usize::MAX)
            .clamp(1, len.max(1));
        let next = AtomicUsize::new(0);
        let done = AtomicUsize::new(0);
        let next_tail = AtomicUsize::new(0);
        let claim = || -> Result<Claimed<J::Output>> {
            let mut scratch = job.scratch()?;
            let mut mine = Vec::new();
            loop {
                let start = next.fetch_add(size, Ordering::Relaxed);
                if start >= len {
                    break;
                }
                for offset in start..(start + size).min(len) {
                    mine.push((offset, one(&mut scratch, first + offset as u64)));
                    done.fetch_add(1, Ordering::Release);
                }
            }
            if tails > 0 && awaited(|| done.load(Ordering::Acquire) == len) {
                loop {
                    let task = next_tail.fetch_add(1, Ordering::Relaxed);
                    if task >= tails {
                        break;
                    }
                    tail(task)?;
                }
            }
            Ok(mine)
        };
        let workers = self.threads.min(len.div_ceil(size).max(tails));
        let claimed: Vec<Slot<Result<Claimed<J::Output>>>> = (0..workers).map(empty).collect();
        self.each_worker(workers, &|worker| {
            let mine = claim();
            *lock(&claimed[worker]) = Some(mine);
        });
        (next_tail.load(Ordering::Relaxed).min(tails)..tails).try_for_each(tail)?;
        let mut outputs: Vec<Option<Result<Option<J::Output>>>> = (0..len).map(|_| None).collect();
        for thread in claimed.into_iter().filter_map(into_inner) {
            for (offset, output) in thread? {
                outputs[offset] = Some(output);
            }
        }
        // Every chunk was claimed; one that was not would count as not started.
        outputs.into_iter().map(|o| o.unwrap_or(Ok(None))).collect()
    }

    /// Runs `a` and `b`, in parallel where threads allow, each with panics caught (reported
    /// at `origin`). Meant for recursive work inside a chunk of [`run`](Self::run).
    pub(crate) fn join<A: Send, B: Send>(
        &self,
        origin: (u64, u64),
        a: impl FnOnce() -> Result<A> + Send,
        b: impl FnOnce() -> Result<B> + Send,
    ) -> (Result<A>, Result<B>) {
        if self.threads == 1 {
            return (guarded(origin, a), guarded(origin, b));
        }
        let (mut a, mut b) = (Some(a), Some(b));
        let (mut from_a, mut from_b) = (None, None);
        self.join_erased(
            &mut || from_a = a.take().map(|a| guarded(origin, a)),
            &mut || from_b = b.take().map(|b| guarded(origin, b)),
        );
        match (from_a, from_b) {
            (Some(a), Some(b)) => (a, b),
            _ => unreachable!("rayon::join returns after running both closures"),
        }
    }

    /// [`join`](Self::join) on closures behind references, so that rayon's machinery is
    /// compiled once rather than for every pair of closure types.
    fn join_erased(&self, a: &mut (dyn FnMut() + Send), b: &mut (dyn FnMut() + Send)) {
        self.install(&mut || {
            rayon::join(&mut *a, &mut *b);
        });
    }

    /// Runs `op` on a thread of this executor's pool (or of the pool the caller is already a
    /// worker of), so that the parallel work it starts needs no handing over between threads;
    /// on the calling thread with one thread, or over a cluster, whose messages must all leave
    /// from the thread that initialized MPI.
    pub(crate) fn on_pool<R: Send>(&self, op: impl FnOnce() -> R + Send) -> R {
        if self.spread() || self.threads == 1 {
            return op();
        }
        let mut op = Some(op);
        let mut result = None;
        self.install(&mut || result = op.take().map(|op| op()));
        match result {
            Some(result) => result,
            None => unreachable!("install returns after running its operation"),
        }
    }

    /// Runs `work(worker)` for each of `workers` workers, in parallel on this executor's pool.
    fn each_worker(&self, workers: usize, work: &(dyn Fn(usize) + Sync)) {
        self.install(&mut || (0..workers).into_par_iter().for_each(work));
    }

    /// Runs `op` on this executor's pool, or on the pool the caller is already a worker of.
    /// The helpers above reach rayon only through here and [`each_worker`](Self::each_worker),
    /// with closures behind references: rayon's generic machinery is then compiled a few
    /// times in all rather than again for every job and closure type a program runs.
    fn install(&self, op: &mut (dyn FnMut() + Send)) {
        if rayon::current_thread_index().is_some() {
            return op();
        }
        match pool(self.threads) {
            Some(pool) => pool.install(op),
            // No threads could be started: the work still gets done, on this one.
            None => op(),
        }
    }
}

/// A run under way on this thread, from [`RunScope::enter`] until dropped.
pub(crate) struct RunScope {
    _private: (),
}

impl RunScope {
    /// Marks a run on this thread until the returned scope is dropped. When the outermost run
    /// of a thread outside the pools ends, the caches that threads keep between fills (those
    /// registered in `crate::threads`) are released on this thread and on every worker of
    /// every pool: the pools live for the process, and an idle worker should not hold them.
    pub(crate) fn enter() -> RunScope {
        RUNS.with(|runs| runs.set(runs.get() + 1));
        RunScope { _private: () }
    }
}

thread_local! {
    /// The runs under way on this thread (more than one when an integrand integrates).
    static RUNS: Cell<usize> = const { Cell::new(0) };
}

impl Drop for RunScope {
    fn drop(&mut self) {
        let outermost = RUNS.with(|runs| {
            runs.set(runs.get() - 1);
            runs.get() == 0
        });
        if !outermost || rayon::current_thread_index().is_some() || !caches_held() {
            return;
        }
        release_caches();
        let pools: Vec<Arc<ThreadPool>> = pools().iter().map(|(_, p)| Arc::clone(p)).collect();
        for pool in pools {
            pool.broadcast(|_| release_caches());
        }
    }
}

/// How long a thread out of chunks waits for a window's last chunks before it leaves the tail
/// tasks to others: about the time of a cheap integrand's chunk.
const TAIL_WAIT: Duration = Duration::from_micros(500);

/// Whether `ready` became true within [`TAIL_WAIT`], spinning then yielding while it waits.
fn awaited(ready: impl Fn() -> bool) -> bool {
    let start = Instant::now();
    let mut spins = 0u32;
    while !ready() {
        if spins < 1 << 10 {
            std::hint::spin_loop();
            spins += 1;
        } else if start.elapsed() > TAIL_WAIT {
            return false;
        } else {
            std::thread::yield_now();
        }
    }
    true
}

/// The pool of `threads` workers, built on first use and kept for the process (one per
/// thread count a program asks for).
fn pool(threads: usize) -> Option<Arc<ThreadPool>> {
    let mut pools = pools();
    if let Some((_, pool)) = pools.iter().find(|(n, _)| *n == threads) {
        return Some(Arc::clone(pool));
    }
    let pool = ThreadPoolBuilder::new()
        .num_threads(threads)
        .thread_name(|i| format!("mcint-worker-{i}"))
        .build()
        .ok()?;
    let pool = Arc::new(pool);
    pools.push((threads, Arc::clone(&pool)));
    Some(pool)
}

/// Where a parallel worker leaves what it computed.
type Slot<T> = Mutex<Option<T>>;

/// An empty [`Slot`] (whatever the index it is made for).
fn empty<T>(_: usize) -> Slot<T> {
    Mutex::new(None)
}

/// `mutex` locked (a poisoned one too: the panic that poisoned it is reported on its own).
fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(PoisonError::into_inner)
}

/// What `slot` holds, once its lock is no longer shared.
fn into_inner<T>(slot: Slot<T>) -> Option<T> {
    slot.into_inner().unwrap_or_else(PoisonError::into_inner)
}

/// The pools built so far, by thread count.
fn pools() -> MutexGuard<'static, Vec<(usize, Arc<ThreadPool>)>> {
    static POOLS: Mutex<Vec<(usize, Arc<ThreadPool>)>> = Mutex::new(Vec::new());
    lock(&POOLS)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Integrator;
    use crate::pdf::UniformBox;
    use crate::sampler::{Halton, Scramble, thread_table_slots};
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// Squares of `0..n`, chunk by chunk, `claim` chunks at a time; panics at chunk `bad`.
    struct Squares {
        bad: Option<u64>,
        claim: u64,
    }

    impl ChunkJob for Squares {
        type Scratch = Vec<u64>;
        type Output = u64;

        fn scratch(&self) -> Result<Vec<u64>> {
            Ok(Vec::new())
        }

        fn run(&self, scratch: &mut Vec<u64>, chunk: u64, _: &Limits) -> Result<Option<u64>> {
            assert!(Some(chunk) != self.bad, "chunk {chunk} is bad");
            scratch.push(chunk);
            Ok(Some(chunk * chunk))
        }

        fn origin(&self, chunk: u64) -> (u64, u64) {
            (chunk / 10, chunk * 100)
        }

        fn claim(&self) -> u64 {
            self.claim
        }
    }

    #[test]
    fn outputs_arrive_in_chunk_order_for_any_thread_count_and_claim() {
        for (threads, claim) in [(1, 1), (2, 1), (3, 1), (8, 1), (2, 3), (3, 7), (8, 200)] {
            let executor = Executor::new(Some(threads)).unwrap();
            let mut seen = Vec::new();
            executor
                .run(
                    &Squares { bad: None, claim },
                    5..105,
                    7,
                    &Limits::default(),
                    |chunk, out| {
                        seen.push((chunk, out));
                        Ok(())
                    },
                )
                .unwrap();
            let expected: Vec<(u64, u64)> = (5..105).map(|c| (c, c * c)).collect();
            assert_eq!(seen, expected, "{threads} threads, claims of {claim}");
        }
    }

    #[test]
    fn a_panic_becomes_one_error_naming_the_chunk_and_the_message() {
        for threads in [1, 2, 4] {
            let executor = Executor::new(Some(threads)).unwrap();
            let err = executor
                .run(
                    &Squares {
                        bad: Some(42),
                        claim: 1,
                    },
                    0..100,
                    16,
                    &Limits::default(),
                    |_, _| Ok(()),
                )
                .unwrap_err();
            assert_eq!(
                err,
                Error::IntegrandPanicked {
                    message: "chunk 42 is bad".to_string(),
                    replicate: 4,
                    first_index: 4200,
                },
                "{threads} threads"
            );
        }
    }

    #[test]
    fn fold_errors_stop_the_run() {
        let executor = Executor::new(Some(2)).unwrap();
        let mut folded = 0;
        let err = executor.run(
            &Squares {
                bad: None,
                claim: 1,
            },
            0..100,
            10,
            &Limits::default(),
            |chunk, _| {
                folded += 1;
                if chunk == 15 {
                    return Err(Error::invalid("chunk", chunk, "not 15"));
                }
                Ok(())
            },
        );
        assert!(err.is_err());
        assert_eq!(folded, 16);
    }

    #[test]
    fn join_catches_panics_and_nested_runs_use_the_outer_pool() {
        let executor = Executor::new(Some(2)).unwrap();
        let (a, b) = executor.join((1, 2), || Ok(1), || -> Result<u32> { panic!("right") });
        assert_eq!(a.unwrap(), 1);
        assert!(
            matches!(b, Err(Error::IntegrandPanicked { ref message, .. }) if message == "right")
        );
        // A run inside a run: the inner one sees the outer pool's worker index.
        let mut inner_on_pool = Vec::new();
        let outer = Squares {
            bad: None,
            claim: 1,
        };
        executor
            .run(&outer, 0..4, 4, &Limits::default(), |_, _| Ok(()))
            .unwrap();
        executor
            .join(
                (0, 0),
                || {
                    let mut sum = 0;
                    Executor::new(Some(3))?.run(
                        &outer,
                        0..10,
                        10,
                        &Limits::default(),
                        |_, out| {
                            sum += out;
                            Ok(())
                        },
                    )?;
                    Ok((sum, rayon::current_thread_index().is_some()))
                },
                || Ok(()),
            )
            .0
            .map(|r| inner_on_pool.push(r))
            .unwrap();
        assert_eq!(inner_on_pool, vec![(285, true)]);
    }

    /// Chunks that count themselves done (some with nested parallel work) and tail tasks
    /// that record, per window, what they found done.
    struct WithTails {
        executor: Executor,
        done: AtomicUsize,
        seen: Mutex<Vec<(u64, usize, usize)>>,
        window_end: AtomicUsize,
    }

    impl ChunkJob for WithTails {
        type Scratch = ();
        type Output = u64;

        fn scratch(&self) -> Result<()> {
            Ok(())
        }

        fn run(&self, _: &mut (), chunk: u64, _: &Limits) -> Result<Option<u64>> {
            // Every third chunk splits its work with `join`: a thread waiting there may pick
            // up another thread's job, which must not wait for this chunk forever.
            let work = |n: u64| (0..n * 1000).fold(0u64, |a, i| a.wrapping_add(i * i));
            let value = if chunk.is_multiple_of(3) {
                let (a, b) = self
                    .executor
                    .join((0, chunk), || Ok(work(chunk)), || Ok(work(3)));
                a? ^ b?
            } else {
                work(chunk)
            };
            self.done.fetch_add(1, Ordering::SeqCst);
            Ok(Some(value))
        }

        fn origin(&self, chunk: u64) -> (u64, u64) {
            (0, chunk)
        }

        fn tail_tasks(&self, chunks: &Range<u64>) -> usize {
            self.window_end.store(chunks.end as usize, Ordering::SeqCst);
            3
        }

        fn run_tail(&self, task: usize) {
            let end = self.window_end.load(Ordering::SeqCst) as u64;
            let done = self.done.load(Ordering::SeqCst);
            self.seen.lock().unwrap().push((end, task, done));
        }
    }

    #[test]
    fn tail_tasks_run_once_each_after_their_window() {
        for threads in [1, 2, 3, 8] {
            let executor = Executor::new(Some(threads)).unwrap();
            let job = WithTails {
                executor,
                done: AtomicUsize::new(0),
                seen: Mutex::new(Vec::new()),
                window_end: AtomicUsize::new(0),
            };
            let mut folded = 0;
            executor
                .run(&job, 0..40, 16, &Limits::default(), |_, _| {
                    folded += 1;
                    Ok(())
                })
                .unwrap();
            assert_eq!(folded, 40);
            let mut seen = job.seen.into_inner().unwrap();
            seen.sort();
            // Windows 0..16, 16..32 and 32..40: each tail task once, every chunk done.
            let expected: Vec<(u64, usize, usize)> = [16, 32, 40]
                .into_iter()
                .flat_map(|end| (0..3).map(move |task| (end, task, end as usize)))
                .collect();
            assert_eq!(seen, expected, "{threads} threads");
        }
    }

    #[test]
    fn a_cancelled_run_folds_the_chunks_before_the_first_one_skipped() {
        use super::super::CancelToken;
        for threads in [1, 2, 3] {
            let token = CancelToken::new();
            let limits = Limits::new(None, None, Some(token.clone()));
            let mut folded = Vec::new();
            let stop = Executor::new(Some(threads))
                .unwrap()
                .run(
                    &Squares {
                        bad: None,
                        claim: 1,
                    },
                    0..1000,
                    8,
                    &limits,
                    |chunk, _| {
                        folded.push(chunk);
                        if chunk == 20 {
                            token.cancel();
                        }
                        Ok(())
                    },
                )
                .unwrap();
            assert_eq!(stop, Some(StopReason::Cancelled));
            // The window holding chunk 20 was finished; nothing after it started.
            assert_eq!(folded, (0..24).collect::<Vec<u64>>(), "{threads} threads");
        }
        let limits = Limits::new(Some(std::time::Duration::ZERO), None, None);
        let stop = Executor::new(Some(2))
            .unwrap()
            .run(
                &Squares {
                    bad: None,
                    claim: 1,
                },
                0..10,
                4,
                &limits,
                |_, _| Ok(()),
            )
            .unwrap();
        assert_eq!(stop, Some(StopReason::TimeLimit));
    }

    #[test]
    fn a_share_of_groups_maps_to_its_chunks_even_empty_past_the_end() {
        // 20 chunks from chunk 5 in groups of 8: chunks 5..13, 13..21, 21..25.
        let grouping = Grouping::new(8, 8);
        let chunks = 5..25;
        assert_eq!(grouping.chunks_of(&chunks, 0..1), 5..13);
        assert_eq!(grouping.chunks_of(&chunks, 1..3), 13..25);
        // Past the last group the first chunk (29) lies past the end: clamped, not 29..25.
        assert_eq!(grouping.chunks_of(&chunks, 3..3), 25..25);
        assert_eq!(grouping.chunks_of(&chunks, 2..2), 21..21);
    }

    #[test]
    fn groups_split_between_shares_join_as_in_one_process() {
        // 20 chunks from chunk 5 in groups of 8, each output the list of its chunks, so a
        // merge out of order or a chunk merged twice shows.
        let merge = |a: &mut Vec<u64>, b: Vec<u64>| a.extend(b);
        let (first, size) = (5, 8);
        let outputs = |range: Range<u64>, skip: Option<u64>| -> Vec<Option<Vec<u64>>> {
            range.map(|c| (Some(c) != skip).then(|| vec![c])).collect()
        };
        for skip in [None, Some(12), Some(13), Some(20)] {
            let whole = Executor::merged(outputs(5..25, skip), 0, size, &merge);
            for cuts in [vec![], vec![15], vec![12, 13], vec![6, 7, 13, 21, 24, 25]] {
                let bounds: Vec<u64> = [5].into_iter().chain(cuts).chain([25]).collect();
                let shares = bounds
                    .windows(2)
                    .map(|w| {
                        let parts =
                            Executor::merged(outputs(w[0]..w[1], skip), w[0] - first, size, &merge);
                        (w[0]..w[1], parts)
                    })
                    .collect();
                let joined = Executor::joined(shares, first, size, &merge);
                assert_eq!(joined, whole, "cuts at {bounds:?}, chunk {skip:?} skipped");
            }
        }
        let whole = Executor::merged(outputs(5..25, None), 0, size, &merge);
        assert_eq!(whole[2], Some(vec![21, 22, 23, 24]));
        assert_eq!(
            Executor::merged(outputs(5..25, Some(13)), 0, size, &merge)[1],
            None
        );
    }

    #[test]
    fn zero_threads_are_refused_and_huge_counts_capped() {
        let err = Executor::new(Some(0)).unwrap_err();
        assert_eq!(err.to_string(), "invalid threads = 0: expected at least 1");
        assert!(Executor::new(None).unwrap().threads() >= 1);
        let most = MAX_THREADS_PER_CORE * available_threads();
        assert_eq!(Executor::new(Some(usize::MAX)).unwrap().threads(), most);
    }

    #[test]
    fn an_ended_run_leaves_no_sampler_tables_on_its_threads() {
        // Seven threads: a pool no other test uses, so nothing fills tables on it meanwhile.
        let threads = 7;
        let held_in_run = AtomicUsize::new(0);
        let integrand = |x: &[f64]| {
            held_in_run.fetch_max(thread_table_slots(), Ordering::Relaxed);
            x[0]
        };
        let halton = Halton::new(3, Scramble::Owen, 5).unwrap();
        let estimate = Integrator::over_box(integrand, UniformBox::unit(3).unwrap())
            .sampler(halton)
            .samples(1 << 14)
            .threads(threads)
            .run()
            .unwrap();
        assert!((estimate.mean - 0.5).abs() < 1e-3);
        assert!(
            held_in_run.load(Ordering::Relaxed) > 0,
            "no tables were kept"
        );
        assert_eq!(thread_table_slots(), 0);
        let pool = pool(Executor::new(Some(threads)).unwrap().threads()).unwrap();
        assert_eq!(
            pool.broadcast(|_| thread_table_slots()),
            vec![0; pool.current_num_threads()]
        );
    }
}
