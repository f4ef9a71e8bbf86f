//! Refitting sphere volumes: DVH (centres fixed on vertices, radii recomputed) and SBV (centres
//! and radii recomputed).

use super::RadiusKind;
use super::RefitInput;
use super::boxes::children_union;
use super::fit::{Fit, NodeSlice, Stack, VolumeSlices};
use crate::geometry::aabb::Aabb;
use crate::geometry::predicates::Point;
use crate::geometry::sphere::{Sphere, distance_squared, round_up};

/// Largest squared distance from `c` to the listed vertices (0 for none).
#[inline]
fn farthest_from(c: &Point, vertices: &[u32], positions: &[Point]) -> f64 {
    let mut far = 0.0f64;
    for &v in vertices {
        let d = distance_squared(c, &positions[v as usize]);
        // Not f64::max: its NaN rules cost a dependency chain; distances are never NaN.
        far = if d > far { d } else { far };
    }
    far
}

/// DVH: centres copied from their vertices, radii recomputed.
pub(super) struct FitDvh<'a> {
    pub centre_vertex: &'a [u32],
}

impl Fit for FitDvh<'_> {
    #[inline]
    fn leaf(&self, w: &mut VolumeSlices, input: &RefitInput, r: usize, leaf: usize) -> u64 {
        let positions = input.positions;
        let rings = input.rings;
        // The ring's centre is the sphere's: only the other vertices can be farther.
        let c = positions[rings.centre[r] as usize];
        let verts = rings.vertices.row(r);
        w.spheres[leaf] = Sphere {
            centre: c,
            radius: round_up(farthest_from(&c, verts, positions).sqrt()),
        };
        verts.len() as u64
    }

    #[inline]
    fn inner(&self, w: &mut VolumeSlices, input: &RefitInput, i: usize, stack: &mut Stack) -> u64 {
        w.spheres[i].centre = input.positions[self.centre_vertex[i] as usize];
        radius::<true>(i, &mut w.spheres, input, stack)
    }
}

/// SBV: every node's box of vertices bottom-up, its midpoint as the centre, then the radius.
pub(super) struct FitSbv;

impl Fit for FitSbv {
    #[inline]
    fn leaf(&self, w: &mut VolumeSlices, input: &RefitInput, r: usize, leaf: usize) -> u64 {
        let positions = input.positions;
        let rings = input.rings;
        let b = Aabb::of_points(rings.all_vertices(r).map(|v| &positions[v as usize]));
        let c = b.centre();
        let verts = rings.vertices.row(r);
        let far = farthest_from(&c, verts, positions)
            .max(distance_squared(&c, &positions[rings.centre[r] as usize]));
        w.boxes[leaf] = b;
        w.spheres[leaf] = Sphere {
            centre: c,
            radius: round_up(far.sqrt()),
        };
        verts.len() as u64 + 1
    }

    #[inline]
    fn inner(&self, w: &mut VolumeSlices, input: &RefitInput, i: usize, stack: &mut Stack) -> u64 {
        let b = children_union(&input.tree.nodes[i], &w.boxes);
        w.boxes[i] = b;
        w.spheres[i].centre = b.centre();
        radius::<false>(i, &mut w.spheres, input, stack)
    }
}

/// Sets inner node `i`'s radius around its centre, as the radius kind asks (`SEEDED`: see
/// [`wrapped`]). Returns the distance evaluations.
fn radius<const SEEDED: bool>(
    i: usize,
    spheres: &mut NodeSlice<Sphere>,
    input: &RefitInput,
    stack: &mut Vec<u32>,
) -> u64 {
    let mut evaluations = 0;
    spheres[i].radius = match input.radius {
        RadiusKind::Wrapped => wrapped::<SEEDED>(i, spheres, input, stack, &mut evaluations),
        RadiusKind::Layered => layered(i, spheres, input, &mut evaluations),
    };
    evaluations
}

/// `max(|c - c_child| + r_child)` over the children of node `i`, rounded up.
fn layered(
    i: usize,
    spheres: &NodeSlice<Sphere>,
    input: &RefitInput,
    evaluations: &mut u64,
) -> f64 {
    let node = &input.tree.nodes[i];
    let c = spheres[i].centre;
    *evaluations += u64::from(node.child_count);
    let reach = node
        .children()
        .map(|ch| {
            let s = &spheres[ch as usize];
            distance_squared(&c, &s.centre).sqrt() + s.radius
        })
        .fold(0.0f64, f64::max);
    round_up(reach)
}

/// Farthest vertex below node `i` from its centre, by branch and bound over the subtree: a
/// subtree is skipped when its sphere cannot hold a vertex farther than the best found. With
/// `SEEDED` (DVH), the centres of the nodes below are themselves vertices below, so they seed the
/// bound; otherwise (SBV) only the rings' vertices do, each ring's centre included.
///
/// Rounding: every distance here is a floating-point estimate within a few ulps of the truth,
/// and a subtree is only skipped when its estimated reach is at most the best estimate, so the
/// true farthest distance is within a few ulps of the result, which [`round_up`] covers.
fn wrapped<const SEEDED: bool>(
    i: usize,
    spheres: &NodeSlice<Sphere>,
    input: &RefitInput,
    stack: &mut Vec<u32>,
    evaluations: &mut u64,
) -> f64 {
    let (tree, rings, positions) = (input.tree, input.rings, input.positions);
    let c = spheres[i].centre;
    let mut best = 0.0f64;
    stack.clear();
    stack.extend(tree.nodes[i].children());
    while let Some(x) = stack.pop() {
        let s = &spheres[x as usize];
        // Measured: a square root per node is cheaper than the branches of comparing squares.
        let d = distance_squared(&c, &s.centre).sqrt();
        *evaluations += 1;
        if SEEDED {
            best = best.max(d);
        }
        if d + s.radius <= best {
            continue;
        }
        let node = &tree.nodes[x as usize];
        if node.is_leaf() {
            let r = node.ring_start as usize;
            let verts = rings.vertices.row(r);
            *evaluations += verts.len() as u64;
            let mut far = farthest_from(&c, verts, positions);
            if !SEEDED {
                *evaluations += 1;
                far = far.max(distance_squared(&c, &positions[rings.centre[r] as usize]));
            }
            best = best.max(far.sqrt());
        } else {
            stack.extend(node.children());
        }
    }
    round_up(best)
}
