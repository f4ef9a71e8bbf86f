//! Sorting a query's pairs in linear time, for the large results of dense contact (a mesh
//! touching a copy of itself reports a million pairs, where a comparison sort took 15% of the
//! query). Most of a counting sort's time over a million pairs goes to cache misses, one per
//! pair placed, so the pairs are first distributed by the high bits of `a` into buckets of
//! [`WIDTH`] first indices (streaming writes, one cache line per bucket at a time), and each
//! bucket, which fits in cache, is then sorted on its own: by counting, byte by byte (`b`, then
//! the rest of `a`) when first indices have many pairs each, or by one counting pass on the
//! rest of `a` and each short run of one `a` in place. Buckets are independent, so threads
//! share them. When the first indices
//! are too sparse for buckets, a least-significant-digit radix sort on the whole key.

use crate::query::pairs::Pair;

/// Bits per digit of the radix sort: 2048 counters, 8 KiB, stay in the first-level cache.
const DIGIT_BITS: u32 = 11;
const BUCKETS: usize = 1 << DIGIT_BITS;
/// Below this, a comparison sort is as fast and needs no scratch.
const SMALL: usize = 4096;
/// First indices per bucket: one byte of digit.
const WIDTH: usize = 256;
/// Below this many pairs per thread, the buckets are sorted on fewer threads.
const PAIRS_PER_THREAD: usize = 1 << 16;

/// Sorts `v` by `(a, b)` on at most `threads` threads. `a_count` and `b_count` bound the `a`
/// and `b` indices; `scratch` and `counts` are reused and grown if they can be (fallibly:
/// without room, the comparison sort is used instead).
pub(crate) fn sort_pairs(
    v: &mut Vec<Pair>,
    scratch: &mut Vec<Pair>,
    counts: &mut Vec<u32>,
    a_count: u64,
    b_count: u64,
    threads: usize,
) {
    if v.len() < SMALL
        || scratch
            .try_reserve(v.len().saturating_sub(scratch.len()))
            .is_err()
    {
        v.sort_unstable();
        return;
    }
    let buckets = buckets_for(a_count);
    if buckets <= v.len()
        && v.len() <= u32::MAX as usize
        && counts
            .try_reserve((2 * buckets + 1).saturating_sub(counts.len()))
            .is_ok()
    {
        bucket_sort(v, scratch, counts, buckets, b_count, threads);
    } else {
        radix_sort(v, scratch, b_count);
    }
}

/// Bytes of the second indices below `b_count`: the in-bucket sort's passes over `b`.
fn digit_bytes(b_count: u64) -> u32 {
    let b_max = b_count.saturating_sub(1).min(u64::from(u32::MAX)) as u32;
    (32 - b_max.leading_zeros()).div_ceil(8).max(1)
}

/// Distributes the pairs into `scratch` by bucket (`a / WIDTH`), then sorts each bucket back
/// into `v`.
fn bucket_sort(
    v: &mut [Pair],
    scratch: &mut Vec<Pair>,
    counts: &mut Vec<u32>,
    buckets: usize,
    b_count: u64,
    threads: usize,
) {
    // `sort_pairs` reserved the room: the distribution cannot fail.
    if !bucket_part(v, scratch, counts, buckets) {
        v.sort_unstable();
        return;
    }
    let threads = threads.min(v.len() / PAIRS_PER_THREAD).max(1);
    let plan = Plan::new(v.len(), (buckets * WIDTH) as u64, b_count);
    let starts = &counts[..=buckets];
    // The pairs are in place already.
    sort_buckets(v, scratch, starts, 0, threads, plan, &|_, _| {});
}

/// Sorts the buckets whose runs in `scratch` start at `starts` (one more entry than buckets, the
/// last the end; offsets counted from `base`) into `v`, sharing them among `threads` threads.
/// `gather(k, into)`, when given, first fills bucket `k`'s run of `scratch` (numbered from the
/// first of `starts`) with its pairs.
fn sort_buckets(
    v: &mut [Pair],
    scratch: &mut [Pair],
    starts: &[u32],
    base: usize,
    threads: usize,
    plan: Plan,
    gather: &Gather,
) {
    sort_buckets_from(v, scratch, starts, 0, base, threads, plan, gather)
}

