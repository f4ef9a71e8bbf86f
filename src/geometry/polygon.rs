//! Is a closed polygon simple? Exact, for the loops of self-collision's patch test.
//!
//! The loops are those of mesh patches projected along an axis: a few dozen corners, jagged
//! (they run round rings of triangles), seldom convex or star-shaped, and monotone along an
//! axis only when small. The test cuts a loop into pieces that are monotone in the
//! lexicographic order of the points (along `x`, ties broken by `y`, or the other way round,
//! whichever gives fewer pieces) and checks each pair of pieces over the range they share:
//! linear in the loop's length when few pieces meet each line across it, as for these loops.
//! Loops cut into very many pieces go to a sweep over the edges' boxes instead.

use super::predicates::{Sign, orient2d};

/// Room for [`is_simple`], kept by the caller so that a warm test allocates nothing.
#[derive(Debug, Default)]
pub struct PolygonScratch {
    /// Per edge: does it run forwards along `x` (bit 0), along `y` (bit 1)?
    ups: Vec<u8>,
    /// The pieces' points, each piece in increasing order.
    points: Vec<[f64; 2]>,
    pieces: Vec<Piece>,
    /// The pieces crossing the sweep's line, from below.
    active: Vec<Crossing>,
    edges: Vec<EdgeBox>,
}

impl PolygonScratch {
    /// Elements of room held, over all its buffers: grows when a test needs more.
    pub(crate) fn room(&self) -> usize {
        self.ups.capacity()
            + self.points.capacity()
            + self.pieces.capacity()
            + self.active.capacity()
            + self.edges.capacity()
    }
}

/// A monotone piece of a loop: `points[start..=end]` in increasing order, from corner `lo` of
/// the loop to corner `hi`.
#[derive(Clone, Copy, Debug)]
struct Piece {
    start: u32,
    end: u32,
    lo: u32,
    hi: u32,
}

/// Loops cut into more pieces than this go to the sweep: the pairs of pieces would cost more.
const MOST_PIECES: usize = 48;

/// Is the closed polygon `p` simple: no two edges meet except consecutive ones at their common
/// corner, and no corner turns back along its incoming edge? Exact. `p` has three corners or
/// more.
pub fn is_simple(p: &[[f64; 2]], scratch: &mut PolygonScratch) -> bool {
    let m = p.len();
    debug_assert!(m >= 3);
    // Edge `i` runs from corner `i` to `i + 1`; the pieces end where an edge's direction in the
    // order differs from the one before it. Both orders are counted in one pass, and each
    // edge's directions kept (bit 0 along `x`, bit 1 along `y`).
    let ups = &mut scratch.ups;
    ups.clear();
    let (mut turns_x, mut turns_y) = (0usize, 0usize);
    let (mut up_x, mut up_y) = (before_x(p[m - 1], p[0]), before_y(p[m - 1], p[0]));
    for i in 0..m {
        let (a, b) = (p[i], p[if i + 1 == m { 0 } else { i + 1 }]);
        if a == b {
            return false;
        }
        let (x, y) = (before_x(a, b), before_y(a, b));
        turns_x += usize::from(x != up_x);
        turns_y += usize::from(y != up_y);
        (up_x, up_y) = (x, y);
        ups.push(u8::from(x) | u8::from(y) << 1);
    }
    let pieces = turns_x.min(turns_y);
    if pieces > MOST_PIECES {
        return sweep(p, &mut scratch.edges);
    }
    // Along `y` as along `x` with the coordinates swapped (a reflection, which keeps a loop
    // simple or not).
    if turns_x <= turns_y {
        monotone_pieces(p, 1, |q| q, scratch)
    } else {
        monotone_pieces(p, 2, |q| [q[1], q[0]], scratch)
    }
}

/// Does `a` come before `b` along `x` (ties broken by `y`)?
#[inline(always)]
fn before_x(a: [f64; 2], b: [f64; 2]) -> bool {
    // Without branches: the loops' directions change often, and would be mispredicted.
    (a[0] < b[0]) | ((a[0] == b[0]) & (a[1] < b[1]))
}

