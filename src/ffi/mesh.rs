//! Meshes through the C ABI: create, refit, free, inspect.

use super::access::{MESH_TAG, Read, read, release, write};
use super::boundary::{Failure, choice, guard, guard_value, slice_from, times_three, try_box};
use super::handles::*;
use super::types::*;
use crate::geometry::predicates::Point;
use crate::{BuildOptions, LeftoverPolicy, Mesh, RadiusKind, TreeKind, VolumeKind};
use std::borrow::Cow;

/// The default build options, the fastest measured for meshes that deform: octree, box volumes
/// (`DVH_VOLUME_KIND_AABB`), layered radii (for sphere volumes), leftover triangles joined to
/// adjacent rings, refits on every core.
///
/// Thread safety: any thread, any time.
#[unsafe(no_mangle)]
pub extern "C" fn dvh_build_options_default() -> DvhBuildOptions {
    const DEFAULT: DvhBuildOptions = DvhBuildOptions {
        tree: DVH_TREE_KIND_OCTREE,
        radius: DVH_RADIUS_KIND_LAYERED,
        leftovers: DVH_LEFTOVER_POLICY_JOIN_ADJACENT,
        volume: DVH_VOLUME_KIND_AABB,
        refit_threads: 0,
    };
    guard_value(DEFAULT, || DEFAULT)
}

/// The build options measured fastest for rigid meshes, moved by poses and never refit: octree,
/// SBV spheres (`DVH_VOLUME_KIND_SBV`) with wrapped radii, leftover triangles joined to adjacent
/// rings.
///
/// Thread safety: any thread, any time.
#[unsafe(no_mangle)]
pub extern "C" fn dvh_build_options_rigid() -> DvhBuildOptions {
    const RIGID: DvhBuildOptions = DvhBuildOptions {
        tree: DVH_TREE_KIND_OCTREE,
        radius: DVH_RADIUS_KIND_WRAPPED,
        leftovers: DVH_LEFTOVER_POLICY_JOIN_ADJACENT,
        volume: DVH_VOLUME_KIND_SBV,
        refit_threads: 0,
    };
    guard_value(RIGID, || RIGID)
}

fn build_options(o: &DvhBuildOptions) -> Result<BuildOptions, Failure> {
    Ok(BuildOptions {
        tree: choice(
            "tree",
            "DVH_TREE_KIND",
            o.tree,
            &[
                (DVH_TREE_KIND_OCTREE, TreeKind::Octree),
                (DVH_TREE_KIND_BINARY, TreeKind::Binary),
            ],
        )?,
        radius: choice(
            "radius",
            "DVH_RADIUS_KIND",
            o.radius,
            &[
                (DVH_RADIUS_KIND_LAYERED, RadiusKind::Layered),
                (DVH_RADIUS_KIND_WRAPPED, RadiusKind::Wrapped),
            ],
        )?,
        leftovers: choice(
            "leftovers",
            "DVH_LEFTOVER_POLICY",
            o.leftovers,
            &[
                (
                    DVH_LEFTOVER_POLICY_JOIN_ADJACENT,
                    LeftoverPolicy::JoinAdjacent,
                ),
                (DVH_LEFTOVER_POLICY_EXTRA_RINGS, LeftoverPolicy::ExtraRings),
            ],
        )?,
        volume: choice(
            "volume",
            "DVH_VOLUME_KIND",
            o.volume,
            &[
                (DVH_VOLUME_KIND_DVH, VolumeKind::Dvh),
                (DVH_VOLUME_KIND_SBV, VolumeKind::Sbv),
                (DVH_VOLUME_KIND_AABB, VolumeKind::Aabb),
            ],
        )?,
        refit_threads: o.refit_threads,
    })
}

