//! Where a query's pairs go: a result that grows fallibly and stops at a limit.

use crate::query::pairs::Pair;

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

impl<'w> Sink<'w> {
    /// A sink into `out`, emptied first, that stops at `limit` pairs.
    pub fn new(out: &'w mut Vec<Pair>, limit: usize) -> Self {
        out.clear();
        Sink {
            out,
            limit,
            stop: None,
        }
    }

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