/// Does `a` come before `b` along `y` (ties broken by `x`)?
#[inline(always)]
fn before_y(a: [f64; 2], b: [f64; 2]) -> bool {
    before_x([a[1], a[0]], [b[1], b[0]])
}

/// [`is_simple`] of the loop `p` read through `at` (the identity or a swap of coordinates),
/// with no two consecutive corners equal, by its pieces monotone along `x` (`bit` of
/// `scratch.ups` says which edges run forwards).
///
/// Each piece is the graph of a function over the order (the order is that of `x + e y` for a
/// small enough `e > 0`), so it cannot meet itself; [`sweep_pieces`] checks them against each
/// other.
#[inline(always)]
fn monotone_pieces(
    p: &[[f64; 2]],
    bit: u8,
    at: impl Fn([f64; 2]) -> [f64; 2],
    scratch: &mut PolygonScratch,
) -> bool {
    let m = p.len();
    let PolygonScratch {
        ups,
        points,
        pieces,
        active,
        ..
    } = scratch;
    let up = |i: usize| ups[i] & bit != 0;
    // The first corner where a piece starts: one whose edge differs in direction from the one
    // before it (there are at least two, since the loop closes).
    let Some(first) = (0..m).find(|&i| up(i) != up(if i == 0 { m - 1 } else { i - 1 })) else {
        return false; // unreachable for a closed loop of distinct consecutive corners
    };
    points.clear();
    pieces.clear();
    let next = |i: usize| if i + 1 == m { 0 } else { i + 1 };
    let mut from = first;
    loop {
        let rising = up(from);
        let mut to = next(from);
        while up(to) == rising {
            to = next(to);
        }
        // Corners `from..=to`, round the loop: at most two runs of `p`.
        let (head, tail) = if from <= to {
            (&p[from..=to], &p[..0])
        } else {
            (&p[from..], &p[..=to])
        };
        let start = points.len() as u32;
        let run = head.iter().chain(tail).map(|&c| at(c));
        if rising {
            points.extend(run);
        } else {
            points.extend(run.rev());
        }
        let (lo, hi) = if rising { (from, to) } else { (to, from) };
        pieces.push(Piece {
            start,
            end: points.len() as u32 - 1,
            lo: lo as u32,
            hi: hi as u32,
        });
        if to == first {
            break;
        }
        from = to;
    }
    // Partners (the two pieces leaving a lowest corner) next to each other.
    pieces.sort_unstable_by(|a, b| {
        let (pa, pb) = (points[a.start as usize], points[b.start as usize]);
        if before_x(pa, pb) || (pa == pb && a.lo < b.lo) {
            std::cmp::Ordering::Less
        } else {
            std::cmp::Ordering::Greater
        }
    });
    sweep_pieces(points, pieces, active)
}

/// A piece crossing the sweep's line: its edge over the line runs from `from` (point `at`) to
/// `to`; it ends at point `end`, corner `hi` of the loop.
#[derive(Clone, Copy, Debug)]
struct Crossing {
    from: [f64; 2],
    to: [f64; 2],
    at: u32,
    end: u32,
    hi: u32,
}

impl Crossing {
    /// `> 0`: `c` is above the edge, which runs forwards along `x`.
    #[inline(always)]
    fn above(&self, c: [f64; 2]) -> Sign {
        orient2d(self.from, self.to, c)
    }
}