/// # Safety
/// `options` is NULL or points to a readable `DvhBuildOptions`.
unsafe fn read_build_options(options: *const DvhBuildOptions) -> Result<BuildOptions, Failure> {
    // SAFETY: NULL or valid for reads, per the caller's contract.
    match unsafe { options.as_ref() } {
        None => Ok(BuildOptions::default()),
        Some(o) => build_options(o),
    }
}

/// Reads `f32` positions at a byte stride, checked so that the span they cover fits in memory.
/// Reads are unaligned, so any stride of at least 12 bytes works.
pub(super) struct StridedF32 {
    base: *const u8,
    stride: usize,
}

impl StridedF32 {
    /// A reader of the positions at `base` (argument `name`, for messages).
    ///
    /// # Safety
    /// If `base` is non-NULL, `vertex_count` vertices of three `f32` each must be readable at
    /// `base + i * stride_bytes` for the duration of the use.
    pub(super) unsafe fn new(
        base: *const f32,
        name: &str,
        stride_bytes: usize,
        vertex_count: usize,
    ) -> Result<StridedF32, Failure> {
        if base.is_null() {
            return Err(Failure::null(name));
        }
        if stride_bytes < 12 {
            return Err(Failure::invalid(format!(
                "stride_bytes = {stride_bytes} is smaller than one vertex (3 floats, 12 bytes)"
            )));
        }
        let span = vertex_count
            .saturating_sub(1)
            .checked_mul(stride_bytes)
            .and_then(|s| s.checked_add(12));
        if span.is_none_or(|s| s > isize::MAX as usize) {
            return Err(Failure::invalid(format!(
                "{vertex_count} vertices at a stride of {stride_bytes} bytes do not fit in memory"
            )));
        }
        Ok(StridedF32 {
            base: base.cast(),
            stride: stride_bytes,
        })
    }

    #[inline]
    pub(super) fn get(&self, i: usize) -> Point {
        // SAFETY: `i` is below the vertex count this reader was checked for; the caller of `new`
        // guarantees three readable floats there. Unaligned reads accept any stride.
        unsafe {
            let p = self.base.add(i * self.stride).cast::<f32>();
            [0, 1, 2].map(|k| f64::from(p.add(k).read_unaligned()))
        }
    }
}

/// Refuses counts that `u32` indices cannot address, before any array is looked at (a slice
/// longer than the caller's array must never be formed).
fn check_counts(vertex_count: usize, triangle_count: usize) -> Result<(), Failure> {
    let limit = u32::MAX as usize;
    if vertex_count > limit {
        return Err(Failure::invalid(format!(
            "vertex_count = {vertex_count}: at most {limit} vertices can be addressed with u32 indices"
        )));
    }
    if triangle_count > limit {
        return Err(Failure::invalid(format!(
            "triangle_count = {triangle_count}: at most {limit} triangles can be addressed with u32 indices"
        )));
    }
    Ok(())
}

/// Writes a new mesh to `mesh_out`.
///
/// # Safety
/// `mesh_out` is NULL or writable.
unsafe fn publish(mesh: Mesh, mesh_out: *mut *mut DvhMesh) -> Result<(), Failure> {
    let ptr = try_box(DvhMesh(Body::new(MESH_TAG, mesh)))?;
    // SAFETY: checked non-NULL by the callers before any work; writable per the contract.
    unsafe { mesh_out.write(ptr) };
    Ok(())
}