/// [`sort_buckets`] for the buckets numbered from `first`.
#[allow(clippy::too_many_arguments)]
fn sort_buckets_from(
    v: &mut [Pair],
    scratch: &mut [Pair],
    starts: &[u32],
    first: usize,
    base: usize,
    threads: usize,
    plan: Plan,
    gather: &Gather,
) {
    let buckets = starts.len() - 1;
    if threads < 2 || buckets < 2 {
        for k in 0..buckets {
            let (lo, hi) = (starts[k] as usize - base, starts[k + 1] as usize - base);
            gather(first + k, &mut scratch[lo..hi]);
            if hi - lo > 1 {
                sort_bucket(&mut v[lo..hi], &mut scratch[lo..hi], plan);
            } else if hi > lo {
                v[lo] = scratch[lo];
            }
        }
        return;
    }
    // Half the pairs (in whole buckets) to each half of the threads.
    let middle = (starts[0] as usize + starts[buckets] as usize) / 2;
    let k = starts[1..buckets]
        .partition_point(|&s| (s as usize) < middle)
        .clamp(0, buckets - 2)
        + 1;
    let at = starts[k] as usize - base;
    let (v_lo, v_hi) = v.split_at_mut(at);
    let (s_lo, s_hi) = scratch.split_at_mut(at);
    let half = threads / 2;
    let (lo, hi) = (&starts[..=k], &starts[k..]);
    crate::threads::join(
        crate::threads::Step::PairSort,
        || sort_buckets_from(v_lo, s_lo, lo, first, base, half, plan, gather),
        || {
            let rest = threads - half;
            sort_buckets_from(v_hi, s_hi, hi, first + k, base + at, rest, plan, gather)
        },
    );
}

/// Fills bucket `k`'s run of the scratch space with its pairs. Behind a reference to a trait
/// object, as [`Part`] is, so that the sort is compiled once rather than for each query type
/// whose threads call it; it is called once per bucket.
type Gather<'g> = dyn Fn(usize, &mut [Pair]) + Sync + 'g;

/// Thread `w`'s bucketed pairs and where each bucket starts.
pub(crate) type Part<'p> = dyn Fn(usize) -> (&'p [Pair], &'p [u32]) + Sync + 'p;

/// Makes `v` `n` long for overwriting every entry: what it holds is left (filling it would be
/// a pass over memory for nothing).
fn fit_len(v: &mut Vec<Pair>, n: usize) {
    if v.len() >= n {
        v.truncate(n);
    } else {
        v.resize(n, Pair::default());
    }
}

/// Is `bucket_part` and [`sort_parts`]'s way open for results with these bounds? (Dense enough
/// first indices, room for the counters.)
pub(crate) fn buckets_for(a_count: u64) -> usize {
    a_count.div_ceil(WIDTH as u64) as usize
}

/// Distributes one thread's pairs into `into` by bucket (`a / WIDTH`, `buckets` of them);
/// `starts` gets where each bucket starts, and the end. Fallible: false when memory ran out.
pub(crate) fn bucket_part(
    part: &[Pair],
    into: &mut Vec<Pair>,
    starts: &mut Vec<u32>,
    buckets: usize,
) -> bool {
    if into
        .try_reserve(part.len().saturating_sub(into.len()))
        .is_err()
        || starts
            .try_reserve((2 * buckets + 1).saturating_sub(starts.len()))
            .is_err()
    {
        return false;
    }
    starts.clear();
    starts.resize(2 * buckets + 1, 0);
    let (starts, next) = starts.split_at_mut(buckets + 1);
    for p in part {
        starts[p.a as usize / WIDTH + 1] += 1;
    }
    for i in 1..=buckets {
        starts[i] += starts[i - 1];
    }
    next.copy_from_slice(&starts[..buckets]);
    fit_len(into, part.len());
    for p in part {
        let c = &mut next[p.a as usize / WIDTH];
        into[*c as usize] = *p;
        *c += 1;
    }
    true
}

