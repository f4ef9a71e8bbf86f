//! The broad phase: which objects' world boxes overlap, by sweep and prune, kept up to date
//! incrementally.
//!
//! Boxes are kept sorted by their lower end on one axis (the one along which the boxes' centres
//! spread most). Each query repairs the order by insertion sort, which costs one pass plus one
//! step per box that moved past another. The overlapping pairs are kept from one query to the
//! next: only the pairs of objects whose boxes changed ("moved": posed, given positions, added,
//! removed) are dropped and looked for again, each moved box against the boxes whose lower ends
//! lie within its reach along the axis (found by binary search). Boxes much longer than the
//! others (a ground, a cloth) are kept aside and tested against every moved box, so that they do
//! not widen every search. A scene of 10,000 objects of which 100 move costs about 100 short
//! searches; a sweep over all of them (the first query, a change of axis, the coarse modes'
//! boxes) costs one pass plus the pairs overlapping along the axis.
//!
//! Sweep and prune rather than a BVH over objects: the objects' boxes change every frame for
//! those that move, the sorted order survives a frame where a tree would be refit or rebuilt,
//! and neither needs an all-pairs loop.

use crate::geometry::aabb::Aabb;
use std::collections::HashSet;

/// The sweep's state: live objects sorted by their boxes' lower end on `axis`, the pairs of
/// overlapping boxes as of the last update, and the objects moved since.
#[derive(Clone, Debug, Default)]
pub(crate) struct SweepAndPrune {
    axis: usize,
    order: Vec<u32>,
    /// Overlapping pairs `(lower id, higher id)`, valid for the boxes of the last
    /// [`SweepAndPrune::update`] plus the moves recorded since (when `known`).
    pairs: HashSet<(u32, u32)>,
    known: bool,
    moved: Vec<u32>,
    is_moved: Vec<bool>,
}

impl SweepAndPrune {
    /// A new object, sorted in at the next sweep.
    pub fn insert(&mut self, id: u32) {
        self.order.push(id);
        self.touch(id);
    }

    /// A removed object.
    pub fn remove(&mut self, id: u32) {
        self.order.retain(|&o| o != id);
        self.touch(id);
    }

    /// Every box may have changed (the boxes compared are other ones): the next
    /// [`SweepAndPrune::update`] sweeps them all.
    pub fn forget(&mut self) {
        self.known = false;
    }

    /// Object `id`'s box changed.
    pub fn touch(&mut self, id: u32) {
        let i = id as usize;
        if self.is_moved.len() <= i {
            self.is_moved.resize(i + 1, false);
        }
        if !self.is_moved[i] {
            self.is_moved[i] = true;
            self.moved.push(id);
        }
    }

    /// The axis along which the boxes' centres spread most, for a sweep that separates them best.
    fn best_axis(&self, boxes: &[Aabb]) -> usize {
        let n = self.order.len() as f64;
        let mut sum = [0.0; 3];
        let mut sum_sq = [0.0; 3];
        for &o in &self.order {
            let c = boxes[o as usize].centre();
            for k in 0..3 {
                sum[k] += c[k];
                sum_sq[k] += c[k] * c[k];
            }
        }
        let spread = |k: usize| sum_sq[k] - sum[k] * sum[k] / n;
        (0..3)
            .max_by(|&i, &j| spread(i).total_cmp(&spread(j)))
            .unwrap_or(0)
    }

    /// Sorts the live objects along the best axis: by insertion when the axis is the last one
    /// (the order is then nearly right), from scratch otherwise. Returns whether the axis changed.
    fn sort(&mut self, boxes: &[Aabb]) -> bool {
        let axis = self.best_axis(boxes);
        let changed = axis != self.axis;
        self.axis = axis;
        if changed {
            self.order
                .sort_unstable_by(|&i, &j| lo(boxes, i, axis).total_cmp(&lo(boxes, j, axis)));
        } else {
            insertion_sort(&mut self.order, |i| lo(boxes, i, axis));
        }
        changed
    }

    /// Every pair of live objects whose boxes meet, `(lower id, higher id)`, into `out` (in no
    /// particular order), by a sweep over all of them. `boxes` is indexed by object id. The
    /// pairs kept for [`SweepAndPrune::update`] are untouched: these boxes may be others.
    pub fn overlapping(&mut self, boxes: &[Aabb], out: &mut Vec<(u32, u32)>) {
        out.clear();
        self.sort(boxes);
        self.sweep(boxes, |pair| out.push(pair));
    }

    fn sweep(&self, boxes: &[Aabb], mut found: impl FnMut((u32, u32))) {
        let (axis, order) = (self.axis, &self.order);
        for (k, &i) in order.iter().enumerate() {
            let bi = &boxes[i as usize];
            for &j in &order[k + 1..] {
                let bj = &boxes[j as usize];
                if bj.lo[axis] > bi.hi[axis] {
                    break;
                }
                if bi.meets(bj) {
                    found((i.min(j), i.max(j)));
                }
            }
        }
    }

    /// Brings the kept pairs up to date with `boxes` (indexed by object id, the boxes that
    /// [`SweepAndPrune::touch`] was told about) and returns them.
    pub fn update(&mut self, boxes: &[Aabb]) -> &HashSet<(u32, u32)> {
        let changed = self.sort(boxes);
        if changed || !self.known {
            self.pairs.clear();
            let mut pairs = std::mem::take(&mut self.pairs);
            self.sweep(boxes, |pair| {
                pairs.insert(pair);
            });
            self.pairs = pairs;
            self.known = true;
        } else if !self.moved.is_empty() {
            self.pairs
                .retain(|&(i, j)| !self.is_moved[i as usize] && !self.is_moved[j as usize]);
            self.search_moved(boxes);
        }
        for &m in &self.moved {
            self.is_moved[m as usize] = false;
        }
        self.moved.clear();
        &self.pairs
    }

