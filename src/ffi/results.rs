//! The C ABI's result buffers (`DvhPairs`, `DvhContacts`, `DvhImpacts`, `DvhNearPairs`,
//! `DvhSceneImpacts`, `DvhSceneNearPairs`) and the family of calls on them (`_new`, `_len`,
//! `_data`, `_free`, and `_kind` for the buffers whose indices may be nodes), written once for
//! all. The entry points themselves are one-line wrappers in `query.rs`, `scene.rs`, `ccd.rs` and
//! `nearest.rs`, written out because cbindgen reads the sources without expanding macros, and
//! each carries its own documentation into the header.

use super::access::{Handle, Read, read, release};
use super::boundary::{guard_value, set_last_error, try_box};
use super::handles::{
    Body, DvhContacts, DvhCurves, DvhImpacts, DvhNearPairs, DvhPairs, DvhSceneImpacts,
    DvhSceneNearPairs,
};
use super::types::{
    DVH_PAIR_KIND_NODES, DVH_PAIR_KIND_TRIANGLES, DvhContact, DvhCurveSegment, DvhImpact,
    DvhNearPair, DvhPair, DvhPairKind, DvhSceneImpact, DvhSceneNearPair,
};
use crate::{Contacts, Curves, Impacts, NearPairs, PairKind, Pairs, SceneImpacts, SceneNearPairs};

/// A result buffer of the C ABI.
pub(crate) trait Results: Handle + Sized {
    /// One result, as C reads it: the same layout as the library's own item.
    type Item;
    /// The name of the buffer's argument in the accessors, for messages.
    const ARGUMENT: &'static str;
    /// The name of the buffer's argument in the queries that write it (`ARGUMENT` + `_out`).
    const OUT: &'static str;
    /// A new, empty buffer.
    fn empty() -> Self;
    /// How many results `inner` holds.
    fn len(inner: &Self::Inner) -> usize;
    /// The first of them.
    fn data(inner: &Self::Inner) -> *const Self::Item;
}

/// A result buffer whose indices are triangles or nodes, as the query's mode says (`_kind`).
/// Impacts and stencils say their kind one by one.
pub(crate) trait Kinded: Results {
    /// What the results' indices refer to.
    fn kind(inner: &Self::Inner) -> PairKind;
}

impl Results for DvhPairs {
    type Item = DvhPair;
    const ARGUMENT: &'static str = "pairs";
    const OUT: &'static str = "pairs_out";

    fn empty() -> DvhPairs {
        DvhPairs(Body::new(Self::TAG, Pairs::new()))
    }

    fn len(inner: &Pairs) -> usize {
        inner.len()
    }

    fn data(inner: &Pairs) -> *const DvhPair {
        // `DvhPair` has `Pair`'s layout (checked in `types`).
        inner.as_slice().as_ptr().cast()
    }
}

impl Kinded for DvhPairs {
    fn kind(inner: &Pairs) -> PairKind {
        inner.kind()
    }
}

impl Results for DvhCurves {
    type Item = DvhCurveSegment;
    const ARGUMENT: &'static str = "curves";
    const OUT: &'static str = "curves_out";

    fn empty() -> DvhCurves {
        DvhCurves(Body::new(Self::TAG, Curves::new()))
    }

    fn len(inner: &Curves) -> usize {
        inner.len()
    }

    fn data(inner: &Curves) -> *const DvhCurveSegment {
        // `DvhCurveSegment` has `CurveSegment`'s layout (checked in `types`).
        inner.segments().as_ptr().cast()
    }
}

impl Results for DvhContacts {
    type Item = DvhContact;
    const ARGUMENT: &'static str = "contacts";
    const OUT: &'static str = "contacts_out";

    fn empty() -> DvhContacts {
        DvhContacts(Body::new(Self::TAG, Contacts::new()))
    }

    fn len(inner: &Contacts) -> usize {
        inner.len()
    }

    fn data(inner: &Contacts) -> *const DvhContact {
        // `DvhContact` has `Contact`'s layout (checked in `types`).
        inner.as_slice().as_ptr().cast()
    }
}

impl Kinded for DvhContacts {
    fn kind(inner: &Contacts) -> PairKind {
        inner.kind()
    }
}

impl Results for DvhImpacts {
    type Item = DvhImpact;
    const ARGUMENT: &'static str = "impacts";
    const OUT: &'static str = "impacts_out";

    fn empty() -> DvhImpacts {
        DvhImpacts(Body::new(Self::TAG, Impacts::new()))
    }

    fn len(inner: &Impacts) -> usize {
        inner.len()
    }

    fn data(inner: &Impacts) -> *const DvhImpact {
        // `DvhImpact` has `Impact`'s layout (checked in `types`).
        inner.as_slice().as_ptr().cast()
    }
}

impl Results for DvhNearPairs {
    type Item = DvhNearPair;
    const ARGUMENT: &'static str = "pairs";
    const OUT: &'static str = "pairs_out";

