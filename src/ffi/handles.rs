//! The opaque handles of the C ABI: what each holds (its tag, its access state, the Rust object)
//! and which kind of object each is.

use super::access::{
    Access, CONTACTS_TAG, CURVES_TAG, Handle, IMPACTS_TAG, MESH_TAG, NEAR_PAIRS_TAG, PAIRS_TAG,
    SCENE_IMPACTS_TAG, SCENE_NEAR_PAIRS_TAG, SCENE_TAG, Tag,
};
use std::cell::UnsafeCell;

/// What every handle holds, in this order. The tag comes first, at offset 0 of every kind of
/// handle (checked below), so reading it through a pointer to a handle of another kind, or to
/// any other object of at least 8 bytes, stays inside that object's memory.
#[repr(C)]
pub(crate) struct Body<T> {
    pub(crate) tag: Tag,
    /// Queries read a mesh and write a result buffer, refits and scene calls change theirs.
    pub(crate) access: Access,
    pub(crate) inner: UnsafeCell<T>,
}

impl<T> Body<T> {
    /// A live handle's body: `tag` says its kind, `inner` is the object.
    pub(crate) fn new(tag: u64, inner: T) -> Body<T> {
        Body {
            tag: Tag::new(tag),
            access: Access::default(),
            inner: UnsafeCell::new(inner),
        }
    }
}

/// A mesh with its hierarchy: topology, current positions, 1-rings, spheres. Opaque; created by
/// `dvh_mesh_create`, released by `dvh_mesh_free`.
pub struct DvhMesh(pub(crate) Body<crate::Mesh>);

/// A reusable result buffer with the scratch space queries need. Opaque; created by
/// `dvh_pairs_new`, released by `dvh_pairs_free`. Use one per thread.
pub struct DvhPairs(pub(crate) Body<crate::Pairs>);

/// A set of objects (rigid or deformable, sharing meshes) queried together. Opaque; created by
/// `dvh_scene_create`, released by `dvh_scene_free`.
pub struct DvhScene(pub(crate) Body<crate::Scene>);

/// A reusable result buffer for `dvh_scene_collide`. Opaque; created by `dvh_contacts_new`,
/// released by `dvh_contacts_free`. Use one per thread.
pub struct DvhContacts(pub(crate) Body<crate::Contacts>);

/// A reusable result buffer for the closest-point queries. Opaque; created by
/// `dvh_near_pairs_new`, released by `dvh_near_pairs_free`. Use one per thread.
pub struct DvhNearPairs(pub(crate) Body<crate::NearPairs>);

/// A reusable result buffer for the continuous queries. Opaque; created by `dvh_impacts_new`,
/// released by `dvh_impacts_free`. Use one per thread.
pub struct DvhImpacts(pub(crate) Body<crate::Impacts>);

/// A reusable result buffer for `dvh_scene_continuous_collide`, with the scratch space of the
/// threads that fill it. Opaque; created by `dvh_scene_impacts_new`, released by
/// `dvh_scene_impacts_free`. Use one per thread.
pub struct DvhSceneImpacts(pub(crate) Body<crate::SceneImpacts>);

/// A reusable result buffer for `dvh_scene_nearest_features`, with the scratch space of the
/// threads that fill it. Opaque; created by `dvh_scene_near_pairs_new`, released by
/// `dvh_scene_near_pairs_free`. Use one per thread.
pub struct DvhSceneNearPairs(pub(crate) Body<crate::SceneNearPairs>);

/// A reusable result buffer for the intersection curves: segments curve by curve, the curves,
/// the degenerate pairs, and the scratch space of the queries. Opaque; created by
/// `dvh_curves_new`, released by `dvh_curves_free`. Use one per thread.
pub struct DvhCurves(pub(crate) Body<crate::Curves>);

// The tag check reads the first 8 bytes of whatever a handle pointer points to: every handle
// keeps its tag there.
const _: () = {
    use std::mem::offset_of;
    assert!(offset_of!(DvhMesh, 0.tag) == 0);
    assert!(offset_of!(DvhPairs, 0.tag) == 0);
    assert!(offset_of!(DvhScene, 0.tag) == 0);
    assert!(offset_of!(DvhContacts, 0.tag) == 0);
    assert!(offset_of!(DvhNearPairs, 0.tag) == 0);
    assert!(offset_of!(DvhImpacts, 0.tag) == 0);
    assert!(offset_of!(DvhSceneImpacts, 0.tag) == 0);
    assert!(offset_of!(DvhSceneNearPairs, 0.tag) == 0);
    assert!(offset_of!(DvhCurves, 0.tag) == 0);
};

macro_rules! handle {
    ($handle:ty, $inner:ty, $tag:expr) => {
        impl Handle for $handle {
            type Inner = $inner;
            const TAG: u64 = $tag;
            fn parts(&self) -> (&Tag, &Access, &UnsafeCell<$inner>) {
                (&self.0.tag, &self.0.access, &self.0.inner)
            }
        }
    };
}

handle!(DvhMesh, crate::Mesh, MESH_TAG);
handle!(DvhPairs, crate::Pairs, PAIRS_TAG);
handle!(DvhScene, crate::Scene, SCENE_TAG);
handle!(DvhContacts, crate::Contacts, CONTACTS_TAG);
handle!(DvhImpacts, crate::Impacts, IMPACTS_TAG);
handle!(DvhNearPairs, crate::NearPairs, NEAR_PAIRS_TAG);
handle!(DvhSceneImpacts, crate::SceneImpacts, SCENE_IMPACTS_TAG);
handle!(
    DvhSceneNearPairs,
    crate::SceneNearPairs,
    SCENE_NEAR_PAIRS_TAG
);
handle!(DvhCurves, crate::Curves, CURVES_TAG);
