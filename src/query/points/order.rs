//! Many points, one mesh: the points taken in Morton order, so that consecutive points are near
//! each other and each can start from its predecessor's answer, in blocks shared among the
//! threads; the answers written back in the caller's order.

use crate::error::{Error, Result};
use crate::geometry::predicates::Point;
use crate::threads::{self, Step};
use std::cell::RefCell;

/// Points a block holds: enough that the walks of consecutive points share their answers, few
/// enough that the blocks balance the threads.
const BLOCK: usize = 256;

/// Below this many points there is no order to gain from: they are taken as given.
const ORDER_MIN_POINTS: usize = 64;

/// Fails with [`Error::NonFinitePoint`] for the first point with a NaN or infinite coordinate,
/// or [`Error::ResultLength`] unless there is one result per point.
pub(super) fn check_points(points: &[Point], results: usize) -> Result<()> {
    for (point, p) in points.iter().enumerate() {
        for (axis, &value) in p.iter().enumerate() {
            if !value.is_finite() {
                return Err(Error::NonFinitePoint { point, axis, value });
            }
        }
    }
    if results != points.len() {
        return Err(Error::ResultLength {
            expected: points.len(),
            got: results,
        });
    }
    Ok(())
}

/// `x`'s 21 low bits spread to every third bit of the result.
fn spread(x: u64) -> u64 {
    let mut x = x & 0x1f_ffff;
    x = (x | x << 32) & 0x1f_0000_0000_ffff;
    x = (x | x << 16) & 0x1f_0000_ff00_00ff;
    x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
    x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
    x = (x | x << 2) & 0x1249_2492_4924_9249;
    x
}

/// The caller's points in Morton order (by 21 bits a coordinate over their bounding box), as
/// indices into `points`, into `order`.
fn morton_order(points: &[Point], order: &mut Vec<u32>, keys: &mut Vec<(u64, u32)>) {
    order.clear();
    if points.len() < ORDER_MIN_POINTS {
        order.extend(0..points.len() as u32);
        return;
    }
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    // Halved, so that the span of coordinates near the largest double stays finite.
    let scale: [f64; 3] =
        std::array::from_fn(|k| 2_097_151.0 / (hi[k] * 0.5 - lo[k] * 0.5).max(f64::MIN_POSITIVE));
    keys.clear();
    keys.extend(points.iter().enumerate().map(|(i, p)| {
        let cell = |k: usize| ((p[k] * 0.5 - lo[k] * 0.5) * scale[k]) as u64;
        (
            spread(cell(0)) | spread(cell(1)) << 1 | spread(cell(2)) << 2,
            i as u32,
        )
    }));
    keys.sort_unstable();
    order.extend(keys.iter().map(|k| k.1));
}

/// The calling thread's order of the points and the answers in that order, kept between calls
/// so that a warmed-up query allocates nothing for them.
#[derive(Default)]
pub(super) struct Scratch<T> {
    order: Vec<u32>,
    keys: Vec<(u64, u32)>,
    answers: Vec<T>,
}

thread_local! {
    static CLOSEST: RefCell<Scratch<super::ClosestPoint>> = RefCell::default();
    static WINDING: RefCell<Scratch<i32>> = RefCell::default();
    static SIGNED: RefCell<Scratch<f64>> = RefCell::default();
}

/// The answer types of the point queries, each with its thread's scratch.
pub(super) trait Answer: Copy + Default + Send + Sync + 'static {
    #[doc(hidden)]
    fn with_scratch<R>(f: impl FnOnce(&mut Scratch<Self>) -> R) -> R;
}

macro_rules! answer {
    ($t:ty, $cell:ident) => {
        impl Answer for $t {
            fn with_scratch<R>(f: impl FnOnce(&mut Scratch<Self>) -> R) -> R {
                $cell.with(|s| f(&mut s.borrow_mut()))
            }
        }
    };
}
answer!(super::ClosestPoint, CLOSEST);
answer!(i32, WINDING);
answer!(f64, SIGNED);

/// A thread's scratch for the walks of one point after another, kept between calls.
#[derive(Default)]
pub(super) struct Walker {
    /// The walks' stack.
    pub stack: super::walk::Stack,
    /// The triangles an exact walk found.
    pub found: Vec<(u32, crate::geometry::nearest::Decided)>,
    /// The triangles the nearest walk kept, with certain lower bounds of their distances.
    pub kept: Vec<(u32, f64)>,
    /// The answer of the point before, in the block: the triangle nearest it.
    pub previous: Option<u32>,
}

thread_local! {
    static WALKER: RefCell<Walker> = RefCell::default();
}

/// Runs `answer(walker, point)` for every point, in Morton order, in blocks shared among up to
/// `threads` threads (as [`crate::QueryOptions::threads`]), and writes each answer at its
/// point's index in `out`. A block's points are answered in order by one thread's walker, whose
/// `previous` answer is cleared at the block's start: each point may start from its
/// predecessor's answer. The answers do not depend on the order or the threads.
pub(super) fn answer_points<T: Answer>(
    points: &[Point],
    threads: u32,
    out: &mut [T],
    answer: impl Fn(&mut Walker, &Point) -> T + Sync,
) -> crate::QueryStats {
    use std::sync::atomic::{AtomicU64, Ordering};
    let (volume_tests, triangle_tests) = (AtomicU64::new(0), AtomicU64::new(0));
    T::with_scratch(|s| {
        morton_order(points, &mut s.order, &mut s.keys);
        s.answers.clear();
        s.answers.resize(points.len(), T::default());
        let threads = threads::resolve(threads)
            .min(points.len().div_ceil(BLOCK))
            .max(1);
        let order = &s.order[..];
        let run = |(indices, answers): (&[u32], &mut [T])| {
            WALKER.with(|w| {
                let w = &mut *w.borrow_mut();
                w.previous = None;
                w.stack.volume_tests = 0;
                w.stack.triangle_tests = 0;
                for (&i, a) in indices.iter().zip(answers.iter_mut()) {
                    *a = answer(w, &points[i as usize]);
                }
                volume_tests.fetch_add(w.stack.volume_tests, Ordering::Relaxed);
                triangle_tests.fetch_add(w.stack.triangle_tests, Ordering::Relaxed);
            })
        };
        if threads <= 1 {
            run((order, &mut s.answers[..]));
        } else {
            let blocks: Vec<_> = order
                .chunks(BLOCK)
                .zip(s.answers.chunks_mut(BLOCK))
                .collect();
            threads::in_turns(Step::Points, threads, blocks, &run);
        }
        for (&i, a) in order.iter().zip(&s.answers) {
            out[i as usize] = *a;
        }
    });
    crate::QueryStats {
        bv_tests: volume_tests.into_inner(),
        triangle_tests: triangle_tests.into_inner(),
        ..crate::QueryStats::default()
    }
}