/// Builds a mesh and its hierarchy from `double` positions.
///
/// `positions` holds `x, y, z` for each of `vertex_count` vertices; `triangles` holds three
/// vertex indices for each of `triangle_count` triangles. Degenerate triangles, repeated indices,
/// boundaries, non-manifold edges, several components and unreferenced vertices are accepted.
/// `options` may be NULL for the defaults. On success `*mesh_out` receives a new mesh, owned by
/// the caller and released with `dvh_mesh_free`; the input arrays are copied and may be freed.
/// On failure `*mesh_out` is not written.
///
/// Errors: NULL_ARGUMENT; INVALID_ARGUMENT (no triangles, counts beyond 2^32 - 1, misaligned
/// arrays, option values out of range); NON_FINITE_COORDINATE; INDEX_OUT_OF_RANGE;
/// OUT_OF_MEMORY.
///
/// Thread safety: any thread; the arrays must not be written during the call.
///
/// # Safety
/// `positions` must point to `3 * vertex_count` readable doubles, `triangles` to
/// `3 * triangle_count` readable indices, `options` be NULL or readable, `mesh_out` writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_mesh_create(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const DvhBuildOptions,
    mesh_out: *mut *mut DvhMesh,
) -> DvhStatus {
    // SAFETY: the caller's contract is this function's.
    unsafe {
        create_f64(
            positions,
            vertex_count,
            triangles,
            triangle_count,
            options,
            mesh_out,
        )
    }
}

/// `dvh_mesh_create` with 16-bit triangle indices, as engines keep the index buffers of small
/// meshes. The same contract, arguments and errors; the indices are widened to 32 bits.
///
/// # Safety
/// `positions` must point to `3 * vertex_count` readable doubles, `triangles` to
/// `3 * triangle_count` readable 16-bit indices, `options` be NULL or readable, `mesh_out`
/// writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_mesh_create_u16(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u16,
    triangle_count: usize,
    options: *const DvhBuildOptions,
    mesh_out: *mut *mut DvhMesh,
) -> DvhStatus {
    // SAFETY: the caller's contract is this function's.
    unsafe {
        create_f64(
            positions,
            vertex_count,
            triangles,
            triangle_count,
            options,
            mesh_out,
        )
    }
}

/// A triangle index type of the C ABI.
trait TriangleIndex: Copy {
    /// The indices as `u32`: borrowed when they are, widened into a fallibly allocated copy
    /// otherwise.
    fn widen(indices: &[Self]) -> Result<Cow<'_, [u32]>, Failure>;
}

impl TriangleIndex for u32 {
    fn widen(indices: &[u32]) -> Result<Cow<'_, [u32]>, Failure> {
        Ok(Cow::Borrowed(indices))
    }
}

impl TriangleIndex for u16 {
    fn widen(indices: &[u16]) -> Result<Cow<'_, [u32]>, Failure> {
        let mut wide: Vec<u32> = Vec::new();
        wide.try_reserve_exact(indices.len()).map_err(|_| {
            Failure::from(crate::Error::OutOfMemory {
                bytes: indices.len() * 4,
            })
        })?;
        wide.extend(indices.iter().map(|&i| u32::from(i)));
        Ok(Cow::Owned(wide))
    }
}

/// `dvh_mesh_create` for either index type.
///
/// # Safety
/// As `dvh_mesh_create`, with `triangles` pointing to `3 * triangle_count` readable `I`.
unsafe fn create_f64<I: TriangleIndex>(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const I,
    triangle_count: usize,
    options: *const DvhBuildOptions,
    mesh_out: *mut *mut DvhMesh,
) -> DvhStatus {
    guard(|| {
        if mesh_out.is_null() {
            return Err(Failure::null("mesh_out"));
        }
        check_counts(vertex_count, triangle_count)?;
        // SAFETY: readable per the contract; NULL, alignment and size are checked inside.
        let positions = unsafe {
            slice_from(
                positions,
                times_three(vertex_count, "vertex_count")?,
                "positions",
            )?
        };
        // SAFETY: as above.
        let triangles = unsafe {
            slice_from(
                triangles,
                times_three(triangle_count, "triangle_count")?,
                "triangles",
            )?
        };
        let triangles = I::widen(triangles)?;
        // SAFETY: NULL or readable per the contract.
        let options = unsafe { read_build_options(options)? };
        let mesh = Mesh::new(positions, &triangles, &options)?;
        // SAFETY: `mesh_out` checked non-NULL above.
        unsafe { publish(mesh, mesh_out) }
    })
}