/// The sweep of [`monotone_pieces`]: the pieces crossing the line are kept in order from below,
/// and every corner the line reaches is checked strictly between the edges of its piece's
/// neighbours. Between two corners the gap between neighbouring pieces is linear, so two pieces
/// meet only where one's corner fails against the other's edge while they are neighbours (a
/// piece between them would have to meet one of them first), or at a corner two corners share.
/// `pieces` are in order of their first points, partners together.
fn sweep_pieces(points: &[[f64; 2]], pieces: &[Piece], active: &mut Vec<Crossing>) -> bool {
    active.clear();
    let mut starting = 0;
    // Each corner is one step of the sweep (the two pieces that start or end at a turning
    // corner together), so two steps at one point are two corners at one point.
    let mut last = [f64::NAN; 2];
    loop {
        // The next corner along the line: the lowest of the active pieces' next corners and the
        // next pieces' first.
        let (mut slot, mut c) = (usize::MAX, [f64::INFINITY; 2]);
        for (s, x) in active.iter().enumerate() {
            if before_x(x.to, c) {
                (slot, c) = (s, x.to);
            }
        }
        let start = pieces
            .get(starting)
            .map(|piece| points[piece.start as usize]);
        if let Some(s) = start.filter(|&s| slot == usize::MAX || before_x(s, c)) {
            // Two pieces leave the corner `s`: in the order above the first edge below it
            // (none on it), the lower of them first.
            let (a, b) = (pieces[starting], pieces.get(starting + 1));
            let Some(&b) = b.filter(|b| b.lo == a.lo && s != last) else {
                return false; // a corner met twice (or, unreachably, a lone piece)
            };
            last = s;
            let at = active.partition_point(|x| x.above(s) > 0);
            if active.get(at).is_some_and(|x| x.above(s) == 0) {
                return false;
            }
            let crossing = |x: Piece| Crossing {
                from: s,
                to: points[x.start as usize + 1],
                at: x.start,
                end: x.end,
                hi: x.hi,
            };
            let (a, b) = (crossing(a), crossing(b));
            let (lower, upper) = match b.above(a.to) {
                ..0 => (a, b),
                1.. => (b, a),
                0 => return false, // the loop turns straight back at `s`
            };
            active.splice(at..at, [lower, upper]);
            starting += 2;
            continue;
        }
        if slot == usize::MAX {
            return true;
        }
        if c == last {
            return false;
        }
        last = c;
        let x = active[slot];
        let strictly_between = |low: usize, high: usize| {
            !(low > 0 && active[low - 1].above(c) <= 0
                || high + 1 < active.len() && active[high + 1].above(c) >= 0)
        };
        if x.at + 1 < x.end {
            // A corner inside the piece.
            if !strictly_between(slot, slot) {
                return false;
            }
            let x = &mut active[slot];
            x.at += 1;
            x.from = c;
            x.to = points[x.at as usize + 1];
            continue;
        }
        // The piece's last corner, which its partner ends at too: the two must be neighbours
        // (a piece between them would pass through the corner).
        let partner = [slot.wrapping_sub(1), slot + 1]
            .into_iter()
            .find(|&s| active.get(s).is_some_and(|o| o.hi == x.hi));
        let Some(partner) = partner else {
            return false;
        };
        let (low, high) = (slot.min(partner), slot.max(partner));
        if !strictly_between(low, high) {
            return false;
        }
        active.drain(low..=high);
    }
}

/// Going counterclockwise about `v` from the direction of `base`, does the direction of `d1`
/// come strictly before that of `d2`? Exact; `false` when either lies along `base` or both
/// point the same way. None of `base`, `d1`, `d2` is `v`.
pub fn turns_before(v: [f64; 2], base: [f64; 2], d1: [f64; 2], d2: [f64; 2]) -> bool {
    // Which part of the turn a direction is in: along `base` (0), the half to its left (1),
    // straight back (2), the half to its right (3).
    let part = |d: [f64; 2]| match orient2d(v, base, d) {
        1.. => 1,
        ..0 => 3,
        0 => {
            // On the line: the same way as `base` when both coordinates' differences agree.
            let same = (0..2)
                .all(|k| (d[k] > v[k]) == (base[k] > v[k]) && (d[k] < v[k]) == (base[k] < v[k]));
            if same { 0 } else { 2 }
        }
    };
    let (p1, p2) = (part(d1), part(d2));
    p1 != 0 && p2 != 0 && (p1 < p2 || (p1 == p2 && p1 % 2 == 1 && orient2d(v, d1, d2) > 0))
}

