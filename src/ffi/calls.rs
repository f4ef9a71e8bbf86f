//! The shape every query entry point of the C ABI shares: meshes (and poses) read and checked,
//! or a scene taken for the call, options read (NULL: the defaults), the query run into the
//! caller's buffer, its counters written unless NULL, all inside the guard that turns errors and
//! panics into a status.

use super::access::{Handle, read, write};
use super::boundary::{Failure, guard, write_unless_null};
use super::handles::{DvhMesh, DvhScene};
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

/// A query between two meshes from C (entry point `call`): the meshes, poses and options read
/// and checked, `query` run into `out` (argument `out_name`), its counters `S` written to
/// `stats_out` as the C struct `C` unless NULL.
///
/// # Safety
/// `a` and `b` are NULL or live meshes, the poses NULL or readable, `options` NULL or readable,
/// `out` NULL or a live buffer used by no other thread, `stats_out` NULL or writable.
#[allow(clippy::too_many_arguments)]
pub(super) unsafe fn two_meshes<H: Handle, O: CallOptions, S, C: for<'s> From<&'s S>>(
    (a, pose_a): Placed,
    (b, pose_b): Placed,
    options: *const O,
    out: *mut H,
    out_name: &str,
    stats_out: *mut C,
    call: &str,
    query: impl FnOnce(
        &Mesh,
        Option<&Pose>,
        &Mesh,
        Option<&Pose>,
        &O::Options,
        &mut H::Inner,
    ) -> crate::Result<S>,
) -> DvhStatus {
    guard(|| {
        // SAFETY: NULL or live, read-only during the call (contract).
        let (ma, mb) = unsafe { (read(a, "a", call)?, read(b, "b", call)?) };
        // SAFETY: NULL or a live buffer used by this thread only (contract).
        let mut out = unsafe { write(out, out_name, call)? };
        // SAFETY: NULL or readable (contract).
        let (pa, pb) = unsafe { (pose_a.as_ref(), pose_b.as_ref()) };
        let pa = pa.map(|p| pose(p, "pose_a")).transpose()?;
        let pb = pb.map(|p| pose(p, "pose_b")).transpose()?;
        // SAFETY: NULL or readable (contract).
        let o = unsafe { O::read_or_default(options) }?;
        let s = query(&ma, pa.as_ref(), &mb, pb.as_ref(), &o, &mut out)?;
        // SAFETY: NULL or writable (contract).
        unsafe { write_unless_null(stats_out, C::from(&s)) };
        Ok(())
    })
}

/// A query of one mesh against itself from C (entry point `call`), as [`two_meshes`].
///
/// # Safety
/// `mesh` is NULL or a live mesh; otherwise as [`two_meshes`].
pub(super) unsafe fn one_mesh<H: Handle, O: CallOptions, S, C: for<'s> From<&'s S>>(
    mesh: *const DvhMesh,
    options: *const O,
    out: *mut H,
    out_name: &str,
    stats_out: *mut C,
    call: &str,
    query: impl FnOnce(&Mesh, &O::Options, &mut H::Inner) -> crate::Result<S>,
) -> DvhStatus {
    guard(|| {
        // SAFETY: NULL or live, read-only during the call (contract).
        let m = unsafe { read(mesh, "mesh", call) }?;
        // SAFETY: NULL or a live buffer used by this thread only (contract).
        let mut out = unsafe { write(out, out_name, call)? };
        // SAFETY: NULL or readable (contract).
        let o = unsafe { O::read_or_default(options) }?;
        let s = query(&m, &o, &mut out)?;
        // SAFETY: NULL or writable (contract).
        unsafe { write_unless_null(stats_out, C::from(&s)) };
        Ok(())
    })
}

/// A query of a whole scene from C (entry point `call`): the scene taken for the call alone (a
/// query refits its objects), the options read and checked, `query` run into `out` (argument
/// `out_name`), its counters `S` written to `stats_out` as the C struct `C` unless NULL.
///
/// # Safety
/// `scene` is NULL or a live scene; otherwise as [`two_meshes`].
pub(super) unsafe fn whole_scene<H: Handle, O: CallOptions, S, C: for<'s> From<&'s S>>(
    scene: *mut DvhScene,
    options: *const O,
    out: *mut H,
    out_name: &str,
    stats_out: *mut C,
    call: &str,
    query: impl FnOnce(&mut Scene, &O::Options, &mut H::Inner) -> crate::Result<S>,
) -> DvhStatus {
    guard(|| {
        // SAFETY: NULL or a live scene (contract); BUSY while another call uses it.
        let mut s = unsafe { write(scene, "scene", call)? };
        // SAFETY: NULL or a live buffer used by this thread only (contract).
        let mut out = unsafe { write(out, out_name, call)? };
        // SAFETY: NULL or readable (contract).
        let o = unsafe { O::read_or_default(options) }?;
        let st = query(&mut s, &o, &mut out)?;
        // SAFETY: NULL or writable (contract).
        unsafe { write_unless_null(stats_out, C::from(&st)) };
        Ok(())
    })
}
