//! The scene queries' common machinery: object pairs shared out among threads, each pair's
//! result appended by the thread that took it, then merged in the pairs' order (so the answer
//! does not depend on the thread count).

use crate::error::{Error, Result};
use crate::threads;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Where one object pair's result is: which worker found it, and where in its list.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Span {
    worker: u32,
    start: usize,
    /// Number of results.
    pub len: usize,
    /// Did a limit cut this pair's query short?
    pub truncated: bool,
}

/// One thread's share of a query: its scratch `work` (a result buffer and counters) and what it
/// found, in the order of the object pairs it took.
#[derive(Debug)]
pub(super) struct Worker<W, T> {
    pub work: W,
    found: Vec<T>,
    /// The object pairs it took (their index among the candidates) and where their results are.
    taken: Vec<(usize, Span)>,
    error: Option<Error>,
}

impl<W: Default, T> Default for Worker<W, T> {
    fn default() -> Self {
        Worker {
            work: W::default(),
            found: Vec::new(),
            taken: Vec::new(),
            error: None,
        }
    }
}

/// The workers of a scene query and, per object pair of its last run, where the results are;
/// and where the merged result is written until the query succeeds. Kept in the caller's
/// result buffer, so that its memory serves the next query.
#[derive(Debug)]
pub(super) struct Shared<W, T> {
    workers: Vec<Worker<W, T>>,
    spans: Vec<Span>,
    /// The merged result of the run, swapped into the buffer's result by [`Shared::publish`].
    spare: Vec<T>,
}

impl<W, T> Default for Shared<W, T> {
    fn default() -> Self {
        Shared {
            workers: Vec::new(),
            spans: Vec::new(),
            spare: Vec::new(),
        }
    }
}

/// Threads for a scene query of `pairs` object pairs (`threads` as the options give it): the
/// pairs share the threads, each pair's query running on the thread that took it; a single
/// pair's query gets them all. Returns the threads to share the pairs among and the
/// `threads` option of each pair's query.
fn pair_threads(threads: u32, pairs: usize) -> (usize, u32) {
    let per_pair = if pairs > 1 { 1 } else { threads };
    (threads::resolve(threads), per_pair)
}

/// What one object pair's query gives: whether a limit cut it short.
pub(super) type Truncated = bool;

/// Appends a pair's `items` to `found`, failing with [`Error::OutOfMemory`] (and appending
/// nothing) when `found` cannot grow.
pub(super) fn append<T>(found: &mut Vec<T>, items: impl ExactSizeIterator<Item = T>) -> Result<()> {
    let n = items.len();
    found.try_reserve(n).map_err(|_| Error::OutOfMemory {
        bytes: n * std::mem::size_of::<T>(),
    })?;
    found.extend(items);
    Ok(())
}