/// Builds a mesh from `float` positions laid out at a byte stride, as engines keep vertex
/// buffers (position interleaved with normals, texture coordinates...).
///
/// Vertex `i`'s coordinates are the three floats at `positions + i * stride_bytes` (in bytes);
/// `stride_bytes` is at least 12, and no alignment is required. Everything else is as for
/// `dvh_mesh_create`; coordinates are widened to double exactly.
///
/// Errors, ownership, thread safety: as `dvh_mesh_create`, plus INVALID_ARGUMENT for a stride
/// below 12 bytes.
///
/// # Safety
/// For each `i < vertex_count`, 12 bytes at `positions + i * stride_bytes` must be readable;
/// `triangles` must point to `3 * triangle_count` readable indices, `options` be NULL or
/// readable, `mesh_out` writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_mesh_create_f32(
    positions: *const f32,
    stride_bytes: usize,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const DvhBuildOptions,
    mesh_out: *mut *mut DvhMesh,
) -> DvhStatus {
    guard(|| {
        if mesh_out.is_null() {
            return Err(Failure::null("mesh_out"));
        }
        check_counts(vertex_count, triangle_count)?;
        // SAFETY: readable per the contract; NULL, stride and span are checked inside.
        let reader =
            unsafe { StridedF32::new(positions, "positions", stride_bytes, vertex_count)? };
        // SAFETY: readable per the contract; NULL, alignment and size are checked inside.
        let triangles = unsafe {
            slice_from(
                triangles,
                times_three(triangle_count, "triangle_count")?,
                "triangles",
            )?
        };
        // SAFETY: NULL or readable per the contract.
        let options = unsafe { read_build_options(options)? };
        let mesh = Mesh::new_with(vertex_count, |i| reader.get(i), triangles, &options)?;
        // SAFETY: `mesh_out` checked non-NULL above.
        unsafe { publish(mesh, mesh_out) }
    })
}

/// Runs a refit (entry point `call`) with the mesh taken for change: refused while another call
/// uses it; if the refit panics the half-updated mesh stays refused.
pub(super) fn refit_guarded(
    mesh: *mut DvhMesh,
    vertex_count: usize,
    call: &str,
    refit: impl FnOnce(&mut Mesh) -> Result<(), Failure>,
) -> Result<(), Failure> {
    // SAFETY: NULL or a live mesh, per the contracts of the callers.
    let mut m = unsafe { write(mesh, "mesh", call)? };
    if vertex_count != m.vertex_count() {
        return Err(Failure::invalid(format!(
            "vertex_count = {vertex_count}, but the mesh has {} vertices",
            m.vertex_count()
        )));
    }
    refit(&mut m)
}

/// Refits a mesh to new `double` positions (`x, y, z` per vertex, the same vertex count as at
/// creation): radii are recomputed, centres move with their vertices. Allocates nothing.
///
/// Errors: NULL_ARGUMENT; INVALID_ARGUMENT (a different vertex count, misaligned array);
/// NON_FINITE_COORDINATE. On failure the mesh is exactly as it was.
///
/// Thread safety: needs exclusive access to `mesh`: no query or other call on it may run at the
/// same time. A refit that would is refused with BUSY, the mesh untouched.
///
/// # Safety
/// `mesh` is NULL or a live mesh from `dvh_mesh_create*`; `positions` points to
/// `3 * vertex_count` readable doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_mesh_refit(
    mesh: *mut DvhMesh,
    positions: *const f64,
    vertex_count: usize,
) -> DvhStatus {
    guard(|| {
        refit_guarded(mesh, vertex_count, "dvh_mesh_refit", |m| {
            // SAFETY: readable per the contract; NULL, alignment and size are checked inside.
            let positions = unsafe { slice_from(positions, vertex_count * 3, "positions")? };
            m.refit(positions)?;
            Ok(())
        })
    })
}

