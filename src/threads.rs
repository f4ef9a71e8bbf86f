//! The threads dvh works on: rayon's global pool, created once per process and shared with the
//! application's own rayon work, so that no call creates threads and dvh never runs more threads
//! than the pool has (rayon sizes it to the available cores, or to `RAYON_NUM_THREADS`).

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
/// Allocates one small job per worker beyond the first.
pub(crate) fn on_each<W: Send, F: Fn(&mut W, usize) + Sync>(workers: &mut [W], f: &F) {
    let Some((first, rest)) = workers.split_first_mut() else {
        return;
    };
    rayon::in_place_scope(|scope| {
        for (i, w) in rest.iter_mut().enumerate() {
            scope.spawn(move |_| f(w, i + 1));
        }
        f(first, 0);
    });
}

/// Runs `f` on every item of `items` on `threads` threads at once (as [`on_each`]), each thread
/// taking the next item as it comes free: for items of uneven cost.
pub(crate) fn in_turns<S: Send, F: Fn(S) + Sync>(threads: usize, items: Vec<S>, f: &F) {
    let items = std::sync::Mutex::new(items.into_iter());
    // Zero-sized: no allocation.
    let mut workers = vec![(); threads];
    on_each(&mut workers, &|_, _| {
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
/// for why the calling thread works rather than waits). Allocates one small job.
pub(crate) fn join<A, B, RA, RB>(a: A, b: B) -> (RA, RB)
where
    A: FnOnce() -> RA + Send,
    B: FnOnce() -> RB + Send,
    RA: Send,
    RB: Send,
{
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
