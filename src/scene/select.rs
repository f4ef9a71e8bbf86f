//! Which object pairs a scene query asks about: the pairs whose boxes meet (the broad phase),
//! that the collision filters allow, and each object with self-contact on paired with itself.

use super::Scene;

/// Which boxes the broad phase compares.
#[derive(Clone, Copy, Debug)]
pub(super) enum Reach {
    /// The world boxes at the end of each object's step (intersection).
    End,
    /// The boxes over each object's whole step (continuous collision).
    Swept,
    /// The end boxes, within this distance of each other (nearness).
    Within(f64),
}

impl Scene {
    /// The object pairs a query asks about, sorted, into `out`: `(i, j)` with `i < j` whose
    /// boxes meet (as `reach` says) and that the filters allow, and `(i, i)` for each object
    /// with self-contact on.
    pub(super) fn select(&mut self, reach: Reach, out: &mut Vec<(u32, u32)>) {
        out.clear();
        match reach {
            Reach::End => out.extend(self.broad.update(&self.boxes).iter().copied()),
            Reach::Swept => out.extend(self.broad_swept.update(&self.swept).iter().copied()),
            Reach::Within(d) => {
                // Boxes grown by half the distance (rounded up) meet wherever the boxes come
                // within the distance.
                let half = (0.5 * d).next_up();
                if self.near_distance != Some(half.to_bits()) {
                    self.near.forget();
                    self.near_distance = Some(half.to_bits());
                }
                self.near_boxes.clear();
                self.near_boxes.extend(
                    self.boxes
                        .iter()
                        .map(|b| if b.is_empty() { *b } else { b.widened(half) }),
                );
                out.extend(self.near.update(&self.near_boxes).iter().copied());
            }
        }
        self.filter_and_add_self(out);
    }

    /// Keeps the pairs of `pairs` that the filters allow, adds each object with self-contact on
    /// paired with itself, and sorts them.
    pub(super) fn filter_and_add_self(&self, pairs: &mut Vec<(u32, u32)>) {
        pairs.retain(|&(i, j)| self.allowed(i, j));
        pairs.extend(
            self.objects
                .iter()
                .enumerate()
                .filter(|(_, o)| o.as_ref().is_some_and(|o| o.self_contact))
                .map(|(id, _)| (id as u32, id as u32)),
        );
        pairs.sort_unstable();
    }

    /// Do the filters let objects `i` and `j` be tested?
    pub(super) fn allowed(&self, i: u32, j: u32) -> bool {
        let (Some(Some(a)), Some(Some(b))) =
            (self.objects.get(i as usize), self.objects.get(j as usize))
        else {
            return false;
        };
        a.group & b.mask != 0 && b.group & a.mask != 0 && !self.excluded.contains(&(i, j))
    }
}

/// An object `pairs` names (in [`marks`]).
pub(super) const NEEDED: u8 = 1;
/// An object `pairs` names paired with itself (in [`marks`]).
pub(super) const WITH_ITSELF: u8 = 2;

/// Per object id (`count` of them) into `out`: [`NEEDED`] when `pairs` names it, with
/// [`WITH_ITSELF`] when paired with itself.
pub(super) fn marks(pairs: &[(u32, u32)], count: usize, out: &mut Vec<u8>) {
    out.clear();
    out.resize(count, 0);
    for &(i, j) in pairs {
        out[i as usize] |= NEEDED;
        out[j as usize] |= NEEDED;
        if i == j {
            out[i as usize] |= WITH_ITSELF;
        }
    }
}