/// Refits a mesh to new `float` positions at a byte stride (see `dvh_mesh_create_f32`).
///
/// Errors, thread safety: as `dvh_mesh_refit`, plus INVALID_ARGUMENT for a stride below 12
/// bytes. On failure the mesh is exactly as it was. Allocates nothing.
///
/// # Safety
/// `mesh` is NULL or a live mesh; for each `i < vertex_count`, 12 bytes at
/// `positions + i * stride_bytes` are readable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_mesh_refit_f32(
    mesh: *mut DvhMesh,
    positions: *const f32,
    stride_bytes: usize,
    vertex_count: usize,
) -> DvhStatus {
    guard(|| {
        refit_guarded(mesh, vertex_count, "dvh_mesh_refit_f32", |m| {
            // SAFETY: readable per the contract; NULL, stride and span are checked inside.
            let reader =
                unsafe { StridedF32::new(positions, "positions", stride_bytes, vertex_count)? };
            m.refit_with(vertex_count, |i| reader.get(i))?;
            Ok(())
        })
    })
}

/// Releases a mesh. NULL is a no-op.
///
/// Thread safety: needs exclusive access to `mesh`; it must not be used afterwards. A mesh in
/// use by another call is not released (the last error message says so).
///
/// # Safety
/// `mesh` is NULL or a live mesh from `dvh_mesh_create*`, not freed before.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_mesh_free(mesh: *mut DvhMesh) {
    // SAFETY: allocated by `try_box` (the global allocator, `DvhMesh`'s layout) and owned by
    // the caller, per the contract.
    guard_value((), || unsafe { release(mesh, "mesh", "dvh_mesh_free") })
}

/// The mesh behind `mesh` for accessor `call`.
///
/// # Safety
/// `mesh` is NULL or a live mesh.
unsafe fn mesh_ref<'a>(mesh: *const DvhMesh, call: &str) -> Result<Read<'a, Mesh>, Failure> {
    // SAFETY: per the contract.
    unsafe { read(mesh, "mesh", call) }
}

/// Writes what `f` reads of a mesh to the out-parameter `out` (named `out_name`), for entry
/// point `call`.
///
/// # Safety
/// `mesh` is NULL or a live mesh; `out` is NULL or writable.
unsafe fn mesh_out<T>(
    mesh: *const DvhMesh,
    out: *mut T,
    out_name: &str,
    call: &str,
    f: impl FnOnce(&Mesh) -> T,
) -> DvhStatus {
    guard(|| {
        // SAFETY: per the contract.
        let m = unsafe { mesh_ref(mesh, call)? };
        if out.is_null() {
            return Err(Failure::null(out_name));
        }
        let value = f(&m);
        // SAFETY: non-NULL (checked) and writable per the contract.
        unsafe { out.write(value) };
        Ok(())
    })
}

/// Number of vertices of a mesh (0 for NULL).
///
/// Thread safety: may run alongside queries on the same mesh, not alongside a refit (0 then, and
/// the functions below that return a status return BUSY).
///
/// # Safety
/// `mesh` is NULL or a live mesh.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_mesh_vertex_count(mesh: *const DvhMesh) -> usize {
    // SAFETY: per the contract.
    guard_value(0, || {
        unsafe { mesh_ref(mesh, "dvh_mesh_vertex_count") }.map_or(0, |m| m.vertex_count())
    })
}

/// Number of triangles of a mesh (0 for NULL).
///
/// Thread safety: as `dvh_mesh_vertex_count`.
///
/// # Safety
/// `mesh` is NULL or a live mesh.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_mesh_triangle_count(mesh: *const DvhMesh) -> usize {
    // SAFETY: per the contract.
    guard_value(0, || {
        unsafe { mesh_ref(mesh, "dvh_mesh_triangle_count") }.map_or(0, |m| m.triangle_count())
    })
}

