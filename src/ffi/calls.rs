//! The shape every query entry point of the C ABI shares ([`Call`]): meshes (and poses) read and
//! checked, or a scene taken for the call, options read (NULL: the defaults), the query run into
//! the caller's buffer, its counters written unless NULL, all inside the guard that turns errors
//! and panics into a status.

use super::access::{read, write};
use super::boundary::{Failure, guard, write_unless_null};
use super::handles::{DvhMesh, DvhScene};
use super::results::Results;
use super::types::{DvhPose, DvhStatus};
use crate::{Mesh, Pose, Scene};

/// A mesh and its pose, as the C arguments give them.
pub(super) type Placed = (*const DvhMesh, *const DvhPose);

/// The pose behind a C pose (argument `name`), checked.
pub(super) fn pose(p: &DvhPose, name: &str) -> Result<Pose, Failure> {
    let r = &p.rotation;
    Pose::new(
        [[r[0], r[1], r[2]], [r[3], r[4], r[5]], [r[6], r[7], r[8]]],
        p.translation,
    )
    .map_err(|e| Failure::about(name, e))
}

/// A C options struct, read from a pointer that may be NULL (then the defaults).
pub(super) trait CallOptions {
    /// The Rust options it stands for.
    type Options;

    /// The options behind `o`, checked, or the defaults for NULL.
    ///
    /// # Safety
    /// `o` is NULL or readable.
    unsafe fn read_or_default(o: *const Self) -> Result<Self::Options, Failure>;
}

/// What a query entry point of the C ABI is given besides its meshes or scene: its name (for the
/// error messages), the options (NULL: the defaults), the caller's result buffer, and where the
/// counters go (NULL: nowhere).
pub(super) struct Call<O, H, C> {
    name: &'static str,
    options: *const O,
    out: *mut H,
    stats_out: *mut C,
}

impl<O: CallOptions, H: Results, C> Call<O, H, C> {
    /// The call `name` with its options, buffer and counters' destination.
    pub fn new(name: &'static str, options: *const O, out: *mut H, stats_out: *mut C) -> Self {
        Call {
            name,
            options,
            out,
            stats_out,
        }
    }

    /// Runs `query` (inside the caller's guard): the caller's buffer taken for the call, then
    /// `checks` (what the call checks of its other arguments, in that order), then the options
    /// read and checked; the counters `S` written as the C struct `C` unless NULL.
    ///
    /// # Safety
    /// `options` is NULL or readable, `out` NULL or a live buffer used by no other thread,
    /// `stats_out` NULL or writable.
    unsafe fn run<P, S>(
        self,
        checks: impl FnOnce() -> Result<P, Failure>,
        query: impl FnOnce(P, &O::Options, &mut H::Inner) -> crate::Result<S>,
    ) -> Result<(), Failure>
    where
        C: for<'s> From<&'s S>,
    {
        // SAFETY: NULL or a live buffer used by this thread only (contract).
        let mut out = unsafe { write(self.out, H::OUT, self.name)? };
        let checked = checks()?;
        // SAFETY: NULL or readable (contract).
        let o = unsafe { O::read_or_default(self.options) }?;
        let s = query(checked, &o, &mut out)?;
        // SAFETY: NULL or writable (contract).
        unsafe { write_unless_null(self.stats_out, C::from(&s)) };
        Ok(())
    }

    /// A query between two meshes, each with its pose (NULL: identity), read and checked.
    ///
    /// # Safety
    /// `a` and `b` are NULL or live meshes, the poses NULL or readable; otherwise as
    /// [`Call::run`].
    pub unsafe fn two_meshes<S>(
        self,
        (a, pose_a): Placed,
        (b, pose_b): Placed,
        query: impl FnOnce(
            &Mesh,
            Option<&Pose>,
            &Mesh,
            Option<&Pose>,
            &O::Options,
            &mut H::Inner,
        ) -> crate::Result<S>,
    ) -> DvhStatus
    where
        C: for<'s> From<&'s S>,
    {
        guard(|| {
            let call = self.name;
            // SAFETY: NULL or live, read-only during the call (contract).
            let (ma, mb) = unsafe { (read(a, "a", call)?, read(b, "b", call)?) };
            let poses = || {
                // SAFETY: NULL or readable (contract).
                let (pa, pb) = unsafe { (pose_a.as_ref(), pose_b.as_ref()) };
                let pa = pa.map(|p| pose(p, "pose_a")).transpose()?;
                Ok((pa, pb.map(|p| pose(p, "pose_b")).transpose()?))
            };
            let query = |(pa, pb): (Option<Pose>, Option<Pose>), o: &_, out: &mut _| {
                query(&ma, pa.as_ref(), &mb, pb.as_ref(), o, out)
            };
            // SAFETY: the caller's contract is this function's.
            unsafe { self.run(poses, query) }
        })
    }

    /// A query of one mesh against itself.
    ///
    /// # Safety
    /// `mesh` is NULL or a live mesh; otherwise as [`Call::run`].
    pub unsafe fn one_mesh<S>(
        self,
        mesh: *const DvhMesh,
        query: impl FnOnce(&Mesh, &O::Options, &mut H::Inner) -> crate::Result<S>,
    ) -> DvhStatus
    where
        C: for<'s> From<&'s S>,
    {
        guard(|| {
            // SAFETY: NULL or live, read-only during the call (contract).
            let m = unsafe { read(mesh, "mesh", self.name) }?;
            // SAFETY: the caller's contract is this function's.
            unsafe { self.run(|| Ok(()), |(), o, out| query(&m, o, out)) }
        })
    }

    /// A query of a whole scene, taken for the call alone (a query refits its objects).
    ///
    /// # Safety
    /// `scene` is NULL or a live scene; otherwise as [`Call::run`].
    pub unsafe fn whole_scene<S>(
        self,
        scene: *mut DvhScene,
        query: impl FnOnce(&mut Scene, &O::Options, &mut H::Inner) -> crate::Result<S>,
    ) -> DvhStatus
    where
        C: for<'s> From<&'s S>,
    {
        guard(|| {
            // SAFETY: NULL or a live scene (contract); BUSY while another call uses it.
            let mut s = unsafe { write(scene, "scene", self.name)? };
            // SAFETY: the caller's contract is this function's.
            unsafe { self.run(|| Ok(()), |(), o, out| query(&mut s, o, out)) }
        })
    }
}