/// Do the chains `a` and `b` keep apart? Each runs from the other's last corner to its first
/// (`a[0] == b[b.len() - 1]`, `b[0] == a[a.len() - 1]`, two or more corners each), and no edge
/// of one may meet an edge of the other, except at those two corners, where the edges that
/// share them are not tested (the caller tells them apart by [`turns_before`]). Exact.
///
/// Only edges within the other chain's box can meet it; those are tested pair by pair, boxes
/// first, or, when there are many, by a sweep along `x`.
pub fn chains_apart(a: &[[f64; 2]], b: &[[f64; 2]], scratch: &mut PolygonScratch) -> bool {
    edges_apart(a, b, false, scratch)
}

/// Do the regions of two simple counterclockwise loops that share one corner meet there only?
/// Each loop is given closed at that corner (`a[0] == a[a.len() - 1] == b[0] == b[b.len() -
/// 1]`, four corners or more each). Exact.
///
/// Near the corner, going counterclockwise from `a`'s first edge, `a`'s region ends (its last
/// edge) before `b`'s begins (its first edge), and `b`'s ends before `a`'s begins again; away
/// from it no edges meet. Then neither loop enters the other's region (it leaves the corner
/// outside it and never crosses its boundary), so neither region holds a point of the other.
pub fn corner_apart(a: &[[f64; 2]], b: &[[f64; 2]], scratch: &mut PolygonScratch) -> bool {
    let v = a[0];
    turns_before(v, a[1], a[a.len() - 2], b[1])
        && turns_before(v, a[1], b[1], b[b.len() - 2])
        && edges_apart(a, b, true, scratch)
}

/// [`chains_apart`], and with `one_corner` (the chains are loops closed at one shared corner,
/// as in [`corner_apart`]) the first edges and the last edges of both are not tested either:
/// the four edges at the corner meet there.
fn edges_apart(
    a: &[[f64; 2]],
    b: &[[f64; 2]],
    one_corner: bool,
    scratch: &mut PolygonScratch,
) -> bool {
    let bounds = |c: &[[f64; 2]]| {
        c.iter()
            .fold(EdgeBox::new(c[0], c[0], 0), |e, &q| e.grown(q))
    };
    let (box_a, box_b) = (bounds(a), bounds(b));
    let (ea, eb) = (a.len() - 1, b.len() - 1);
    let edges = &mut scratch.edges;
    edges.clear();
    // Edges of `b` are numbered after those of `a`.
    for (chain, other, offset) in [(a, &box_b, 0), (b, &box_a, ea)] {
        for i in 0..chain.len() - 1 {
            let e = EdgeBox::new(chain[i], chain[i + 1], (offset + i) as u32);
            if e.meets(other) {
                edges.push(e);
            }
        }
    }
    let point = |i: usize| {
        if i < ea {
            (a[i], a[i + 1])
        } else {
            (b[i - ea], b[i - ea + 1])
        }
    };
    // Edges of different chains that may meet: not the two pairs at the shared corners.
    let test = |e: &EdgeBox, f: &EdgeBox| {
        let (i, j) = (e.index.min(f.index) as usize, e.index.max(f.index) as usize);
        let last_b = ea + eb - 1;
        if i >= ea
            || j < ea
            || (i == ea - 1 && j == ea)
            || (i == 0 && j == last_b)
            || (one_corner && ((i == 0 && j == ea) || (i == ea - 1 && j == last_b)))
        {
            return false;
        }
        let ((p, q), (r, s)) = (point(i), point(j));
        e.meets(f) && segments_meet(p, q, r, s)
    };
    if edges.len() <= 16 {
        return !(0..edges.len()).any(|s| edges[s + 1..].iter().any(|f| test(&edges[s], f)));
    }
    edges.sort_unstable_by(|e, f| e.lo[0].total_cmp(&f.lo[0]));
    !(0..edges.len()).any(|s| {
        let e = &edges[s];
        edges[s + 1..]
            .iter()
            .take_while(|f| f.lo[0] <= e.hi[0])
            .any(|f| test(e, f))
    })
}