/// The pairs of `parts` threads' results, each distributed by [`bucket_part`] (`part(w)`: the
/// bucketed pairs and their starts), sorted into `out` on at most `threads` threads: each
/// bucket gathered from every part, then sorted in cache. `scratch` and `starts` are reused.
/// `out`'s contents are replaced. Fallible: false when memory ran out.
#[allow(clippy::too_many_arguments)]
pub(crate) fn sort_parts<'p>(
    parts: usize,
    part: &Part<'p>,
    buckets: usize,
    b_count: u64,
    out: &mut Vec<Pair>,
    scratch: &mut Vec<Pair>,
    starts: &mut Vec<u32>,
    threads: usize,
) -> bool {
    let total: usize = (0..parts).map(|w| part(w).0.len()).sum();
    if out.try_reserve(total.saturating_sub(out.len())).is_err()
        || scratch
            .try_reserve(total.saturating_sub(scratch.len()))
            .is_err()
        || starts
            .try_reserve((buckets + 1).saturating_sub(starts.len()))
            .is_err()
        || total > u32::MAX as usize
    {
        return false;
    }
    starts.clear();
    starts.resize(buckets + 1, 0);
    for w in 0..parts {
        let s = part(w).1;
        for k in 0..buckets {
            starts[k + 1] += s[k + 1] - s[k];
        }
    }
    for k in 1..=buckets {
        starts[k] += starts[k - 1];
    }
    fit_len(out, total);
    fit_len(scratch, total);
    let plan = Plan::new(total, (buckets * WIDTH) as u64, b_count);
    let threads = threads.min(total / PAIRS_PER_THREAD).max(1);
    let gather = |k: usize, into: &mut [Pair]| {
        let mut at = 0;
        for w in 0..parts {
            let (pairs, s) = part(w);
            let segment = &pairs[s[k] as usize..s[k + 1] as usize];
            into[at..at + segment.len()].copy_from_slice(segment);
            at += segment.len();
        }
    };
    sort_buckets(out, scratch, starts, 0, threads, plan, &gather);
    true
}

/// Sorts one bucket's pairs (`from`) into `to`. Where first indices have few pairs each (between
/// coplanar sheets, 1.6 on average), by the low bits of `a` in one counting pass and then each
/// run of one `a` by `b` in place: cheaper than counting passes over `b`'s bytes, which serve
/// long runs ([`sort_bucket_by_digits`]; a mesh against its copy: 14).
fn sort_bucket(to: &mut [Pair], from: &mut [Pair], plan: Plan) {
    if !plan.short_runs {
        sort_bucket_by_digits(to, from, plan.b_bytes);
        return;
    }
    let mut start = [0u32; WIDTH + 1];
    for p in from.iter() {
        start[p.a as usize % WIDTH + 1] += 1;
    }
    for i in 1..=WIDTH {
        start[i] += start[i - 1];
    }
    let mut next = [0u32; WIDTH];
    next.copy_from_slice(&start[..WIDTH]);
    for p in from.iter() {
        let c = &mut next[p.a as usize % WIDTH];
        to[*c as usize] = *p;
        *c += 1;
    }
    for k in 0..WIDTH {
        let run = &mut to[start[k] as usize..start[k + 1] as usize];
        if run.len() > 1 {
            sort_run(run);
        }
    }
}

/// Pairs per first index, on average, up to which runs are sorted in place.
const SHORT_RUNS: u64 = 8;

/// How buckets are sorted: the bytes of `b` to count, or each run of one `a` in place.
#[derive(Clone, Copy)]
struct Plan {
    b_bytes: u32,
    short_runs: bool,
}

impl Plan {
    /// For `pairs` pairs whose indices are below `a_count` and `b_count`.
    fn new(pairs: usize, a_count: u64, b_count: u64) -> Plan {
        Plan {
            b_bytes: digit_bytes(b_count),
            short_runs: pairs as u64 <= SHORT_RUNS.saturating_mul(a_count),
        }
    }
}

/// Sorts pairs of one `a` by `b`: by insertion when few (no call, no recursion), by the
/// standard library's sort otherwise (insertion is quadratic).
#[inline]
fn sort_run(run: &mut [Pair]) {
    if run.len() > 16 {
        run.sort_unstable_by_key(|p| p.b);
        return;
    }
    for i in 1..run.len() {
        let p = run[i];
        let mut j = i;
        while j > 0 && run[j - 1].b > p.b {
            run[j] = run[j - 1];
            j -= 1;
        }
        run[j] = p;
    }
}

