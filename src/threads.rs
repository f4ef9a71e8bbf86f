//! The threads dvh works on: rayon's global pool, created once per process and shared with the
//! application's own rayon work, so that no call creates threads and dvh never runs more threads
//! than the pool has (rayon sizes it to the available cores, or to `RAYON_NUM_THREADS`).

use std::cell::Cell;

/// A step of dvh's work that may be shared out among threads, each with its own cut-off below
/// which it stays on the calling thread.
#[doc(hidden)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Step {
    /// A query's traversal of the two hierarchies.
    Traversal,
    /// The narrow phase of the primitive queries (proximity, continuous, nearest features) over
    /// the traversal's node pairs.
    Pairs,
    /// Sorting the primitive queries' results.
    Sort,
    /// Sorting the triangle pairs of [`crate::collide`] and [`crate::self_collide`].
    PairSort,
    /// The closest-point queries' values.
    Values,
    /// The intersection curves' segments, pair by pair.
    Crossings,
    /// A refit's volumes.
    Refit,
    /// Storing a mesh's new positions (refit, motion).
    Store,
    /// A scene's stale objects refit, one share of them per thread.
    SceneRefit,
    /// A scene's candidate pairs queried, taken in turn by the threads.
    ScenePairs,
    /// The point queries' blocks of points, taken in turn by the threads.
    Points,
}

const STEPS: usize = 11;

thread_local! {
    // Plain cells with a constant start: reading and adding allocate nothing and register no
    // destructor.
    static SHARED: [Cell<u64>; STEPS] = const { [const { Cell::new(0) }; STEPS] };
}

/// Counts `step` shared out by the calling thread.
#[inline]
pub(crate) fn shared_out(step: Step) {
    SHARED.with(|s| {
        let c = &s[step as usize];
        c.set(c.get() + 1);
    });
}

/// How many times the calling thread has shared `step` out among more than one worker (a
/// nested share, handed on by a thread of the pool, counts on that thread). For tests that claim
/// to exercise the threaded paths: a query or refit below its cut-off never counts, whatever
/// thread count it was asked for.
#[doc(hidden)]
pub fn shared_count(step: Step) -> u64 {
    SHARED.with(|s| s[step as usize].get())
}

/// Makes sure rayon's pool has at least two threads, for tests of the threaded paths on a
/// machine with one core: builds the pool with two when it is not built yet and
/// `RAYON_NUM_THREADS` does not size it. Returns the pool's thread count (still 1 when the pool
/// was built before, or sized to one).
#[doc(hidden)]
pub fn at_least_two_threads() -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    if cores < 2 && std::env::var_os("RAYON_NUM_THREADS").is_none() {
        // Fails when the pool exists already: its size is then reported as it is.
        let _ = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build_global();
    }
    rayon::current_num_threads()
}

/// How many threads a call asking for `requested` uses: all of the pool's for 0, otherwise at
/// most `requested`. Asking for 1 never touches the pool (the call runs on the calling thread and
/// allocates nothing).
pub(crate) fn resolve(requested: u32) -> usize {
    match requested {
        1 => 1,
        0 => rayon::current_num_threads(),
        n => (n as usize).min(rayon::current_num_threads()),
    }
}

/// Runs `f(worker, index)` for every worker at once: the first on the calling thread, the
/// others on threads of the pool. The calling thread works rather than waits: a thread that was
/// running keeps its core, where handing all the work to the pool left it to the scheduler to
/// wake two pool threads on two cores (measured: after a long pause it often ran them on one).
/// Allocates one small job per worker beyond the first. Counts `step` shared out when there are
/// several workers.
pub(crate) fn on_each<W: Send, F: Fn(&mut W, usize) + Sync>(step: Step, workers: &mut [W], f: &F) {
    let Some((first, rest)) = workers.split_first_mut() else {
        return;
    };
    if !rest.is_empty() {
        shared_out(step);
    }
    rayon::in_place_scope(|scope| {
        for (i, w) in rest.iter_mut().enumerate() {
            scope.spawn(move |_| f(w, i + 1));
        }
        f(first, 0);
    });
}

