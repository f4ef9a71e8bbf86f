//! Segments chained into curves by their ends' names, never by their rounded coordinates.
//!
//! Two segment ends join when they have the same name ([`CurvePoint`]) and no other end has
//! it: a name held by one end is where an open curve stops (a boundary edge, a degenerate pair
//! beside it), a name held by three or more is a junction, where every curve through it stops.
//! So every segment lies on exactly one curve, and the answer depends only on the names, which
//! the exact predicates decide.
//!
//! The order is fixed by the pairs alone: pieces come in `(triangle_a, triangle_b)` order, a
//! curve runs the way its least piece does (along `n_a x n_b` of that pair), a closed curve
//! starts at its least piece, and curves are ordered by their least piece.

#[cfg(test)]
use super::result::Piece;
use super::result::{Curve, CurvePoint, CurveSegment, CurveSet, CurveWork};
use crate::error::{Error, Result};
#[cfg(test)]
use crate::geometry::crossing::EndFeature;

/// A segment end that joins no other.
const NONE: u32 = u32::MAX;

/// Joins the ends of `work.pieces`: sorts them by name into `work.ends`, marks where each
/// name's group starts (`work.groups`, then `ends.len()`), and sets each end's partner (the other
/// end of a group of two). The pieces' points are not read.
pub(crate) fn link(work: &mut CurveWork) {
    let CurveWork {
        pieces,
        ends,
        partner,
        groups,
        ..
    } = work;
    let n = pieces.len();
    debug_assert!(2 * n < NONE as usize, "two ends per piece, indexed by u32");
    ends.clear();
    for (i, p) in pieces.iter().enumerate() {
        let i = i as u64;
        for (which, name) in p.names.iter().enumerate() {
            let (fields, kind) = packed(name);
            ends.push((fields, (kind << 32) | (2 * i + which as u64)));
        }
    }
    ends.sort_unstable();
    partner.clear();
    partner.resize(2 * n, NONE);
    groups.clear();
    let mut at = 0u32;
    for group in ends.chunk_by(|x, y| x.0 == y.0 && x.1 >> 32 == y.1 >> 32) {
        groups.push(at);
        at += group.len() as u32;
        if let [(_, e), (_, f)] = *group {
            let (e, f) = (end_index(e), end_index(f));
            partner[e as usize] = f;
            partner[f as usize] = e;
        }
    }
    groups.push(at);
}

/// A name as two integers that sort and compare as cheaply as the machine allows (the derived
/// order of [`CurvePoint`] compared field by field was most of the ends' sort): its indices,
/// a crossed triangle's first, and its kind. Distinct names give distinct pairs.
fn packed(name: &CurvePoint) -> (u128, u64) {
    let fields = |f: [u32; 4]| f.iter().fold(0u128, |key, &x| (key << 32) | u128::from(x));
    match *name {
        CurvePoint::VertexA(v) => (fields([v, 0, 0, 0]), 0),
        CurvePoint::VertexB(v) => (fields([v, 0, 0, 0]), 1),
        // The triangle first, as for `EdgeB`: the points in one plane then come together.
        CurvePoint::EdgeA { edge, triangle } => (fields([triangle, edge[0], edge[1], 0]), 2),
        CurvePoint::EdgeB { triangle, edge } => (fields([triangle, edge[0], edge[1], 0]), 3),
        CurvePoint::Edges { a, b } => (fields([a[0], a[1], b[0], b[1]]), 4),
    }
}

/// The segment end (`2 * piece + which`) of an entry of `CurveWork::ends`.
#[inline]
pub(crate) fn end_index(packed: u64) -> u32 {
    packed as u32
}

/// Chains `work.pieces` (in `(triangle_a, triangle_b)` order, linked by [`link`], their points
/// set) into curves, written to `out` (cleared first).
pub(crate) fn chain(work: &mut CurveWork, out: &mut CurveSet) -> Result<()> {
    out.clear();
    let CurveWork {
        pieces,
        partner,
        taken,
        walk,
        order,
        walk_all,
        ..
    } = work;
    let n = pieces.len();
    out.segments
        .try_reserve(n)
        .and_then(|()| out.points.try_reserve(n))
        .map_err(|_| Error::OutOfMemory {
            bytes: n * std::mem::size_of::<CurveSegment>(),
        })?;

    taken.clear();
    taken.resize(n, false);
    order.clear();
    walk_all.clear();
    // Open curves: from every end that joins nothing, in piece order; the walk stops at the
    // curve's other open end (every end between joins exactly one other).
    for e in 0..2 * n as u32 {
        if partner[e as usize] != NONE || taken[(e / 2) as usize] {
            continue;
        }
        walk.clear();
        let mut entry = e;
        loop {
            let piece = entry / 2;
            taken[piece as usize] = true;
            walk.push((piece, entry % 2 == 1));
            let next = partner[(entry ^ 1) as usize];
            if next == NONE {
                break;
            }
            entry = next;
        }
        // Run the way the least piece runs.
        let &(least, reversed) = walk.iter().min_by_key(|(p, _)| *p).expect("one piece");
        if reversed {
            walk.reverse();
            for step in walk.iter_mut() {
                step.1 = !step.1;
            }
        }
        order.push((least, walk_all.len() as u32, walk.len() as u32, false));
        walk_all.extend_from_slice(walk);
    }
    // What is left are cycles (every end joins one other); each starts at its least piece,
    // which is the least piece not yet taken, run forwards.
    for start in 0..n as u32 {
        if taken[start as usize] {
            continue;
        }
        let first = walk_all.len() as u32;
        let mut entry = 2 * start;
        let mut closed = false;
        loop {
            let piece = entry / 2;
            taken[piece as usize] = true;
            walk_all.push((piece, entry % 2 == 1));
            let next = partner[(entry ^ 1) as usize];
            if next == NONE {
                // Not reached: such an end would have started an open curve.
                break;
            }
            if next / 2 == start {
                closed = true;
                break;
            }
            entry = next;
        }
        order.push((start, first, walk_all.len() as u32 - first, closed));
    }
    order.sort_unstable_by_key(|c| c.0);

    for (curve, &(_, first, count, closed)) in order.iter().enumerate() {
        let begin = out.segments.len();
        for &(piece, reversed) in &walk_all[first as usize..(first + count) as usize] {
            let p = &pieces[piece as usize];
            let (s, e) = if reversed { (1, 0) } else { (0, 1) };
            out.segments.push(CurveSegment {
                triangle_a: p.triangle_a,
                triangle_b: p.triangle_b,
                curve: curve as u32,
                reserved: 0,
                start: p.points[s],
                end: p.points[e],
            });
            out.points.push([p.names[s], p.names[e]]);
        }
        out.curves.push(Curve {
            segments: begin..out.segments.len(),
            closed,
        });
    }
    Ok(())
}

/// A piece's end names, for tests.
#[cfg(test)]
pub(crate) fn piece(a: u32, b: u32, names: [CurvePoint; 2]) -> Piece {
    Piece {
        triangle_a: a,
        triangle_b: b,
        names,
        points: [[0.0; 3]; 2],
        features: [EndFeature::CornerOfA(0); 2],
    }
}