/// [`sort_bucket`] least significant digit first: by `b` a byte at a time (as many bytes as
/// `b_count` needs), then by the low bits of `a`. Every pass is a stable counting sort over a
/// bucket that stays in cache; `from` serves as scratch.
fn sort_bucket_by_digits(to: &mut [Pair], from: &mut [Pair], b_bytes: u32) {
    // Each pass moves the pairs between the two buffers; with an even number of passes before
    // the last, the last writes into `to`.
    let mut src: &mut [Pair] = from;
    let mut dst: &mut [Pair] = to;
    let passes = b_bytes + 1;
    if passes.is_multiple_of(2) {
        // Start from `to` so that the last pass lands there.
        dst.copy_from_slice(src);
        std::mem::swap(&mut src, &mut dst);
    }
    for pass in 0..passes {
        let digit = |p: &Pair| -> usize {
            if pass < b_bytes {
                (p.b >> (8 * pass)) as usize & 0xff
            } else {
                p.a as usize % WIDTH
            }
        };
        let mut next = [0u32; WIDTH];
        for p in src.iter() {
            next[digit(p)] += 1;
        }
        let mut total = 0;
        for c in next.iter_mut() {
            let n = *c;
            *c = total;
            total += n;
        }
        for p in src.iter() {
            let c = &mut next[digit(p)];
            dst[*c as usize] = *p;
            *c += 1;
        }
        std::mem::swap(&mut src, &mut dst);
    }
}

/// Least-significant digit first, `DIGIT_BITS` at a time, on the key `a * b_count + b`.
fn radix_sort(v: &mut Vec<Pair>, scratch: &mut Vec<Pair>, b_count: u64) {
    let key = |p: &Pair| u64::from(p.a) * b_count + u64::from(p.b);
    let max = v.iter().map(key).max().unwrap_or(0);
    let bits = 64 - max.leading_zeros();
    let passes = bits.div_ceil(DIGIT_BITS);
    fit_len(scratch, v.len());
    for pass in 0..passes {
        let shift = pass * DIGIT_BITS;
        let digit = |p: &Pair| ((key(p) >> shift) as usize) & (BUCKETS - 1);
        let mut start = [0usize; BUCKETS];
        for p in v.iter() {
            start[digit(p)] += 1;
        }
        let mut total = 0;
        for s in start.iter_mut() {
            let count = *s;
            *s = total;
            total += count;
        }
        for p in v.iter() {
            let d = digit(p);
            scratch[start[d]] = *p;
            start[d] += 1;
        }
        std::mem::swap(v, scratch);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::Rng;

    #[test]
    fn sorts_like_a_comparison_sort() {
        let mut rng = Rng::new(5);
        // One scratch pair for every case, as a query reuses them.
        let (mut scratch, mut counts) = (Vec::new(), Vec::new());
        for (k, (n, na, nb)) in [
            // A comparison sort.
            (10, 5, 5),
            (4000, 3, 100_000),
            // Bucket sorts: short runs of one `a`, long runs, dense and sparse `b`, on one
            // thread and shared out.
            (20_000, 70_000, 70_000),
            (50_000, 1000, 1_000_000),
            (9000, 3, 5),
            (30_000, 100, 50_000),
            (300_000, 40_000, 40_000),
            (300_000, 3_000_000, 1000),
            // Radix sorts: first indices too sparse to count.
            (10_000, 1_000_000, 10),
            (9000, 4_000_000_000, 4_000_000_000),
        ]
        .into_iter()
        .enumerate()
        {
            let threads = 1 + k % 3;
            let mut v: Vec<Pair> = (0..n)
                .map(|_| Pair {
                    a: rng.below(na) as u32,
                    b: rng.below(nb) as u32,
                })
                .collect();
            // Among short runs, a few long ones: sorted in place by the library's sort.
            if na >= 20_000 {
                for i in 0..n / 50 {
                    v[i * 50].a = (i % 7) as u32;
                }
            }
            let mut expected = v.clone();
            expected.sort_unstable();
            sort_pairs(&mut v, &mut scratch, &mut counts, na, nb, threads);
            assert_eq!(v, expected, "n = {n}, threads {threads}");
        }
    }
}