/// Runs `f` on every item of `items` on `threads` threads at once (as [`on_each`]), each thread
/// taking the next item as it comes free: for items of uneven cost. Counts `step` shared out
/// when there are several threads and several items.
pub(crate) fn in_turns<S: Send, F: Fn(S) + Sync>(step: Step, threads: usize, items: Vec<S>, f: &F) {
    // One item: its thread does it alone, and the others would only wait.
    let threads = if items.len() > 1 { threads } else { 1 };
    let items = std::sync::Mutex::new(items.into_iter());
    // Zero-sized: no allocation.
    let mut workers = vec![(); threads];
    on_each(step, &mut workers, &|_, _| {
        loop {
            // The lock is let go before `f` runs: a panic in `f` cannot poison it.
            let next = items.lock().expect("no item is taken mid-panic").next();
            let Some(item) = next else {
                break;
            };
            f(item);
        }
    });
}

/// Runs `a` on the calling thread and `b` on a thread of the pool, at once (see [`on_each`]
/// for why the calling thread works rather than waits). Allocates one small job. Counts `step`
/// shared out.
pub(crate) fn join<A, B, RA, RB>(step: Step, a: A, b: B) -> (RA, RB)
where
    A: FnOnce() -> RA + Send,
    B: FnOnce() -> RB + Send,
    RA: Send,
    RB: Send,
{
    shared_out(step);
    let mut rb = None;
    let ra = rayon::in_place_scope(|scope| {
        scope.spawn(|_| rb = Some(b()));
        a()
    });
    (ra, rb.expect("the scope waits for its jobs"))
}

/// Work items taken by several threads and finished in any order, counted in order from the
/// first: a query cut short at `limit` results may stop once the items settled from the first
/// hold that many, because one thread taking them in order would have stopped within them.
pub(crate) struct Settled<'c> {
    /// Results of each item, `usize::MAX` while it is not finished.
    counts: &'c [std::sync::atomic::AtomicUsize],
    /// Items settled from the first, and the results they hold.
    state: std::sync::Mutex<(usize, usize)>,
    limit: usize,
}

impl<'c> Settled<'c> {
    /// Every item of `counts` unfinished.
    pub(crate) fn new(counts: &'c [std::sync::atomic::AtomicUsize], limit: usize) -> Settled<'c> {
        for c in counts {
            c.store(usize::MAX, std::sync::atomic::Ordering::Relaxed);
        }
        Settled {
            counts,
            state: std::sync::Mutex::new((0, 0)),
            limit,
        }
    }

    /// Item `i` found `found` results. Returns whether the items settled from the first now
    /// hold `limit` results (never, without a limit).
    pub(crate) fn finish(&self, i: usize, found: usize) -> bool {
        use std::sync::atomic::Ordering;
        if self.limit == usize::MAX {
            return false;
        }
        self.counts[i].store(found, Ordering::Release);
        let mut s = self.state.lock().unwrap_or_else(|e| e.into_inner());
        while s.0 < self.counts.len() {
            let found = self.counts[s.0].load(Ordering::Acquire);
            if found == usize::MAX {
                break;
            }
            s.1 += found;
            s.0 += 1;
        }
        s.1 >= self.limit
    }
}

/// Runs `f` on the calling thread, asserting that it shared each of `steps` out among several
/// workers: a threaded answer compared with the single-threaded one says nothing about threads
/// if the query stayed below its cut-offs. For tests: panics when a step was not shared.
#[doc(hidden)]
pub fn sharing<R>(steps: &[Step], what: &str, f: impl FnOnce() -> R) -> R {
    assert!(
        at_least_two_threads() >= 2,
        "rayon's pool has one thread: nothing can be shared out"
    );
    let before: Vec<u64> = steps.iter().map(|&s| shared_count(s)).collect();
    let r = f();
    for (&step, before) in steps.iter().zip(before) {
        assert!(
            shared_count(step) > before,
            "{what}: {step:?} ran on the calling thread alone"
        );
    }
    r
}
