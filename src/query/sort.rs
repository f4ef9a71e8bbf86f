//! Sorting a query's pairs: a least-significant-digit radix sort, linear in the pairs, for the
//! large results of dense contact (a mesh touching a copy of itself reports a million pairs,
//! where a comparison sort took 15% of the query).

use super::pairs::Pair;

/// Bits per digit: 2048 counters, 8 KiB, stay in the first-level cache.
const DIGIT_BITS: u32 = 11;
const BUCKETS: usize = 1 << DIGIT_BITS;
/// Below this, a comparison sort is as fast and needs no scratch.
const SMALL: usize = 4096;

/// Sorts `v` by `(a, b)`. `b_count` bounds the `b` indices; `scratch` is reused and grown if it
/// can be (fallibly: without room, the comparison sort is used instead).
pub(crate) fn sort_pairs(v: &mut Vec<Pair>, scratch: &mut Vec<Pair>, b_count: u64) {
    if v.len() < SMALL
        || scratch
            .try_reserve(v.len().saturating_sub(scratch.len()))
            .is_err()
    {
        v.sort_unstable();
        return;
    }
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
        for (n, na, nb) in [
            (10, 5, 5),
            (5000, 3, 100_000),
            (20_000, 70_000, 70_000),
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
            let mut scratch = Vec::new();
            sort_pairs(&mut v, &mut scratch, nb);
            assert_eq!(v, expected, "n = {n}");
        }
    }
}