/// A scene query's public result buffer: the result (`items`) and the machinery that fills it
/// (`shared`, whose workers keep a `$buffer` for the pair queries and sum `$stats`), with the
/// reading side of [`crate::query::result_buffer`] and `memory_bytes`. `$name`'s own
/// documentation comes first.
macro_rules! scene_results {
    (
        $(#[$doc:meta])*
        $name:ident, $item:ty, $buffer:ty, $stats:ty, $items:literal, as_slice: $as_slice:literal
    ) => {
        $(#[$doc])*
        #[derive(Debug, Default)]
        pub struct $name {
            items: Vec<$item>,
            shared: $crate::scene::share::Shared<$crate::scene::share::Work<$buffer, $stats>, $item>,
        }

        $crate::query::result_buffer!($name, $item, $items, as_slice: $as_slice);

        impl $name {
            /// Bytes of memory the buffer holds beyond the struct itself: the result, and the
            /// scratch space of the threads that filled it and merged their results.
            pub fn memory_bytes(&self) -> usize {
                $crate::csr::heap_bytes(&self.items) + self.shared.memory_bytes(<$buffer>::memory_bytes)
            }
        }
    };
}
pub(super) use scene_results;

/// One thread's scratch in a scene query: the result buffer its pair queries write, and the
/// counters it sums over the pairs it takes (zero at the start of every run).
#[derive(Debug, Default)]
pub(super) struct Work<B, S> {
    pub buffer: B,
    pub stats: S,
}

impl<B, S, T> Shared<Work<B, S>, T>
where
    B: Default + Send,
    S: Default + Send,
    T: Copy + Send,
{
    /// Runs `query` on every object pair of `candidates`, on the threads `threads` (the
    /// options' field) allows, one pair at a time each (pairs' costs differ by orders of
    /// magnitude). `query(work, pair, threads, found)` appends the pair's results to `found`;
    /// `threads` is what the pair's own query may use (see [`pair_threads`]). Fails with the
    /// first error a pair's query returned.
    pub fn run<Q>(&mut self, candidates: &[(u32, u32)], threads: u32, query: &Q) -> Result<()>
    where
        Q: Fn(&mut Work<B, S>, (u32, u32), u32, &mut Vec<T>) -> Result<Truncated> + Sync,
    {
        let (threads, per_pair) = pair_threads(threads, candidates.len());
        let threads = threads.min(candidates.len()).max(1);
        if self.workers.len() < threads {
            self.workers.resize_with(threads, Worker::default);
        }
        for w in &mut self.workers {
            w.found.clear();
            w.taken.clear();
            w.error = None;
            w.work.stats = S::default();
        }
        self.spans.clear();
        self.spans.resize(candidates.len(), Span::default());
        let one = |w: &mut Worker<Work<B, S>, T>, index: usize, pair| -> Span {
            let start = w.found.len();
            if w.error.is_some() {
                return Span::default();
            }
            let truncated = match query(&mut w.work, pair, per_pair, &mut w.found) {
                Ok(truncated) => truncated,
                Err(e) => {
                    w.error = Some(e);
                    w.found.truncate(start);
                    false
                }
            };
            Span {
                worker: index as u32,
                start,
                len: w.found.len() - start,
                truncated,
            }
        };
        if threads == 1 {
            let w = &mut self.workers[0];
            for (span, &pair) in self.spans.iter_mut().zip(candidates) {
                *span = one(w, 0, pair);
            }
        } else {
            let next = AtomicUsize::new(0);
            threads::on_each(
                threads::Step::ScenePairs,
                &mut self.workers[..threads],
                &|w: &mut Worker<Work<B, S>, T>, index| {
                    loop {
                        let k = next.fetch_add(1, Ordering::Relaxed);
                        let Some(&pair) = candidates.get(k) else {
                            break;
                        };
                        let span = one(w, index, pair);
                        w.taken.push((k, span));
                    }
                },
            );
            for w in &self.workers[..threads] {
                for &(k, span) in &w.taken {
                    self.spans[k] = span;
                }
            }
        }
        match self.workers.iter_mut().find_map(|w| w.error.take()) {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    /// Where each object pair's results are, in the order of the candidates of the last run.
    pub fn spans(&self) -> &[Span] {
        &self.spans
    }

    /// The workers' scratch, for their counters.
    pub fn works(&self) -> impl Iterator<Item = &Work<B, S>> {
        self.workers.iter().map(|w| &w.work)
    }

    /// The results of the pair at `span`.
    pub fn results(&self, span: &Span) -> &[T] {
        &self.workers[span.worker as usize].found[span.start..span.start + span.len]
    }

    /// Every result of the last run in the pairs' order, at most `limit` of them, merged
    /// (replacing what was merged before). Returns whether anything was left out: a pair's
    /// query cut short, or more results than `limit`. Fails, changing nothing else, when the
    /// merged result cannot grow.
    pub fn merge(&mut self, limit: usize) -> Result<bool> {
        let found: usize = self.spans.iter().map(|s| s.len).sum();
        let keep = found.min(limit);
        let mut out = std::mem::take(&mut self.spare);
        out.clear();
        let grown = out.try_reserve(keep).map_err(|_| Error::OutOfMemory {
            bytes: keep * std::mem::size_of::<T>(),
        });
        let mut truncated = found > limit;
        if grown.is_ok() {
            for s in &self.spans {
                truncated |= s.truncated;
                let room = keep - out.len();
                out.extend_from_slice(&self.results(s)[..s.len.min(room)]);
            }
        }
        self.spare = out;
        grown.map(|()| truncated)
    }

    /// The merged result, to replace or edit before it is published.
    pub fn merged(&mut self) -> &mut Vec<T> {
        &mut self.spare
    }

    /// Makes the merged result the buffer's `result` (the previous result's memory serves the
    /// next merge).
    pub fn publish(&mut self, result: &mut Vec<T>) {
        std::mem::swap(result, &mut self.spare);
    }

    /// Bytes of memory held beyond the struct itself, with `work_bytes` of each worker's
    /// scratch.
    pub fn memory_bytes(&self, work_bytes: impl Fn(&B) -> usize) -> usize {
        self.workers
            .iter()
            .map(|w| {
                crate::csr::heap_bytes(&w.found)
                    + crate::csr::heap_bytes(&w.taken)
                    + work_bytes(&w.work.buffer)
            })
            .sum::<usize>()
            + self.workers.capacity() * std::mem::size_of::<Worker<Work<B, S>, T>>()
            + crate::csr::heap_bytes(&self.spans)
            + crate::csr::heap_bytes(&self.spare)
    }
}
