//! The broad phase: which objects' world boxes overlap, by sweep and prune.
//!
//! Boxes are kept sorted by their lower end on one axis; each frame the order is repaired by
//! insertion sort, which costs one pass plus one step per box that moved past another (little
//! when few objects move), and a sweep along it meets only the boxes whose intervals on that
//! axis overlap. Sweep and prune over a BVH of objects: a scene's objects are few next to a
//! mesh's triangles, its boxes change every frame for the objects that move, and the sorted
//! order survives a frame where a tree would be refit or rebuilt; no all-pairs loop either way.

use crate::geometry::aabb::Aabb;

/// The sweep's state: live objects sorted by their boxes' lower end on `axis`.
#[derive(Clone, Debug, Default)]
pub(crate) struct SweepAndPrune {
    axis: usize,
    order: Vec<u32>,
}

impl SweepAndPrune {
    /// A new object, sorted in at the next sweep.
    pub fn insert(&mut self, id: u32) {
        self.order.push(id);
    }

    /// A removed object.
    pub fn remove(&mut self, id: u32) {
        self.order.retain(|&o| o != id);
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

    /// Every pair of live objects whose boxes meet, `(lower id, higher id)`, into `out` (in no
    /// particular order) after repairing the sort. `boxes` is indexed by object id.
    pub fn overlapping(&mut self, boxes: &[Aabb], out: &mut Vec<(u32, u32)>) {
        out.clear();
        let axis = self.best_axis(boxes);
        // A change of axis costs one full sort; otherwise the order is nearly right.
        if axis != self.axis {
            self.axis = axis;
            self.order
                .sort_unstable_by(|&i, &j| lo(boxes, i, axis).total_cmp(&lo(boxes, j, axis)));
        } else {
            insertion_sort(&mut self.order, |i| lo(boxes, i, axis));
        }
        let order = &self.order;
        for (k, &i) in order.iter().enumerate() {
            let bi = &boxes[i as usize];
            for &j in &order[k + 1..] {
                let bj = &boxes[j as usize];
                if bj.lo[axis] > bi.hi[axis] {
                    break;
                }
                if bi.meets(bj) {
                    out.push((i.min(j), i.max(j)));
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

    /// The sweep finds exactly the pairs an all-pairs loop finds, frame after frame as boxes
    /// move, appear and disappear.
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
        for frame in 0..20 {
            for (i, b) in boxes.iter_mut().enumerate() {
                if (i + frame) % 5 == 0 {
                    *b = random_box(&mut rng);
                }
            }
            let id = (frame * 37) % boxes.len();
            if live[id] {
                sap.remove(id as u32);
            } else {
                sap.insert(id as u32);
            }
            live[id] = !live[id];
            sap.overlapping(&boxes, &mut found);
            found.sort_unstable();
            let mut expected = Vec::new();
            for i in 0..boxes.len() {
                for j in i + 1..boxes.len() {
                    if live[i] && live[j] && boxes[i].meets(&boxes[j]) {
                        expected.push((i as u32, j as u32));
                    }
                }
            }
            assert_eq!(found, expected, "frame {frame}");
        }
    }
}
