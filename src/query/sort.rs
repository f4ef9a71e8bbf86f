//! Sorting a query's pairs in linear time, for the large results of dense contact (a mesh
//! touching a copy of itself reports a million pairs, where a comparison sort took 15% of the
//! query): a counting sort on the first triangle, whose runs are then short, when the first
//! indices are dense enough; otherwise a least-significant-digit radix sort on the whole key.

use super::pairs::Pair;

/// Bits per digit: 2048 counters, 8 KiB, stay in the first-level cache.
const DIGIT_BITS: u32 = 11;
const BUCKETS: usize = 1 << DIGIT_BITS;
/// Below this, a comparison sort is as fast and needs no scratch.
const SMALL: usize = 4096;
/// The counting sort runs when there are at most this many counters per pair: its passes over
/// the counters then cost no more than its passes over the pairs.
const COUNTERS_PER_PAIR: usize = 4;

/// Sorts `v` by `(a, b)`. `b_count` bounds the `b` indices; `scratch` and `counts` are reused and
/// grown if they can be (fallibly: without room, the comparison sort is used instead).
pub(crate) fn sort_pairs(
    v: &mut Vec<Pair>,
    scratch: &mut Vec<Pair>,
    counts: &mut Vec<usize>,
    b_count: u64,
) {
    if v.len() < SMALL
        || scratch
            .try_reserve(v.len().saturating_sub(scratch.len()))
            .is_err()
    {
        v.sort_unstable();
        return;
    }
    let groups = v.iter().map(|p| p.a as usize).max().unwrap_or(0) + 1;
    if groups <= COUNTERS_PER_PAIR * v.len()
        && counts
            .try_reserve(groups.saturating_sub(counts.len()))
            .is_ok()
    {
        counting_sort(v, scratch, counts, groups);
    } else {
        radix_sort(v, scratch, b_count);
    }
}

/// Places the pairs by `a` (a stable counting sort: one pass to count, one to place), then sorts
/// each run of one `a` by `b`; on a mesh's contacts those runs hold a few pairs each.
fn counting_sort(
    v: &mut Vec<Pair>,
    scratch: &mut Vec<Pair>,
    counts: &mut Vec<usize>,
    groups: usize,
) {
    counts.clear();
    counts.resize(groups, 0);
    for p in v.iter() {
        counts[p.a as usize] += 1;
    }
    // Each counter becomes the start of its run.
    let mut total = 0;
    for c in counts.iter_mut() {
        let n = *c;
        *c = total;
        total += n;
    }
    scratch.clear();
    scratch.resize(v.len(), Pair::default());
    for p in v.iter() {
        let c = &mut counts[p.a as usize];
        scratch[*c] = *p;
        *c += 1;
    }
    // Each counter is now the end of its run, which is where the next run starts.
    let mut start = 0;
    for &end in counts.iter() {
        if end - start > 1 {
            scratch[start..end].sort_unstable_by_key(|p| p.b);
        }
        start = end;
    }
    std::mem::swap(v, scratch);
}

/// Least-significant digit first, `DIGIT_BITS` at a time, on the key `a * b_count + b`.
fn radix_sort(v: &mut Vec<Pair>, scratch: &mut Vec<Pair>, b_count: u64) {
    let key = |p: &Pair| u64::from(p.a) * b_count + u64::from(p.b);
    let max = v.iter().map(key).max().unwrap_or(0);
    let bits = 64 - max.leading_zeros();
    let passes = bits.div_ceil(DIGIT_BITS);
    scratch.clear();
    scratch.resize(v.len(), Pair::default());
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
        for (n, na, nb) in [
            // A comparison sort.
            (10, 5, 5),
            (4000, 3, 100_000),
            // Counting sorts: short runs of one `a`, long runs.
            (20_000, 70_000, 70_000),
            (50_000, 1000, 1_000_000),
            (9000, 3, 5),
            // Radix sorts: first indices too sparse to count.
            (10_000, 1_000_000, 10),
            (9000, 4_000_000_000, 4_000_000_000),
        ] {
            let mut v: Vec<Pair> = (0..n)
                .map(|_| Pair {
                    a: rng.below(na) as u32,
                    b: rng.below(nb) as u32,
                })
                .collect();
            let mut expected = v.clone();
            expected.sort_unstable();
            sort_pairs(&mut v, &mut scratch, &mut counts, nb);
            assert_eq!(v, expected, "n = {n}");
        }
    }
}
