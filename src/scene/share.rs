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

/// The workers of a scene query and, per object pair of its last run, where the results are.
/// Kept in the caller's result buffer, so that its memory serves the next query.
#[derive(Debug)]
pub(super) struct Shared<W, T> {
    workers: Vec<Worker<W, T>>,
    spans: Vec<Span>,
}

impl<W, T> Default for Shared<W, T> {
    fn default() -> Self {
        Shared {
            workers: Vec::new(),
            spans: Vec::new(),
        }
    }
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

impl<W: Default + Send, T: Copy + Send> Shared<W, T> {
    /// Runs `query` on every object pair of `candidates`, on up to `threads` threads (one pair
    /// at a time each: pairs' costs differ by orders of magnitude). `query(work, pair, found)`
    /// appends the pair's results to `found`. `reset` readies each worker's scratch first.
    /// Fails with the first error a pair's query returned.
    pub fn run<Q, R>(
        &mut self,
        candidates: &[(u32, u32)],
        threads: usize,
        reset: R,
        query: &Q,
    ) -> Result<()>
    where
        R: Fn(&mut W),
        Q: Fn(&mut W, (u32, u32), &mut Vec<T>) -> Result<Truncated> + Sync,
    {
        let threads = threads.min(candidates.len()).max(1);
        if self.workers.len() < threads {
            self.workers.resize_with(threads, Worker::default);
        }
        for w in &mut self.workers {
            w.found.clear();
            w.taken.clear();
            w.error = None;
            reset(&mut w.work);
        }
        self.spans.clear();
        self.spans.resize(candidates.len(), Span::default());
        let one = |w: &mut Worker<W, T>, index: usize, pair| -> Span {
            let start = w.found.len();
            if w.error.is_some() {
                return Span::default();
            }
            let truncated = match query(&mut w.work, pair, &mut w.found) {
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
                &|w: &mut Worker<W, T>, index| {
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
    pub fn works(&self) -> impl Iterator<Item = &W> {
        self.workers.iter().map(|w| &w.work)
    }

    /// The results of the pair at `span`.
    pub fn results(&self, span: &Span) -> &[T] {
        &self.workers[span.worker as usize].found[span.start..span.start + span.len]
    }

    /// Every result of the last run in the pairs' order, at most `limit` of them, into `out`
    /// (cleared first). Returns whether anything was left out: a pair's query cut short, or
    /// more results than `limit`. Fails, changing nothing else, when `out` cannot grow.
    pub fn merge(&self, limit: usize, out: &mut Vec<T>) -> Result<bool> {
        let found: usize = self.spans.iter().map(|s| s.len).sum();
        let keep = found.min(limit);
        out.clear();
        out.try_reserve(keep).map_err(|_| Error::OutOfMemory {
            bytes: keep * std::mem::size_of::<T>(),
        })?;
        let mut truncated = found > limit;
        for s in &self.spans {
            truncated |= s.truncated;
            let room = keep - out.len();
            out.extend_from_slice(&self.results(s)[..s.len.min(room)]);
        }
        Ok(truncated)
    }

    /// Bytes of memory held beyond the struct itself, with `work_bytes` of each worker's
    /// scratch.
    pub fn memory_bytes(&self, work_bytes: impl Fn(&W) -> usize) -> usize {
        self.workers
            .iter()
            .map(|w| {
                crate::csr::heap_bytes(&w.found)
                    + crate::csr::heap_bytes(&w.taken)
                    + work_bytes(&w.work)
            })
            .sum::<usize>()
            + self.workers.capacity() * std::mem::size_of::<Worker<W, T>>()
            + crate::csr::heap_bytes(&self.spans)
    }
}