    /// Adds the pairs of each moved live object: against the long boxes, and by a binary search
    /// of the sorted order for the others whose lower ends are within reach.
    fn search_moved(&mut self, boxes: &[Aabb]) {
        let axis = self.axis;
        let length = |o: u32| {
            let b = &boxes[o as usize];
            b.hi[axis] - b.lo[axis]
        };
        // Long boxes: more than 8 times the mean length (and finite lengths only count).
        let (sum, n) = self.order.iter().fold((0.0, 0usize), |(s, n), &o| {
            let l = length(o);
            if l.is_finite() {
                (s + l, n + 1)
            } else {
                (s, n)
            }
        });
        let limit = 8.0 * sum / n.max(1) as f64;
        // NaN lengths cannot occur (finite boxes); counted as long, they would be safe anyway.
        let is_long = |l: f64| l > limit || l.is_nan();
        let long: Vec<u32> = self
            .order
            .iter()
            .copied()
            .filter(|&o| is_long(length(o)))
            .collect();
        let reach = self
            .order
            .iter()
            .map(|&o| length(o))
            .filter(|&l| l <= limit)
            .fold(0.0, f64::max);
        for &m in &self.moved {
            let bm = &boxes[m as usize];
            if bm.is_empty() {
                continue; // removed, or no vertices
            }
            let found = |o: u32, pairs: &mut HashSet<(u32, u32)>| {
                if o != m && bm.meets(&boxes[o as usize]) {
                    pairs.insert((m.min(o), m.max(o)));
                }
            };
            if is_long(length(m)) {
                // A long box searches everything.
                for &o in &self.order {
                    found(o, &mut self.pairs);
                }
                continue;
            }
            for &o in &long {
                found(o, &mut self.pairs);
            }
            // Every box meeting `bm` along the axis has its lower end at least this low (the
            // lengths are rounded: the reach is widened past their rounding).
            let from = (bm.lo[axis] - reach * (1.0 + 4.0 * f64::EPSILON)).next_down();
            let start = self.order.partition_point(|&o| lo(boxes, o, axis) < from);
            for &o in &self.order[start..] {
                if lo(boxes, o, axis) > bm.hi[axis] {
                    break;
                }
                if length(o) <= limit {
                    found(o, &mut self.pairs);
                }
            }
        }
    }
}
#[inline]
fn lo(boxes: &[Aabb], id: u32, axis: usize) -> f64 {
    boxes[id as usize].lo[axis]
}

/// Sorts `items` by `key`, fast when they are nearly sorted already.
fn insertion_sort(items: &mut [u32], key: impl Fn(u32) -> f64) {
    for i in 1..items.len() {
        let x = items[i];
        let kx = key(x);
        let mut j = i;
        while j > 0 && key(items[j - 1]) > kx {
            items[j] = items[j - 1];
            j -= 1;
        }
        items[j] = x;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::Rng;

    fn random_box(rng: &mut Rng) -> Aabb {
        let lo = [0, 1, 2].map(|_| rng.range(-10.0, 10.0));
        let size = [0, 1, 2].map(|_| rng.range(0.0, 3.0));
        Aabb {
            lo,
            hi: [0, 1, 2].map(|k| lo[k] + size[k]),
        }
    }

    /// The sweep, and the pairs kept from frame to frame, are exactly the pairs an all-pairs
    /// loop finds, frame after frame as boxes move (a few of them long), appear and disappear.
    #[test]
    fn finds_what_all_pairs_find() {
        let mut rng = Rng::new(7);
        let mut boxes: Vec<Aabb> = (0..300).map(|_| random_box(&mut rng)).collect();
        let mut live: Vec<bool> = vec![true; boxes.len()];
        let mut sap = SweepAndPrune::default();
        for i in 0..boxes.len() {
            sap.insert(i as u32);
        }
        let mut found = Vec::new();
        for frame in 0..30 {
            for (i, b) in boxes.iter_mut().enumerate() {
                if live[i] && (i + frame) % 7 == 0 {
                    *b = random_box(&mut rng);
                    if i % 50 == 1 {
                        // A long box: a ground or a cloth among small objects.
                        b.hi[0] += 40.0;
                        b.lo[1] -= 15.0;
                    }
                    sap.touch(i as u32);
                }
            }
            let id = (frame * 37) % boxes.len();
            if live[id] {
                sap.remove(id as u32);
                boxes[id] = Aabb::EMPTY;
            } else {
                boxes[id] = random_box(&mut rng);
                sap.insert(id as u32);
            }
            live[id] = !live[id];
            let mut kept: Vec<(u32, u32)> = sap.update(&boxes).iter().copied().collect();
            kept.sort_unstable();
            let mut expected = Vec::new();
            for i in 0..boxes.len() {
                for j in i + 1..boxes.len() {
                    if live[i] && live[j] && boxes[i].meets(&boxes[j]) {
                        expected.push((i as u32, j as u32));
                    }
                }
            }
            assert_eq!(kept, expected, "frame {frame}: the kept pairs");
            sap.overlapping(&boxes, &mut found);
            found.sort_unstable();
            assert_eq!(found, expected, "frame {frame}: the sweep");
        }
    }
}
