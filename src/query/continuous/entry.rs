//! The continuous queries: the traversal over the meshes' motion finds the leaf pairs whose
//! volumes overlap, and the narrow phase tests their primitive pairs, on one thread or shared
//! out in chunks whose results are joined in order (so the answer does not depend on the
//! thread count).

use super::impacts::{CcdOptions, CcdStats, Impact, Impacts};
use super::sweeps::{Sweeps, VertexPaths};
use crate::error::Result;
use crate::mesh::Mesh;
use crate::query::engine::{NodeVolumes, OneMesh, Reach, leaf_pairs};
use crate::query::primitives::{self, Narrow, Owners};
use std::sync::atomic::AtomicU64;

/// Every vertex-face and edge-edge pair of meshes `a` and `b` that meets while each moves
/// through its last motion ([`Mesh::refit_motion`]; a mesh refit without one stays still), with
/// the earliest time it does: every vertex of `a` against every triangle of `b`
/// ([`crate::ImpactKind::VertexFace`]), every triangle of `a` against every vertex of `b`
/// ([`crate::ImpactKind::FaceVertex`]), every edge of `a` against every edge of `b` (an edge is
/// a pair of distinct vertices joined by a triangle side, counted once however many triangles
/// share it). Vertices that belong to no triangle are not tested.
///
/// Exact with the default [`crate::CcdMode::Exact`]: the answer is that of
/// [`crate::exact::vertex_face_impact`] and [`crate::exact::edge_edge_impact`] over every
/// primitive pair. The result replaces the contents of `out`, sorted by
/// `(kind, a0, a1, b0, b1)`; the counters are returned.
///
/// Errors: [`crate::Error::OutOfMemory`] when the result cannot grow (set
/// [`CcdOptions::max_impacts`] to bound it). On error `out` still holds the previous result.
pub fn continuous_collide(
    a: &Mesh,
    b: &Mesh,
    options: &CcdOptions,
    out: &mut Impacts,
) -> Result<CcdStats> {
    let best = AtomicU64::new(1.0f64.to_bits());
    impacts_sharing(a, Some(b), options, out, &best)
}

/// Every pair of one mesh's primitives that meets during its last motion, with the earliest
/// time: every vertex against every triangle that does not contain it (reported as
/// [`crate::ImpactKind::VertexFace`], the vertex in `a0`), every pair of edges that share no
/// vertex (`(a0, a1) < (b0, b1)`). Otherwise as [`continuous_collide`].
pub fn self_continuous_collide(
    mesh: &Mesh,
    options: &CcdOptions,
    out: &mut Impacts,
) -> Result<CcdStats> {
    let best = AtomicU64::new(1.0f64.to_bits());
    impacts_sharing(mesh, None, options, out, &best)
}

/// The traversal over the motion: leaf pairs whose volumes overlap (the volumes of a moving
/// mesh hold its whole motion).
#[derive(Clone, Copy)]
struct SweptVolumes {
    one_mesh: bool,
}

impl<'m> Reach<'m> for SweptVolumes {
    type SideA<K: NodeVolumes<'m>> = K;

    fn side_a<K: NodeVolumes<'m>>(&self, kind: K) -> K {
        kind
    }

    fn own(&self) -> Option<OneMesh<'m>> {
        // No patch skips: a patch free of self-intersection at the end may still pass through
        // itself during the step.
        self.one_mesh.then_some(OneMesh { patches: None })
    }
}

/// [`continuous_collide`] of `a` and `b`, or [`self_continuous_collide`] of `a` (`b` is `None`),
/// as part of a larger query: with [`CcdOptions::earliest_only`], `best` holds the bits of the
/// earliest impact time that query has found so far (1 at first), and is lowered by this one
/// (each primitive test searches only up to it, ties included). The impact reported is then the
/// earliest of this pair's at or before the time `best` held when its primitives were tested:
/// the pair's own earliest whenever that is no later than the whole query's.
pub(crate) fn impacts_sharing(
    a: &Mesh,
    b: Option<&Mesh>,
    options: &CcdOptions,
    out: &mut Impacts,
    best: &AtomicU64,
) -> Result<CcdStats> {
    let one_mesh = b.is_none();
    let b = b.unwrap_or(a);
    let test = SweptVolumes { one_mesh };
    let broad = leaf_pairs(
        a,
        (!one_mesh).then_some(b),
        test,
        options.threads,
        &mut out.leaves,
    )?;
    let mut stats = CcdStats {
        bv_tests: broad.bv_tests,
        ..CcdStats::default()
    };
    let limit = if options.earliest_only {
        options.max_impacts.unwrap_or(usize::MAX).min(1)
    } else {
        options.max_impacts.unwrap_or(usize::MAX)
    };
    let Impacts {
        items,
        spare,
        leaves,
        narrow_space,
    } = out;
    let leaves = leaves.as_slice();
    spare.clear();
    if limit == 0 {
        stats.truncated = true;
        std::mem::swap(items, spare);
        return Ok(stats);
    }
    let narrow = Narrow {
        a: Owners::new(a),
        b: Owners::new(b),
        one_mesh,
        test: Sweeps {
            a: VertexPaths::new(a),
            b: VertexPaths::new(b),
            mode: options.mode,
            earliest_only: options.earliest_only,
            best,
        },
    };
    let joined = primitives::test_leaf_pairs(
        &narrow,
        leaves,
        options.threads,
        limit,
        narrow_space,
        spare,
        Impact::key,
    )?;
    stats.primitive_tests = joined.primitive_tests;
    if options.earliest_only {
        let first = narrow_space
            .workers
            .iter()
            .filter_map(|w| w.best)
            .min_by(|x, y| (x.toi, x.key()).partial_cmp(&(y.toi, y.key())).unwrap());
        spare.extend(first);
    } else {
        stats.truncated = joined.truncated;
    }
    stats.impacts = spare.len() as u64;
    stats.earliest_toi = spare.iter().map(|i| i.toi).fold(f64::INFINITY, f64::min);
    std::mem::swap(items, spare);
    Ok(stats)
}