/// Number of nodes of a mesh's hierarchy, leaves included (0 for NULL). Node 0 is the root.
///
/// Thread safety: as `dvh_mesh_vertex_count`.
///
/// # Safety
/// `mesh` is NULL or a live mesh.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_mesh_node_count(mesh: *const DvhMesh) -> usize {
    // SAFETY: per the contract.
    guard_value(0, || {
        unsafe { mesh_ref(mesh, "dvh_mesh_node_count") }.map_or(0, |m| m.node_count())
    })
}

/// Writes the shape of a mesh's hierarchy to `*stats_out`.
///
/// Errors: NULL_ARGUMENT. Thread safety: as `dvh_mesh_vertex_count`.
///
/// # Safety
/// `mesh` is NULL or a live mesh; `stats_out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_mesh_tree_stats(
    mesh: *const DvhMesh,
    stats_out: *mut DvhTreeStats,
) -> DvhStatus {
    // SAFETY: the caller's contract is this function's.
    unsafe {
        mesh_out(mesh, stats_out, "stats_out", "dvh_mesh_tree_stats", |m| {
            DvhTreeStats::from(&m.tree_stats())
        })
    }
}

/// Writes the counters of a mesh's last refit (or of its build) to `*stats_out`.
///
/// Errors: NULL_ARGUMENT. Thread safety: as `dvh_mesh_vertex_count`.
///
/// # Safety
/// `mesh` is NULL or a live mesh; `stats_out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_mesh_last_refit_stats(
    mesh: *const DvhMesh,
    stats_out: *mut DvhRefitStats,
) -> DvhStatus {
    // SAFETY: the caller's contract is this function's.
    unsafe {
        mesh_out(
            mesh,
            stats_out,
            "stats_out",
            "dvh_mesh_last_refit_stats",
            |m| DvhRefitStats::from(&m.last_refit()),
        )
    }
}

/// The triangles below a node, to expand the node pairs of the coarse query modes: on success
/// `*triangles_out` points to `*count_out` triangle indices, owned by the mesh and valid until it
/// is freed (refits do not change them).
///
/// Errors: NULL_ARGUMENT; INVALID_ARGUMENT for a node index not below `dvh_mesh_node_count`.
///
/// Thread safety: as `dvh_mesh_vertex_count`.
///
/// # Safety
/// `mesh` is NULL or a live mesh; the out-pointers are NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_mesh_node_triangles(
    mesh: *const DvhMesh,
    node: u32,
    triangles_out: *mut *const u32,
    count_out: *mut usize,
) -> DvhStatus {
    guard(|| {
        // SAFETY: per the contract.
        let m = unsafe { mesh_ref(mesh, "dvh_mesh_node_triangles")? };
        if triangles_out.is_null() {
            return Err(Failure::null("triangles_out"));
        }
        if count_out.is_null() {
            return Err(Failure::null("count_out"));
        }
        if node as usize >= m.node_count() {
            return Err(Failure::invalid(format!(
                "node {node} is out of range (the mesh has {} nodes)",
                m.node_count()
            )));
        }
        let tris = m.node_triangles(node);
        // SAFETY: both non-NULL (checked) and writable per the contract.
        unsafe {
            triangles_out.write(tris.as_ptr());
            count_out.write(tris.len());
        }
        Ok(())
    })
}

/// Checks every invariant of a mesh's hierarchy (slow: for tests and bug reports).
///
/// Errors: NULL_ARGUMENT; INVARIANT_BROKEN, with the broken invariant in the last error message
/// (a bug in dvh). Thread safety: as `dvh_mesh_vertex_count`.
///
/// # Safety
/// `mesh` is NULL or a live mesh.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_mesh_validate(mesh: *const DvhMesh) -> DvhStatus {
    guard(|| {
        // SAFETY: per the contract.
        let m = unsafe { mesh_ref(mesh, "dvh_mesh_validate")? };
        m.validate()
            .map_err(|e| Failure::new(DVH_STATUS_INVARIANT_BROKEN, e.to_string()))
    })
}
