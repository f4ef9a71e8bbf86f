//! Volumes over a motion: fitted to the end positions, then grown to hold the start positions
//! too, so that each volume holds the straight path of every vertex below it (a path lies in
//! the box of its ends, and within the larger of its ends' distances from any centre).

use super::{RefitInput, Volumes};
use crate::geometry::aabb::Aabb;
use crate::geometry::predicates::Point;

impl Volumes {
    /// Grows the volumes, fitted to `input.positions` (the end of the step), to hold each
    /// vertex's position in `start` too. Boxes take the union with the start positions' boxes;
    /// spheres keep their centres (mesh vertices at the end, or their own) and grow by the
    /// longest displacement of a vertex below them, rounded up. `scratch` holds a value per node.
    pub fn hold_start(&mut self, input: &RefitInput, start: &[Point], scratch: &mut Vec<f64>) {
        let nodes = &input.tree.nodes;
        let rings = input.rings;
        match self {
            Volumes::Aabb { boxes } => {
                // Children come after their parent: a reverse pass sees them first.
                for n in (0..nodes.len()).rev() {
                    let node = &nodes[n];
                    if node.is_leaf() {
                        let r = node.ring_start as usize;
                        for v in rings.all_vertices(r) {
                            boxes[n].grow(&start[v as usize]);
                        }
                    } else {
                        let mut b = Aabb::EMPTY;
                        for c in node.children() {
                            b.merge(&boxes[c as usize]);
                        }
                        boxes[n] = b;
                    }
                }
            }
            Volumes::Dvh { spheres, .. } | Volumes::Sbv { spheres, .. } => {
                scratch.clear();
                scratch.resize(nodes.len(), 0.0);
                for n in (0..nodes.len()).rev() {
                    let node = &nodes[n];
                    let longest = if node.is_leaf() {
                        let r = node.ring_start as usize;
                        rings
                            .all_vertices(r)
                            .map(|v| displacement(&start[v as usize], &input.positions[v as usize]))
                            .fold(0.0, f64::max)
                    } else {
                        node.children()
                            .map(|c| scratch[c as usize])
                            .fold(0.0, f64::max)
                    };
                    scratch[n] = longest;
                    let s = &mut spheres[n];
                    s.radius = (s.radius + longest).next_up();
                }
            }
        }
    }
}

/// An upper bound on the distance from `a` to `b`: the computed norm is within a few rounding
/// errors of the exact one, and the factor covers them (an overflow gives infinity, which holds
/// everything).
fn displacement(a: &Point, b: &Point) -> f64 {
    let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let norm = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    if norm < 1e-140 {
        // The squares may have underflowed: the sum of the magnitudes bounds the norm.
        return (d[0].abs() + d[1].abs() + d[2].abs()) * (1.0 + 4.0 * f64::EPSILON);
    }
    // The differences are rounded too: at most half an ulp each, which the factor also covers.
    norm * (1.0 + 8.0 * f64::EPSILON)
}