    fn empty() -> DvhNearPairs {
        DvhNearPairs(Body::new(Self::TAG, NearPairs::new()))
    }

    fn len(inner: &NearPairs) -> usize {
        inner.len()
    }

    fn data(inner: &NearPairs) -> *const DvhNearPair {
        // `DvhNearPair` has `NearPair`'s layout (checked in `types`).
        inner.as_slice().as_ptr().cast()
    }
}

impl Results for DvhSceneImpacts {
    type Item = DvhSceneImpact;
    const ARGUMENT: &'static str = "impacts";
    const OUT: &'static str = "impacts_out";

    fn empty() -> DvhSceneImpacts {
        DvhSceneImpacts(Body::new(Self::TAG, SceneImpacts::new()))
    }

    fn len(inner: &SceneImpacts) -> usize {
        inner.len()
    }

    fn data(inner: &SceneImpacts) -> *const DvhSceneImpact {
        // `DvhSceneImpact` has `SceneImpact`'s layout (checked in `types`).
        inner.as_slice().as_ptr().cast()
    }
}

impl Results for DvhSceneNearPairs {
    type Item = DvhSceneNearPair;
    const ARGUMENT: &'static str = "pairs";
    const OUT: &'static str = "pairs_out";

    fn empty() -> DvhSceneNearPairs {
        DvhSceneNearPairs(Body::new(Self::TAG, SceneNearPairs::new()))
    }

    fn len(inner: &SceneNearPairs) -> usize {
        inner.len()
    }

    fn data(inner: &SceneNearPairs) -> *const DvhSceneNearPair {
        // `DvhSceneNearPair` has `SceneNearPair`'s layout (checked in `types`).
        inner.as_slice().as_ptr().cast()
    }
}

/// `dvh_*_new`: a new, empty buffer owned by the caller, or NULL when memory ran out.
pub(super) fn new<R: Results>() -> *mut R {
    guard_value(std::ptr::null_mut(), || match try_box(R::empty()) {
        Ok(p) => p,
        Err(f) => {
            set_last_error(&f.message);
            std::ptr::null_mut()
        }
    })
}

/// The contents of buffer `r` for accessor `call`, or `None` (NULL, not a live buffer, being
/// written).
///
/// # Safety
/// `r` is NULL or a live buffer.
unsafe fn contents<'a, R: Results + 'a>(r: *const R, call: &str) -> Option<Read<'a, R::Inner>> {
    // SAFETY: per the contract.
    unsafe { read(r, R::ARGUMENT, call) }.ok()
}

/// `dvh_*_len`-like accessors of other parts of a buffer (entry point `call`): `part` of its
/// contents, `fallback` when there is no buffer to read.
///
/// # Safety
/// `r` is NULL or a live buffer.
pub(super) unsafe fn part<R: Results, T: Copy>(
    r: *const R,
    call: &str,
    fallback: T,
    part: impl FnOnce(&R::Inner) -> T,
) -> T {
    // SAFETY: per the contract.
    guard_value(fallback, || {
        unsafe { contents(r, call) }.map_or(fallback, |c| part(&c))
    })
}

/// `dvh_*_len` (entry point `call`): the number of results, 0 when there is no buffer to read.
///
/// # Safety
/// `r` is NULL or a live buffer.
pub(super) unsafe fn len<R: Results>(r: *const R, call: &str) -> usize {
    // SAFETY: per the contract.
    guard_value(0, || unsafe { contents(r, call) }.map_or(0, |c| R::len(&c)))
}

/// `dvh_*_data`: the first result, NULL when there are none or no buffer to read.
///
/// # Safety
/// `r` is NULL or a live buffer.
pub(super) unsafe fn data<R: Results>(r: *const R, call: &str) -> *const R::Item {
    guard_value(std::ptr::null(), || {
        // SAFETY: per the contract.
        match unsafe { contents(r, call) } {
            Some(c) if R::len(&c) > 0 => R::data(&c),
            _ => std::ptr::null(),
        }
    })
}

/// `dvh_*_kind`: what the results' indices refer to, triangles when there is no buffer to read.
///
/// # Safety
/// `r` is NULL or a live buffer.
pub(super) unsafe fn kind<R: Kinded>(r: *const R, call: &str) -> DvhPairKind {
    guard_value(DVH_PAIR_KIND_TRIANGLES, || {
        // SAFETY: per the contract.
        match unsafe { contents(r, call) }.map(|c| R::kind(&c)) {
            Some(PairKind::Nodes) => DVH_PAIR_KIND_NODES,
            _ => DVH_PAIR_KIND_TRIANGLES,
        }
    })
}

/// `dvh_*_free`: releases the buffer; NULL is a no-op.
///
/// # Safety
/// `r` is NULL or a live buffer from `new`, owned by the caller, not freed before.
pub(super) unsafe fn free<R: Results>(r: *mut R, call: &str) {
    // SAFETY: allocated by `try_box` in `new` and owned by the caller (contract).
    guard_value((), || unsafe { release(r, R::ARGUMENT, call) })
}