/// An edge of a polygon, `index`, with its box.
#[derive(Clone, Copy, Debug)]
struct EdgeBox {
    lo: [f64; 2],
    hi: [f64; 2],
    index: u32,
}

impl EdgeBox {
    fn new(a: [f64; 2], b: [f64; 2], index: u32) -> EdgeBox {
        EdgeBox {
            lo: [a[0].min(b[0]), a[1].min(b[1])],
            hi: [a[0].max(b[0]), a[1].max(b[1])],
            index,
        }
    }

    /// The box grown to hold `q`.
    fn grown(self, q: [f64; 2]) -> EdgeBox {
        EdgeBox {
            lo: [self.lo[0].min(q[0]), self.lo[1].min(q[1])],
            hi: [self.hi[0].max(q[0]), self.hi[1].max(q[1])],
            index: self.index,
        }
    }

    /// Do the closed boxes share a point?
    fn meets(&self, other: &EdgeBox) -> bool {
        self.lo[0] <= other.hi[0]
            && other.lo[0] <= self.hi[0]
            && self.lo[1] <= other.hi[1]
            && other.lo[1] <= self.hi[1]
    }
}

/// [`is_simple`] by a sweep along `x`: edges in order of their lower `x`, each tested only
/// against the edges after it whose lower `x` is within its span and whose boxes meet.
fn sweep(p: &[[f64; 2]], edges: &mut Vec<EdgeBox>) -> bool {
    let m = p.len();
    let after = |i: usize| if i + 1 == m { 0 } else { i + 1 };
    for i in 0..m {
        let (a, b) = (p[i], p[after(i)]);
        if a == b {
            return false;
        }
        // The corner at b: the next edge must not fold back over this one.
        let c = p[after(after(i))];
        if (c == b || between(a, b, c) || between(b, c, a)) && orient2d(a, b, c) == 0 {
            return false;
        }
    }
    edges.clear();
    edges.extend((0..m).map(|i| EdgeBox::new(p[i], p[after(i)], i as u32)));
    edges.sort_unstable_by(|e, f| e.lo[0].total_cmp(&f.lo[0]));
    !(0..m).any(|s| {
        let e = &edges[s];
        edges[s + 1..]
            .iter()
            .take_while(|f| f.lo[0] <= e.hi[0])
            .any(|f| {
                let (i, j) = (e.index.min(f.index) as usize, e.index.max(f.index) as usize);
                let apart = j - i > 1 && !(i == 0 && j == m - 1);
                apart
                    && e.lo[1] <= f.hi[1]
                    && f.lo[1] <= e.hi[1]
                    && segments_meet(p[i], p[after(i)], p[j], p[after(j)])
            })
    })
}

/// Is `x` on the segment `[a, b]` (all three collinear)? Coordinates compared exactly.
fn between(a: [f64; 2], b: [f64; 2], x: [f64; 2]) -> bool {
    (0..2).all(|k| a[k].min(b[k]) <= x[k] && x[k] <= a[k].max(b[k]))
}

/// Do the closed segments `[a, b]` and `[c, d]` share a point? Exact.
#[inline]
fn segments_meet(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let (o1, o2) = (orient2d(a, b, c), orient2d(a, b, d));
    let (o3, o4) = (orient2d(c, d, a), orient2d(c, d, b));
    let opposite = |x: Sign, y: Sign| x * y <= 0;
    if o1 == 0 && o2 == 0 {
        // Collinear: overlapping projections on the line.
        return between(a, b, c) || between(a, b, d) || between(c, d, a) || between(c, d, b);
    }
    opposite(o1, o2) && opposite(o3, o4)
}

#[cfg(test)]
mod tests;
