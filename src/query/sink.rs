//! Where a query's pairs go: a result that grows fallibly and stops at a limit.

use super::pairs::{Pair, PairKind, Pairs, QueryStats};
use super::workspace::Worker;
use crate::error::{Error, Result};

/// Why a traversal stopped early.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Stop {
    /// As many pairs as asked for.
    Limit,
    /// The result could not grow.
    OutOfMemory { bytes: usize },
}

/// Where pairs go.
pub(crate) struct Sink<'w> {
    pub out: &'w mut Vec<Pair>,
    /// Pairs to find before stopping.
    pub limit: usize,
    pub stop: Option<Stop>,
}

impl Sink<'_> {
    /// Records a pair; returns whether the traversal must stop. The result grows fallibly, so
    /// that a pathological input (say every triangle at one point) ends in an error, not an abort.
    #[inline]
    pub fn report(&mut self, pair: Pair) -> bool {
        if self.out.len() == self.out.capacity() {
            let extra = self.out.capacity().max(256);
            if self.out.try_reserve(extra).is_err() {
                let bytes = (self.out.capacity() + extra) * std::mem::size_of::<Pair>();
                self.stop = Some(Stop::OutOfMemory { bytes });
                return true;
            }
        }
        self.out.push(pair);
        if self.out.len() >= self.limit {
            self.stop = Some(Stop::Limit);
            return true;
        }
        false
    }
}

/// A query on the calling thread into `out`: `fill` runs with the workspace's first worker and a
/// sink of at most `limit` pairs (not at all for a limit of 0); then the pairs found, sorted,
/// replace `out`'s (triangle pairs). A stop at the limit marks the result truncated when
/// `limit_truncates`. On error `out` still holds the previous result.
pub(crate) fn one_thread(
    out: &mut Pairs,
    limit: usize,
    limit_truncates: bool,
    fill: impl FnOnce(&mut Worker, &mut Sink, &mut QueryStats),
) -> Result<QueryStats> {
    let Pairs {
        items,
        spare,
        kind,
        workspace,
    } = out;
    if workspace.workers.is_empty() {
        workspace.workers.push(Worker::default());
    }
    let mut stats = QueryStats::default();
    spare.clear();
    let mut sink = Sink {
        out: spare,
        limit,
        stop: (limit == 0).then_some(Stop::Limit),
    };
    if limit > 0 {
        fill(&mut workspace.workers[0], &mut sink, &mut stats);
    }
    match sink.stop {
        Some(Stop::OutOfMemory { bytes }) => return Err(Error::OutOfMemory { bytes }),
        Some(Stop::Limit) => stats.truncated = limit_truncates,
        None => {}
    }
    spare.sort_unstable();
    std::mem::swap(items, spare);
    *kind = PairKind::Triangles;
    stats.pairs = items.len() as u64;
    Ok(stats)
}
