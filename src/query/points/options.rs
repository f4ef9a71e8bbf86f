//! What a distance query may trade for speed, and how far it looks.

use crate::error::{Error, Result};

/// Options of the distance queries ([`crate::distance`], [`crate::closest_points`],
/// [`crate::signed_distances`], the scene's): how far to look, what error to accept, how many
/// threads. The defaults (no bound, no tolerance, every core) give the exact answer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DistanceOptions {
    /// Farther than this is "not found" (and a signed distance an infinity of its sign): the
    /// search looks no farther, so a small bound is the cheapest query. Infinity: no bound.
    pub max_distance: f64,
    /// Relative tolerance: a result at distance `d` is accepted when `d <= (1 + rel_err) m +
    /// abs_err` for the least distance `m` (as FCL's `rel_err` and `abs_err`), so that branches
    /// which cannot beat it by more are not searched. 0 (and `abs_err` 0): the least, exactly.
    pub rel_err: f64,
    /// Absolute tolerance, as `rel_err` says. 0: exact.
    pub abs_err: f64,
    /// Threads the query may use, as [`crate::QueryOptions::threads`]: 0 for every core, 1 for
    /// the calling thread, n for at most n. The answer is the same for every count.
    pub threads: u32,
}

impl Default for DistanceOptions {
    fn default() -> Self {
        DistanceOptions {
            max_distance: f64::INFINITY,
            rel_err: 0.0,
            abs_err: 0.0,
            threads: 0,
        }
    }
}

impl DistanceOptions {
    /// The defaults with the bound `max_distance`.
    pub fn with_max_distance(self, max_distance: f64) -> Self {
        DistanceOptions {
            max_distance,
            ..self
        }
    }

    /// The options with the tolerances `rel_err` and `abs_err`.
    pub fn with_tolerance(self, rel_err: f64, abs_err: f64) -> Self {
        DistanceOptions {
            rel_err,
            abs_err,
            ..self
        }
    }

    /// The options with `threads` threads.
    pub fn with_threads(self, threads: u32) -> Self {
        DistanceOptions { threads, ..self }
    }

    /// Fails with [`Error::InvalidDistanceOption`] naming the first option out of range.
    pub(crate) fn check(&self) -> Result<()> {
        let bad = |name, value| Err(Error::InvalidDistanceOption { name, value });
        if self.max_distance.is_nan() || self.max_distance < 0.0 {
            return bad("max_distance", self.max_distance);
        }
        for (name, value) in [("rel_err", self.rel_err), ("abs_err", self.abs_err)] {
            if !value.is_finite() || value < 0.0 {
                return bad(name, value);
            }
        }
        Ok(())
    }

    /// Is any tolerance set?
    pub(crate) fn tolerant(&self) -> bool {
        self.rel_err > 0.0 || self.abs_err > 0.0
    }

    /// Where to look for a better candidate once one at distance at most `d` is found: a
    /// radius at least `(d - abs_err) / (1 + rel_err)` (rounded up), so that when nothing lies
    /// within it the least distance `m` has `d <= (1 + rel_err) m + abs_err` and the candidate
    /// is accepted. `d` itself when exact.
    pub(crate) fn improving(&self, d: f64) -> f64 {
        if !self.tolerant() {
            return d;
        }
        let reach = ((d - self.abs_err).next_up() / (1.0 + self.rel_err).next_down()).next_up();
        reach.clamp(0.0, d)
    }
}
