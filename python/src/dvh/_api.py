"""The Python layer over dvh's C ABI (``include/dvh.h``), through cffi.

Arrays are checked here, before any call, so that a wrong shape or dtype is a ``ValueError`` or
``TypeError`` naming the argument; what only the library can check (an index out of range, a
NaN, a non-rigid pose) comes back as :class:`DvhError` with the library's message. cffi releases
the GIL for the duration of every C call, so refits and queries on other threads run alongside.
"""

from __future__ import annotations

import threading
import weakref
from dataclasses import dataclass
from typing import Literal, Optional, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

from ._dvh import ffi, lib

__all__ = [
    "DvhError",
    "Mesh",
    "Scene",
    "QueryStats",
    "SceneStats",
    "TreeStats",
    "RefitStats",
    "CONTACT_DTYPE",
    "CcdStats",
    "IMPACT_DTYPE",
    "IMPACT_VERTEX_FACE",
    "IMPACT_FACE_VERTEX",
    "IMPACT_EDGE_EDGE",
    "collide",
    "self_collide",
    "proximity",
    "self_proximity",
    "triangles_intersect",
    "continuous_collide",
    "self_continuous_collide",
    "ccd_vertex_face",
    "ccd_edge_edge",
    "NEAR_PAIR_DTYPE",
    "FEATURE_VERTEX_0",
    "FEATURE_VERTEX_1",
    "FEATURE_VERTEX_2",
    "FEATURE_EDGE_01",
    "FEATURE_EDGE_12",
    "FEATURE_EDGE_20",
    "FEATURE_INTERIOR",
    "nearest_features",
    "self_nearest_features",
    "version",
]

_VOLUMES = {
    "aabb": lib.DVH_VOLUME_KIND_AABB,
    "dvh": lib.DVH_VOLUME_KIND_DVH,
    "sbv": lib.DVH_VOLUME_KIND_SBV,
}
_TREES = {"octree": lib.DVH_TREE_KIND_OCTREE, "binary": lib.DVH_TREE_KIND_BINARY}
_RADII = {"layered": lib.DVH_RADIUS_KIND_LAYERED, "wrapped": lib.DVH_RADIUS_KIND_WRAPPED}
_LEFTOVERS = {
    "join_adjacent": lib.DVH_LEFTOVER_POLICY_JOIN_ADJACENT,
    "extra_rings": lib.DVH_LEFTOVER_POLICY_EXTRA_RINGS,
}
_MODES = {
    "triangles": lib.DVH_QUERY_MODE_TRIANGLES,
    "first_hit": lib.DVH_QUERY_MODE_FIRST_HIT,
    "leaves": lib.DVH_QUERY_MODE_LEAVES,
    "depth": lib.DVH_QUERY_MODE_DEPTH,
    "budget": lib.DVH_QUERY_MODE_BUDGET,
}
_U32_MAX = 0xFFFF_FFFF
_U64_MAX = 0xFFFF_FFFF_FFFF_FFFF

#: The dtype of :meth:`Scene.collide`'s contacts: two object ids (the lower first) and a
#: triangle (or node) index in each object's mesh.
CONTACT_DTYPE = np.dtype(
    [("object_a", "<u4"), ("object_b", "<u4"), ("a", "<u4"), ("b", "<u4")]
)

_CCD_MODES = {
    "exact": lib.DVH_CCD_MODE_EXACT,
    "conservative": lib.DVH_CCD_MODE_CONSERVATIVE,
}

#: :data:`IMPACT_DTYPE`'s ``kind``: a vertex of the first mesh (``a0``) against a triangle of the
#: second (``b0``).
IMPACT_VERTEX_FACE: int = int(lib.DVH_IMPACT_KIND_VERTEX_FACE)
#: :data:`IMPACT_DTYPE`'s ``kind``: a triangle of the first mesh (``a0``) against a vertex of the
#: second (``b0``); never reported by :func:`self_continuous_collide`.
IMPACT_FACE_VERTEX: int = int(lib.DVH_IMPACT_KIND_FACE_VERTEX)
#: :data:`IMPACT_DTYPE`'s ``kind``: an edge ``(a0, a1)``, ``a0 < a1``, of the first mesh against an
#: edge ``(b0, b1)``, ``b0 < b1``, of the second (in self queries ``(a0, a1) < (b0, b1)``).
IMPACT_EDGE_EDGE: int = int(lib.DVH_IMPACT_KIND_EDGE_EDGE)

#: The dtype of :func:`continuous_collide`'s impacts, the layout of the C ``DvhImpact``: the
#: ``kind`` (an ``IMPACT_*`` constant), the primitives ``a0, a1`` of the first mesh and ``b0, b1``
#: of the second (a vertex or triangle in ``a0``/``b0`` with ``a1``/``b1`` 0, or an edge's lower
#: and higher vertex), and ``toi``, the earliest time of contact in ``[0, 1]``.
#: Its offsets and size (32 bytes, the padding after ``b1`` included) are the C struct's.
IMPACT_DTYPE = np.dtype(
    {
        "names": ["kind", "a0", "a1", "b0", "b1", "toi"],
        "formats": ["=u4", "=u4", "=u4", "=u4", "=u4", "=f8"],
        "offsets": [ffi.offsetof("DvhImpact", f) for f in ("kind", "a0", "a1", "b0", "b1", "toi")],
        "itemsize": ffi.sizeof("DvhImpact"),
    }
)


class DvhError(Exception):
    """A call the library refused: ``status`` is the ``DVH_STATUS_*`` code, ``name`` its name and
    ``message`` the library's explanation (which argument, index or value was wrong). The objects
    involved are as they were before the call."""

    def __init__(self, status: int, message: str):
        self.status = int(status)
        self.name = ffi.string(lib.dvh_status_name(status)).decode()
        self.message = message
        super().__init__(f"{self.name}: {message}")


def _raise_for(status: int) -> None:
    if status == lib.DVH_STATUS_OK:
        return
    n = lib.dvh_last_error_message(ffi.NULL, 0)
    buf = ffi.new("char[]", n + 1)
    lib.dvh_last_error_message(buf, n + 1)
    message = ffi.string(buf).decode("utf-8", "replace")
    if status == lib.DVH_STATUS_OUT_OF_MEMORY:
        raise MemoryError(message)
    raise DvhError(status, message)


def version() -> str:
    """The library's version, such as ``"0.3.0"``."""
    return ffi.string(lib.dvh_version()).decode()


def _choice(name: str, value: str, table: dict) -> int:
    if not isinstance(value, str):
        raise TypeError(f"{name} must be a string, one of {sorted(table)}; got {value!r}")
    try:
        return table[value]
    except KeyError:
        raise ValueError(f"{name} must be one of {sorted(table)}; got {value!r}") from None


def _count(name: str, value, limit: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an integer; got {value!r}")
    value = int(value)
    if not 0 <= value <= limit:
        raise ValueError(f"{name} must be in 0..={limit}; got {value}")
    return value


# ---------------------------------------------------------------------------------------------
# Arrays


def _positions(name: str, positions, expected: Optional[int] = None):
    """A cffi pointer to `positions` and what the C call needs to read it, with the array kept
    alive by the caller. float64 arrays are read in place when C-contiguous (other layouts are
    copied once); float32 arrays in place whenever their rows are evenly spaced, as the C ABI
    takes a row stride for them."""
    arr = np.asarray(positions)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise ValueError(f"{name} must have shape (n, 3); got {arr.shape}")
    if expected is not None and arr.shape[0] != expected:
        raise ValueError(f"{name} has {arr.shape[0]} vertices; the mesh has {expected}")
    if arr.dtype == np.float32:
        if arr.strides[1] != 4 or arr.strides[0] < 12 or arr.strides[0] % 4:
            arr = np.ascontiguousarray(arr)
        ptr = ffi.cast("const float *", arr.ctypes.data)
        return arr, ptr, arr.strides[0] if arr.shape[0] > 0 else 12, True
    arr = _float64(name, arr)
    return arr, ffi.cast("const double *", arr.ctypes.data), 24, False


def _float64(name: str, arr: np.ndarray) -> np.ndarray:
    """`arr` as a C-contiguous float64 array (itself when it is one already). Integers, float16
    and float32 convert exactly; long double would round, so it is refused."""
    kind = arr.dtype.kind
    if kind not in "fiu" or (kind == "f" and arr.dtype.itemsize > 8):
        raise TypeError(f"{name} must hold float64 or float32 values; got dtype {arr.dtype}")
    return np.ascontiguousarray(arr, dtype=np.float64)


def _positions64(name: str, positions, expected: int):
    """`positions` as a C-contiguous ``(expected, 3)`` float64 array and a cffi pointer to it,
    for the calls that take doubles only (float32 is widened, exactly)."""
    arr = np.asarray(positions)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise ValueError(f"{name} must have shape (n, 3); got {arr.shape}")
    if arr.shape[0] != expected:
        raise ValueError(f"{name} has {arr.shape[0]} vertices; the mesh has {expected}")
    arr = _float64(name, arr)
    return arr, ffi.cast("const double *", arr.ctypes.data)


def _triangles(triangles):
    """`triangles` as a C-contiguous (m, 3) array of uint32 or uint16 (read in place when it is
    one already), after checking that no index is negative."""
    arr = np.asarray(triangles)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise ValueError(f"triangles must have shape (m, 3); got {arr.shape}")
    if arr.dtype.kind not in "iu":
        raise TypeError(f"triangles must hold integers; got dtype {arr.dtype}")
    if arr.dtype in (np.uint32, np.uint16):
        return np.ascontiguousarray(arr)
    if arr.size:
        low, high = int(arr.min()), int(arr.max())
        if low < 0:
            t = int(np.argwhere(arr < 0)[0][0])
            raise ValueError(f"triangle {t} has a negative vertex index: {arr[t].tolist()}")
        if high > _U32_MAX:
            t = int(np.argwhere(arr > _U32_MAX)[0][0])
            raise ValueError(f"triangle {t} has a vertex index above 2**32 - 1: {arr[t].tolist()}")
    return np.ascontiguousarray(arr, dtype=np.uint32)


def _pose(name: str, pose):
    """A `DvhPose *` for a 4x4 or 3x4 rigid transform (NULL for None)."""
    if pose is None:
        return ffi.NULL
    m = np.asarray(pose, dtype=np.float64)
    if m.shape not in ((4, 4), (3, 4)):
        raise ValueError(f"{name} must be a 4x4 or 3x4 matrix; got shape {m.shape}")
    if m.shape == (4, 4) and not np.array_equal(m[3], [0.0, 0.0, 0.0, 1.0]):
        raise ValueError(f"{name}'s last row must be [0, 0, 0, 1]; got {m[3].tolist()}")
    p = ffi.new("DvhPose *")
    p.rotation = m[:3, :3].ravel().tolist()
    p.translation = m[:3, 3].tolist()
    return p


# ---------------------------------------------------------------------------------------------
# Counters


@dataclass(frozen=True)
class QueryStats:
    """Counters of one query: the terms of the paper's cost model ``T = NV*CV + NP*CP + NU*CU``."""

    #: Volume pairs tested for overlap (NV).
    bv_tests: int
    #: Triangle pairs given to the exact test (NP).
    triangle_tests: int
    #: Triangle pairs of overlapping leaves, before the exact bounding-box filter.
    triangle_candidates: int
    #: Overlapping pairs of terminal nodes the traversal reached.
    leaf_pairs: int
    #: Pairs reported.
    pairs: int
    #: Nodes recomputed by the last refit of each mesh (NU of the frame).
    nodes_refit: int
    #: Did ``max_pairs`` stop the query before every pair was found?
    truncated: bool
    #: Node pairs left unopened when the ``"budget"`` mode's budget ran out.
    frontier_pairs: int

    @classmethod
    def _of(cls, s) -> "QueryStats":
        return cls(
            s.bv_tests, s.triangle_tests, s.triangle_candidates, s.leaf_pairs, s.pairs,
            s.nodes_refit, bool(s.truncated), s.frontier_pairs,
        )


@dataclass(frozen=True)
class SceneStats:
    """Counters of one :meth:`Scene.collide`."""

    #: Objects in the scene.
    objects: int
    #: Object pairs that passed the broad phase and the filters, and were queried.
    object_pairs_tested: int
    #: Object pairs with at least one contact.
    object_pairs_colliding: int
    #: Volume pairs tested, over every object pair.
    bv_tests: int
    #: Triangle pairs given to the exact test, over every object pair.
    triangle_tests: int
    #: Nodes recomputed by the refits the query made.
    nodes_refit: int
    #: Contacts reported.
    contacts: int
    #: Did ``max_pairs`` cut the result short?
    truncated: bool


@dataclass(frozen=True)
class TreeStats:
    """The shape of a mesh's hierarchy."""

    #: Triangles in the mesh.
    triangles: int
    #: 1-rings, that is leaves.
    rings: int
    #: Inner nodes.
    inner_nodes: int
    #: Levels: the depth of the deepest leaf plus one.
    levels: int
    #: Most triangles in one ring.
    max_ring_triangles: int


@dataclass(frozen=True)
class RefitStats:
    """Counters of a mesh's last refit (or of its build)."""

    #: Nodes whose volume was recomputed.
    nodes_refit: int
    #: Vertex-to-centre distances evaluated (for boxes: vertices folded into leaf boxes).
    distance_evaluations: int


# ---------------------------------------------------------------------------------------------
# Meshes


class Mesh:
    """A triangle mesh with its collision hierarchy.

    ``positions`` is an ``(n, 3)`` float64 or float32 array, ``triangles`` an ``(m, 3)`` integer
    array of vertex indices. Both are copied by the library; the arrays may change afterwards.

    ``volume`` is the bounding volume on every node: ``"aabb"`` (boxes, the fastest measured for
    deforming meshes; the default), ``"dvh"`` (spheres centred on vertices, refit by radii only)
    or ``"sbv"`` (free sphere centres). ``tree`` is ``"octree"`` (the default) or ``"binary"``.
    ``rigid=True`` starts from the options measured fastest for meshes moved by poses and never
    refit (SBV spheres with wrapped radii); ``volume``, ``tree``, ``radius`` and ``leftovers``,
    when given, override the starting point. ``refit_threads`` bounds the threads of a refit
    (0: every core).
    """

    __slots__ = ("_ptr", "_vertices", "_triangles", "__weakref__")

    def __init__(
        self,
        positions,
        triangles,
        volume: Optional[str] = None,
        tree: Optional[str] = None,
        rigid: bool = False,
        radius: Optional[str] = None,
        leftovers: Optional[str] = None,
        refit_threads: int = 0,
    ):
        opts = ffi.new("DvhBuildOptions *")
        opts[0] = lib.dvh_build_options_rigid() if rigid else lib.dvh_build_options_default()
        if volume is not None:
            opts.volume = _choice("volume", volume, _VOLUMES)
        if tree is not None:
            opts.tree = _choice("tree", tree, _TREES)
        if radius is not None:
            opts.radius = _choice("radius", radius, _RADII)
        if leftovers is not None:
            opts.leftovers = _choice("leftovers", leftovers, _LEFTOVERS)
        opts.refit_threads = _count("refit_threads", refit_threads, _U32_MAX)
        pos, pptr, stride, single = _positions("positions", positions)
        tri = _triangles(triangles)
        out = ffi.new("DvhMesh **")
        n, m = pos.shape[0], tri.shape[0]
        if single:
            if tri.dtype != np.uint32:
                tri = tri.astype(np.uint32)
            tptr = ffi.cast("const uint32_t *", tri.ctypes.data)
            status = lib.dvh_mesh_create_f32(pptr, stride, n, tptr, m, opts, out)
        elif tri.dtype == np.uint16:
            tptr = ffi.cast("const uint16_t *", tri.ctypes.data)
            status = lib.dvh_mesh_create_u16(pptr, n, tptr, m, opts, out)
        else:
            tptr = ffi.cast("const uint32_t *", tri.ctypes.data)
            status = lib.dvh_mesh_create(pptr, n, tptr, m, opts, out)
        _raise_for(status)
        self._ptr = ffi.gc(out[0], lib.dvh_mesh_free)
        self._vertices = n
        self._triangles = m

    @property
    def vertex_count(self) -> int:
        """Vertices of the mesh."""
        return self._vertices

    @property
    def triangle_count(self) -> int:
        """Triangles of the mesh."""
        return self._triangles

    @property
    def node_count(self) -> int:
        """Nodes of the hierarchy (node indices of the coarse query modes are below this)."""
        return lib.dvh_mesh_node_count(self._ptr)

    def refit(self, positions) -> None:
        """Moves every vertex to ``positions`` (``(n, 3)``, the mesh's vertex count) and refits the
        hierarchy. On error the mesh keeps its previous positions and volumes."""
        pos, pptr, stride, single = _positions("positions", positions, self._vertices)
        if single:
            status = lib.dvh_mesh_refit_f32(self._ptr, pptr, stride, pos.shape[0])
        else:
            status = lib.dvh_mesh_refit(self._ptr, pptr, pos.shape[0])
        _raise_for(status)

    def refit_motion(self, start: npt.ArrayLike, end: npt.ArrayLike) -> None:
        """Gives the mesh a motion over one step, for :func:`continuous_collide` and
        :func:`self_continuous_collide`: every vertex moves in a straight line from its row of
        ``start`` (time 0) to its row of ``end`` (time 1), both ``(n, 3)`` arrays of the mesh's
        vertex count (float64, or float32 and integers, widened exactly). The hierarchy is refit
        to hold every vertex's whole path, and the mesh's positions become ``end``: the discrete
        queries (:func:`collide`, ...) see the end of the step. A plain :meth:`refit` makes the
        mesh stationary again.

        A wrong shape or dtype is a ``ValueError``/``TypeError`` naming ``start`` or ``end``; a
        NaN or infinite coordinate a :class:`DvhError` (``NON_FINITE_COORDINATE``) whose message
        says which positions (start or end), vertex and axis. On error the mesh keeps its previous
        positions, motion and volumes."""
        s, sptr = _positions64("start", start, self._vertices)
        e, eptr = _positions64("end", end, self._vertices)
        _raise_for(lib.dvh_mesh_refit_motion(self._ptr, sptr, eptr, s.shape[0]))

    def tree_stats(self) -> TreeStats:
        """The shape of the hierarchy."""
        s = ffi.new("DvhTreeStats *")
        _raise_for(lib.dvh_mesh_tree_stats(self._ptr, s))
        return TreeStats(s.triangles, s.rings, s.inner_nodes, s.levels, s.max_ring_triangles)

    def last_refit_stats(self) -> RefitStats:
        """Counters of the last refit (or of the build)."""
        s = ffi.new("DvhRefitStats *")
        _raise_for(lib.dvh_mesh_last_refit_stats(self._ptr, s))
        return RefitStats(s.nodes_refit, s.distance_evaluations)

    def node_triangles(self, node: int) -> np.ndarray:
        """The triangles below ``node`` (a uint32 array), to expand the node pairs of the
        ``"leaves"``, ``"depth"`` and ``"budget"`` modes."""
        node = _count("node", node, _U32_MAX)
        tris = ffi.new("const uint32_t **")
        count = ffi.new("size_t *")
        _raise_for(lib.dvh_mesh_node_triangles(self._ptr, node, tris, count))
        return np.frombuffer(ffi.buffer(tris[0], 4 * count[0]), dtype=np.uint32).copy()

    @property
    def is_closed(self) -> bool:
        """Is the surface closed (every directed edge matched by its reverse)? Winding numbers
        and signed distances need it."""
        out = ffi.new("bool *")
        _raise_for(lib.dvh_mesh_is_closed(self._ptr, out))
        return bool(out[0])

    def validate(self) -> None:
        """Checks every invariant of the hierarchy; :class:`DvhError` (``INVARIANT_BROKEN``) if
        one is broken, which would be a bug in dvh."""
        _raise_for(lib.dvh_mesh_validate(self._ptr))

    def __repr__(self) -> str:
        return f"dvh.Mesh({self._vertices} vertices, {self._triangles} triangles)"


def _mesh(name: str, mesh) -> object:
    if not isinstance(mesh, Mesh):
        raise TypeError(f"{name} must be a dvh.Mesh; got {type(mesh).__name__}")
    return mesh._ptr


# ---------------------------------------------------------------------------------------------
# Queries


_option_cache: dict = {}


def _options(mode, max_pairs, threads, max_depth, budget):
    """The C options for these arguments, checked once and kept: the per-call cost of the
    Python layer is mostly here, and most programs use a handful of option sets. Only plain
    `str` and `int` arguments are kept (`True == 1` and `1.0 == 1` must not find a checked set)."""
    plain = (
        type(mode) is str
        and type(max_pairs) is int
        and type(threads) is int
        and type(max_depth) is int
        and type(budget) is int
    )
    key = (mode, max_pairs, threads, max_depth, budget)
    if plain:
        o = _option_cache.get(key)
        if o is not None:
            return o
    o = _new_options(mode, max_pairs, threads, max_depth, budget)
    if plain and len(_option_cache) < 256:
        _option_cache[key] = o
    return o


def _new_options(mode, max_pairs, threads, max_depth, budget):
    o = ffi.new("DvhQueryOptions *")
    o[0] = lib.dvh_query_options_default()
    o.mode = _choice("mode", mode, _MODES)
    o.max_pairs = _count("max_pairs", max_pairs, _U64_MAX)
    o.threads = _count("threads", threads, _U32_MAX)
    o.max_depth = _count("max_depth", max_depth, _U32_MAX)
    o.budget = _count("budget", budget, _U64_MAX)
    return o


class _Lent:
    """A result buffer's items lent to the arrays that view them: NumPy keeps this object as
    their base, so the buffer stays alive, and is not queried into again, while any view is."""

    __slots__ = ("_buffer", "__array_interface__", "__weakref__")

    def __init__(self, buffer, data, nbytes: int):
        self._buffer = buffer
        self.__array_interface__ = {
            "shape": (nbytes,),
            "typestr": "|u1",
            "data": (int(ffi.cast("uintptr_t", data)), False),
            "version": 3,
        }


class _Results:
    """The result buffers of one kind of query, whose results reach NumPy without a copy.

    A query writes into a buffer; the array returned views the buffer's items, and the buffer is
    used again only once every view of it is gone. (A result of a million stencils is 136 MB:
    copying it, into pages the system must first clear, took a quarter of the query's time.) A
    loop that holds the last result while it asks for the next alternates between two buffers,
    each keeping its capacity and the library's workspace. With ``LENT_MAX`` results held, a
    further query is copied out of one more buffer, so that results kept in numbers cost their
    own size, not a buffer's."""

    LENT_MAX = 2

    def __init__(self, new, free, length, data, dtype: np.dtype, width: int, what: str):
        self._new, self._free, self._len, self._data = new, free, length, data
        self._dtype, self._width, self._what = dtype, width, what
        self._itemsize = dtype.itemsize * width
        # [buffer, weak reference to the _Lent viewing its items, or None]
        self._lendable = []
        self._copying = None

    def _make(self):
        buf = self._new()
        if buf == ffi.NULL:
            raise MemoryError(f"{self._what}: out of memory")
        return ffi.gc(buf, self._free)

    def _take(self):
        """A buffer that no array views, and whether its result may be lent."""
        for slot in self._lendable:
            lent = slot[1]
            if lent is None or lent() is None:
                return slot, True
        if len(self._lendable) < self.LENT_MAX:
            self._lendable.append([self._make(), None])
            return self._lendable[-1], True
        if self._copying is None:
            self._copying = [self._make(), None]
        return self._copying, False

    def run(self, query, args, stats) -> np.ndarray:
        """The result of ``query(*args, buffer, stats)`` (a status, raised if an error; a failed
        query leaves the buffer's items as they were) as an array of this kind: ``(n,)`` of the
        dtype, or ``(n, width)``."""
        slot, lend = self._take()
        buf = slot[0]
        status = query(*args, buf, stats)
        if status:
            _raise_for(status)
        n = self._len(buf)
        if n == 0:
            slot[1] = None
            return np.empty((0, self._width) if self._width > 1 else 0, dtype=self._dtype)
        nbytes = self._itemsize * n
        if lend:
            owner = _Lent(buf, self._data(buf), nbytes)
            slot[1] = weakref.ref(owner)
            raw = np.asarray(owner)
        else:
            # Copied as bytes: NumPy copies a structured dtype with padding (``DvhImpact``'s,
            # ``DvhNearPair``'s) item by item, about three times slower than the bytes.
            raw = np.frombuffer(ffi.buffer(self._data(buf), nbytes), dtype=np.uint8).copy()
        out = raw.view(self._dtype)
        return out.reshape(n, self._width) if self._width > 1 else out


class _Buffers(threading.local):
    """The result buffers of each kind of query, per thread, reused by every query on it: the
    library keeps its workspace (the threads' scratch space) in the buffer, so reuse saves
    allocations. Each buffer is created by the first query that needs it."""

    def __init__(self):
        self.pairs = _Results(lib.dvh_pairs_new, lib.dvh_pairs_free, lib.dvh_pairs_len,
                              lib.dvh_pairs_data, np.dtype(np.uint32), 2, "dvh_pairs_new")
        self.impacts = _Results(lib.dvh_impacts_new, lib.dvh_impacts_free, lib.dvh_impacts_len,
                                lib.dvh_impacts_data, IMPACT_DTYPE, 1, "dvh_impacts_new")
        self.near_pairs = _Results(lib.dvh_near_pairs_new, lib.dvh_near_pairs_free,
                                   lib.dvh_near_pairs_len, lib.dvh_near_pairs_data,
                                   NEAR_PAIR_DTYPE, 1, "dvh_near_pairs_new")


def _stats_out(want: bool):
    return ffi.new("DvhQueryStats *") if want else ffi.NULL


def _finish(result: np.ndarray, stats, kind):
    """The result, with the statistics as ``kind`` when they were asked for."""
    return result if stats == ffi.NULL else (result, kind._of(stats))


_Result = Union[np.ndarray, Tuple[np.ndarray, QueryStats]]


def collide(
    a: Mesh,
    b: Mesh,
    pose_a=None,
    pose_b=None,
    mode: str = "triangles",
    max_pairs: int = 0,
    threads: int = 0,
    max_depth: int = 0,
    budget: int = 0,
    stats: bool = False,
) -> _Result:
    """The intersecting triangle pairs of ``a`` and ``b``, each placed by its pose (a 4x4 or 3x4
    rigid transform; None for the identity), as a ``(k, 2)`` uint32 array sorted by ``a`` then
    ``b``. The decision is exact: touching triangles intersect.

    ``mode``: ``"triangles"`` (every pair), ``"first_hit"`` (at most one), ``"leaves"`` (node pairs
    of overlapping leaves, no triangle tests), ``"depth"`` (node pairs at most ``max_depth`` deep),
    ``"budget"`` (at most ``budget`` volume tests). Node indices expand with
    :meth:`Mesh.node_triangles`. ``max_pairs`` stops after that many (0: no limit); ``threads``
    bounds the threads (0: every core; the result is the same for any count). With
    ``stats=True`` returns ``(pairs, QueryStats)``."""
    pa, pb = _mesh("a", a), _mesh("b", b)
    ka, kb = _pose("pose_a", pose_a), _pose("pose_b", pose_b)
    o = _options(mode, max_pairs, threads, max_depth, budget)
    s = _stats_out(stats)
    pairs = _buffers.pairs.run(lib.dvh_collide, (pa, ka, pb, kb, o), s)
    return _finish(pairs, s, QueryStats)


def self_collide(
    mesh: Mesh,
    mode: str = "triangles",
    max_pairs: int = 0,
    threads: int = 0,
    max_depth: int = 0,
    budget: int = 0,
    stats: bool = False,
) -> _Result:
    """The pairs ``(a, b)``, ``a < b``, of one mesh's triangles that intersect beyond what they
    share: triangles sharing a vertex or an edge are reported only when they also meet elsewhere.
    Options and result as :func:`collide`."""
    p = _mesh("mesh", mesh)
    o = _options(mode, max_pairs, threads, max_depth, budget)
    s = _stats_out(stats)
    pairs = _buffers.pairs.run(lib.dvh_self_collide, (p, o), s)
    return _finish(pairs, s, QueryStats)


def _distance(distance) -> float:
    if isinstance(distance, bool) or not isinstance(distance, (int, float, np.integer, np.floating)):
        raise TypeError(f"distance must be a number; got {distance!r}")
    return float(distance)


def proximity(
    a: Mesh,
    b: Mesh,
    distance: float,
    pose_a=None,
    pose_b=None,
    mode: str = "triangles",
    max_pairs: int = 0,
    threads: int = 0,
    max_depth: int = 0,
    budget: int = 0,
    stats: bool = False,
) -> _Result:
    """The triangle pairs of ``a`` and ``b`` whose distance is at most ``distance`` (decided
    exactly: 0 gives the touching pairs). Options and result as :func:`collide`; a negative,
    NaN or infinite distance is a :class:`DvhError`."""
    pa, pb = _mesh("a", a), _mesh("b", b)
    d = _distance(distance)
    ka, kb = _pose("pose_a", pose_a), _pose("pose_b", pose_b)
    o = _options(mode, max_pairs, threads, max_depth, budget)
    s = _stats_out(stats)
    pairs = _buffers.pairs.run(lib.dvh_proximity, (pa, ka, pb, kb, d, o), s)
    return _finish(pairs, s, QueryStats)


def self_proximity(
    mesh: Mesh,
    distance: float,
    mode: str = "triangles",
    max_pairs: int = 0,
    threads: int = 0,
    max_depth: int = 0,
    budget: int = 0,
    stats: bool = False,
) -> _Result:
    """The pairs ``(a, b)``, ``a < b``, of one mesh's triangles that share no vertex and lie
    within ``distance``. Options and result as :func:`proximity`."""
    p = _mesh("mesh", mesh)
    d = _distance(distance)
    o = _options(mode, max_pairs, threads, max_depth, budget)
    s = _stats_out(stats)
    pairs = _buffers.pairs.run(lib.dvh_self_proximity, (p, d, o), s)
    return _finish(pairs, s, QueryStats)


def triangles_intersect(t1, t2) -> bool:
    """Do two closed triangles (each a ``(3, 3)`` array of corners) intersect? Exact for every
    finite input; degenerate triangles are the segment or point they cover."""
    out = ffi.new("bool *")
    a = np.ascontiguousarray(t1, dtype=np.float64)
    b = np.ascontiguousarray(t2, dtype=np.float64)
    for name, t in (("t1", a), ("t2", b)):
        if t.shape != (3, 3):
            raise ValueError(f"{name} must have shape (3, 3); got {t.shape}")
    pa = ffi.cast("const double *", a.ctypes.data)
    pb = ffi.cast("const double *", b.ctypes.data)
    _raise_for(lib.dvh_triangles_intersect(pa, pb, out))
    return bool(out[0])


# ---------------------------------------------------------------------------------------------
# Continuous collision


@dataclass(frozen=True)
class CcdStats:
    """Counters of one continuous query (:func:`continuous_collide`,
    :func:`self_continuous_collide`)."""

    #: Volume pairs tested by the traversal over the motion.
    bv_tests: int
    #: Primitive pairs (vertex-face, edge-edge) given to the continuous test.
    primitive_tests: int
    #: Impacts reported.
    impacts: int
    #: The earliest ``toi`` of the impacts reported; ``inf`` when there are none.
    earliest_toi: float
    #: Did ``max_impacts`` stop the query before every impact was found?
    truncated: bool

    @classmethod
    def _of(cls, s) -> "CcdStats":
        return cls(
            s.bv_tests, s.primitive_tests, s.impacts, float(s.earliest_toi), bool(s.truncated)
        )


_ccd_option_cache: dict = {}


def _ccd_options(mode, threads, max_impacts, earliest_only):
    """The C continuous options for these arguments, checked once and kept (as `_options`)."""
    plain = (
        type(mode) is str
        and type(threads) is int
        and (max_impacts is None or type(max_impacts) is int)
        and type(earliest_only) is bool
    )
    key = (mode, threads, max_impacts, earliest_only)
    if plain:
        o = _ccd_option_cache.get(key)
        if o is not None:
            return o
    o = _new_ccd_options(mode, threads, max_impacts, earliest_only)
    if plain and len(_ccd_option_cache) < 256:
        _ccd_option_cache[key] = o
    return o


def _new_ccd_options(mode, threads, max_impacts, earliest_only):
    o = ffi.new("DvhCcdOptions *")
    o[0] = lib.dvh_ccd_options_default()
    o.mode = _choice("mode", mode, _CCD_MODES)
    o.threads = _count("threads", threads, _U32_MAX)
    if max_impacts is not None:
        if isinstance(max_impacts, bool) or not isinstance(max_impacts, (int, np.integer)):
            raise TypeError(f"max_impacts must be None or an integer; got {max_impacts!r}")
        n = int(max_impacts)
        if not 1 <= n <= _U64_MAX:
            raise ValueError(f"max_impacts must be None (no limit) or in 1..={_U64_MAX}; got {n}")
        o.max_impacts = n
    if not isinstance(earliest_only, (bool, np.bool_)):
        raise TypeError(f"earliest_only must be a bool; got {earliest_only!r}")
    o.earliest_only = bool(earliest_only)
    return o


_CcdResult = Union[np.ndarray, Tuple[np.ndarray, CcdStats]]


@overload
def continuous_collide(
    a: Mesh,
    b: Mesh,
    *,
    mode: str = ...,
    threads: int = ...,
    max_impacts: Optional[int] = ...,
    earliest_only: bool = ...,
    stats: Literal[False] = ...,
) -> np.ndarray: ...
@overload
def continuous_collide(
    a: Mesh,
    b: Mesh,
    *,
    mode: str = ...,
    threads: int = ...,
    max_impacts: Optional[int] = ...,
    earliest_only: bool = ...,
    stats: Literal[True],
) -> Tuple[np.ndarray, CcdStats]: ...
@overload
def continuous_collide(
    a: Mesh,
    b: Mesh,
    *,
    mode: str = ...,
    threads: int = ...,
    max_impacts: Optional[int] = ...,
    earliest_only: bool = ...,
    stats: bool = ...,
) -> _CcdResult: ...
def continuous_collide(
    a: Mesh,
    b: Mesh,
    *,
    mode: str = "exact",
    threads: int = 0,
    max_impacts: Optional[int] = None,
    earliest_only: bool = False,
    stats: bool = False,
) -> _CcdResult:
    """Every vertex-face and edge-edge pair of ``a`` and ``b`` that meets while each mesh moves
    through its last motion (:meth:`Mesh.refit_motion`; a mesh built or :meth:`Mesh.refit`
    since stays still at its positions), with the earliest time it does.

    Returns a structured array of :data:`IMPACT_DTYPE`, sorted by ``(kind, a0, a1, b0, b1)``:
    each vertex of ``a`` against each triangle of ``b`` (``kind`` :data:`IMPACT_VERTEX_FACE`,
    ``a0`` the vertex, ``b0`` the triangle), each triangle of ``a`` against each vertex of ``b``
    (:data:`IMPACT_FACE_VERTEX`, ``a0`` the triangle, ``b0`` the vertex), each edge of ``a``
    against each edge of ``b`` (:data:`IMPACT_EDGE_EDGE`, ``(a0, a1)`` and ``(b0, b1)`` with the
    lower vertex first; an edge is reported once however many triangles share it). ``toi`` is
    the earliest time of contact in ``[0, 1]``, rounded down to a double. Vertices of no
    triangle are not tested.

    ``mode``: ``"exact"`` (every decision exact; the default) or ``"conservative"`` (floating
    point only, bounded time per test: never misses an impact nor reports a later time than
    ``"exact"``, but may report primitives that come within rounding error of contact).
    ``threads`` bounds the threads (0: every core; the impacts are the same, in the same order,
    for any count). ``max_impacts`` stops the query after that many (None: no limit).
    ``earliest_only=True`` returns only the earliest impact (of several at that time, the first
    in the result's order), much faster than the whole list. With ``stats=True`` returns
    ``(impacts, CcdStats)``."""
    pa, pb = _mesh("a", a), _mesh("b", b)
    o = _ccd_options(mode, threads, max_impacts, earliest_only)
    s = ffi.new("DvhCcdStats *") if stats else ffi.NULL
    impacts = _buffers.impacts.run(lib.dvh_continuous_collide, (pa, pb, o), s)
    return _finish(impacts, s, CcdStats)


@overload
def self_continuous_collide(
    mesh: Mesh,
    *,
    mode: str = ...,
    threads: int = ...,
    max_impacts: Optional[int] = ...,
    earliest_only: bool = ...,
    stats: Literal[False] = ...,
) -> np.ndarray: ...
@overload
def self_continuous_collide(
    mesh: Mesh,
    *,
    mode: str = ...,
    threads: int = ...,
    max_impacts: Optional[int] = ...,
    earliest_only: bool = ...,
    stats: Literal[True],
) -> Tuple[np.ndarray, CcdStats]: ...
@overload
def self_continuous_collide(
    mesh: Mesh,
    *,
    mode: str = ...,
    threads: int = ...,
    max_impacts: Optional[int] = ...,
    earliest_only: bool = ...,
    stats: bool = ...,
) -> _CcdResult: ...
def self_continuous_collide(
    mesh: Mesh,
    *,
    mode: str = "exact",
    threads: int = 0,
    max_impacts: Optional[int] = None,
    earliest_only: bool = False,
    stats: bool = False,
) -> _CcdResult:
    """Every pair of one mesh's primitives that meets during its last motion, with the earliest
    time: each vertex against each triangle that does not contain it
    (:data:`IMPACT_VERTEX_FACE`, ``a0`` the vertex, ``b0`` the triangle) and each pair of edges
    that share no vertex (:data:`IMPACT_EDGE_EDGE`, ``(a0, a1) < (b0, b1)``); no
    :data:`IMPACT_FACE_VERTEX` impacts. Options and result as :func:`continuous_collide`."""
    p = _mesh("mesh", mesh)
    o = _ccd_options(mode, threads, max_impacts, earliest_only)
    s = ffi.new("DvhCcdStats *") if stats else ffi.NULL
    impacts = _buffers.impacts.run(lib.dvh_self_continuous_collide, (p, o), s)
    return _finish(impacts, s, CcdStats)


def _points4(name: str, points) -> np.ndarray:
    arr = np.asarray(points)
    if arr.shape != (4, 3):
        raise ValueError(f"{name} must have shape (4, 3); got {arr.shape}")
    return _float64(name, arr)


def _primitive(test, start, end, mode) -> Optional[float]:
    s, e = _points4("start", start), _points4("end", end)
    o = _ccd_options(mode, 0, None, False)
    hit = ffi.new("bool *")
    toi = ffi.new("double *")
    sptr = ffi.cast("const double *", s.ctypes.data)
    eptr = ffi.cast("const double *", e.ctypes.data)
    _raise_for(test(sptr, eptr, o, hit, toi))
    return float(toi[0]) if hit[0] else None


def ccd_vertex_face(
    start: npt.ArrayLike, end: npt.ArrayLike, *, mode: str = "exact"
) -> Optional[float]:
    """Does a point moving in a straight line meet a moving triangle during the step
    ``t`` in ``[0, 1]``, and when first? ``start`` and ``end`` are ``(4, 3)`` arrays: the point,
    then the triangle's three corners, at ``t = 0`` and ``t = 1``; every corner moves in a
    straight line. The triangle is closed (one of zero area is the segment or point it covers).

    Returns the earliest time of contact, rounded down to a double, or None when they never
    meet. ``mode`` as :func:`continuous_collide`: ``"exact"`` decides exactly for every finite
    input; ``"conservative"`` never returns None nor a later time where ``"exact"`` finds a
    contact, but may report near misses. A NaN or infinite coordinate is a :class:`DvhError`
    (``NON_FINITE_COORDINATE``)."""
    return _primitive(lib.dvh_ccd_vertex_face, start, end, mode)


def ccd_edge_edge(
    start: npt.ArrayLike, end: npt.ArrayLike, *, mode: str = "exact"
) -> Optional[float]:
    """Do two segments, their ends moving in straight lines, share a point during the step
    ``t`` in ``[0, 1]``, and when first? ``start`` and ``end`` are ``(4, 3)`` arrays: edge a's
    two ends, then edge b's, at ``t = 0`` and ``t = 1``. The segments are closed (a zero-length
    one is its point); parallel, collinear and overlapping segments are decided like any
    others. Result, ``mode`` and errors as :func:`ccd_vertex_face`."""
    return _primitive(lib.dvh_ccd_edge_edge, start, end, mode)


# ---------------------------------------------------------------------------------------------
# Scenes


class Scene:
    """A set of objects (rigid or deformable, sharing meshes) queried together: a broad phase
    over the objects, then the exact query on every pair that can collide. Objects ``i`` and
    ``j`` are tested when ``group_i & mask_j`` and ``group_j & mask_i`` are both non-zero; by
    default an object is in group 1 and its mask takes every group (as in the C++ layer).

    A rigid object keeps the mesh's current positions as local coordinates, moved by its pose; a
    deformable one is refit from :meth:`set_positions`. The scene copies what it needs: the mesh
    may be refit or dropped afterwards."""

    __slots__ = ("_ptr", "_vertices", "_contacts", "_impacts", "_near")

    def __init__(self):
        out = ffi.new("DvhScene **")
        _raise_for(lib.dvh_scene_create(out))
        self._ptr = ffi.gc(out[0], lib.dvh_scene_free)
        self._vertices = {}
        self._contacts = _Results(lib.dvh_contacts_new, lib.dvh_contacts_free, lib.dvh_contacts_len,
                                  lib.dvh_contacts_data, CONTACT_DTYPE, 1,
                                  "dvh_contacts_new")
        # Made on first use: their dtypes are defined after this class.
        self._impacts = None
        self._near = None

    def add_rigid(self, mesh: Mesh, pose=None, group: int = 1, mask: int = _U32_MAX) -> int:
        """Adds a rigid object placed by ``pose`` (4x4 or 3x4; None: the identity); returns its id."""
        p = _mesh("mesh", mesh)
        k = _pose("pose", pose)
        g, m = _count("group", group, _U32_MAX), _count("mask", mask, _U32_MAX)
        out = ffi.new("uint32_t *")
        _raise_for(lib.dvh_scene_add_rigid(self._ptr, p, k, g, m, out))
        return int(out[0])

    def add_deformable(self, mesh: Mesh, group: int = 1, mask: int = _U32_MAX) -> int:
        """Adds a deformable object, at the mesh's current positions; returns its id."""
        p = _mesh("mesh", mesh)
        g, m = _count("group", group, _U32_MAX), _count("mask", mask, _U32_MAX)
        out = ffi.new("uint32_t *")
        _raise_for(lib.dvh_scene_add_deformable(self._ptr, p, g, m, out))
        self._vertices[int(out[0])] = mesh.vertex_count
        return int(out[0])

    def set_pose(self, obj: int, pose) -> None:
        """Moves rigid object ``obj`` to ``pose``."""
        k = _pose("pose", pose)
        if k == ffi.NULL:
            k = _pose("pose", np.eye(4))
        _raise_for(lib.dvh_scene_set_pose(self._ptr, _count("obj", obj, _U32_MAX), k))

    def set_positions(self, obj: int, positions) -> None:
        """Gives deformable object ``obj`` new vertex positions (``(n, 3)``); it is refit when a
        query needs it."""
        obj = _count("obj", obj, _U32_MAX)
        pos, pptr, stride, single = _positions("positions", positions, self._vertices.get(obj))
        if single:
            status = lib.dvh_scene_set_positions_f32(self._ptr, obj, pptr, stride, pos.shape[0])
        else:
            status = lib.dvh_scene_set_positions(self._ptr, obj, pptr, pos.shape[0])
        _raise_for(status)

    def set_self_contact(self, obj: int, on: bool) -> None:
        """Turns deformable object ``obj``'s self-contact on or off (off when added): when on,
        :meth:`collide`, :meth:`continuous_collide` and :meth:`nearest_features` also report the
        object's pairs with itself (``object_a == object_b``), as :func:`self_collide`,
        :func:`self_continuous_collide` and :func:`self_nearest_features` do. Groups and masks do
        not gate it. Turning it on for a rigid object is a :class:`DvhError`
        (``INVALID_ARGUMENT``); turning it off is accepted."""
        if not isinstance(on, (bool, np.bool_)):
            raise TypeError(f"on must be a bool; got {on!r}")
        _raise_for(lib.dvh_scene_set_self_contact(self._ptr, _count("obj", obj, _U32_MAX), bool(on)))

    def set_motion(self, obj: int, start: npt.ArrayLike, end: npt.ArrayLike) -> None:
        """Gives deformable object ``obj`` a step: every vertex moves in a straight line from its
        row of ``start`` to its row of ``end`` (``(n, 3)`` arrays of the object's vertex count;
        float64, or float32 and integers, widened exactly). The discrete queries see ``end``;
        :meth:`continuous_collide` the whole step. The step lasts until the next
        :meth:`set_motion` or :meth:`set_positions`. Errors as :meth:`Mesh.refit_motion`; a
        rigid object is a :class:`DvhError` (``INVALID_ARGUMENT``)."""
        obj = _count("obj", obj, _U32_MAX)
        # A rigid or unknown object is the library's to refuse, naming it.
        n = self._vertices.get(obj)
        st, sptr = _positions64("start", start, len(np.asarray(start)) if n is None else n)
        en, eptr = _positions64("end", end, len(np.asarray(end)) if n is None else n)
        if st.shape != en.shape:
            raise ValueError(f"start and end must have the same shape; got {st.shape} and {en.shape}")
        _raise_for(lib.dvh_scene_set_motion(self._ptr, obj, sptr, eptr, st.shape[0]))

    def set_pose_motion(self, obj: int, start=None, end=None) -> None:
        """Gives rigid object ``obj`` a step from pose ``start`` to pose ``end`` (4x4 or 3x4;
        None: the identity): each vertex moves in a straight line from its start-pose to its
        end-pose world position. A large rotation in one step shortens the object midway (a half
        turn passes every vertex through the axis): steps should turn little. The discrete
        queries see ``end``. The step lasts until the next :meth:`set_pose_motion` or
        :meth:`set_pose`. A deformable object is a :class:`DvhError` (``INVALID_ARGUMENT``)."""
        k0, k1 = _pose("start", start), _pose("end", end)
        _raise_for(lib.dvh_scene_set_pose_motion(self._ptr, _count("obj", obj, _U32_MAX), k0, k1))

    def continuous_collide(
        self,
        mode: str = "exact",
        threads: int = 0,
        max_impacts: Optional[int] = None,
        earliest_only: bool = False,
        stats: bool = False,
    ):
        """Every impact during the objects' steps between two objects the filters allow, and
        within each object with self-contact on, as a structured array of
        :data:`SCENE_IMPACT_DTYPE`, sorted by ``(object_a, object_b)`` then as
        :func:`continuous_collide` sorts: for each pair exactly what :func:`continuous_collide`
        reports on stand-alone meshes holding the objects' world positions and motions (an
        object given no step stands still). ``earliest_only=True``: only the scene's earliest
        impact (of several at that time, the first in that order), every pair searching only up
        to the earliest found so far in any pair. Options as :func:`continuous_collide`; with
        ``stats=True`` returns ``(impacts, CcdStats)``, the counters summed over the pairs."""
        if self._impacts is None:
            self._impacts = _Results(lib.dvh_scene_impacts_new, lib.dvh_scene_impacts_free,
                                     lib.dvh_scene_impacts_len, lib.dvh_scene_impacts_data,
                                     SCENE_IMPACT_DTYPE, 1, "dvh_scene_impacts_new")
        o = _ccd_options(mode, threads, max_impacts, earliest_only)
        s = ffi.new("DvhCcdStats *") if stats else ffi.NULL
        impacts = self._impacts.run(lib.dvh_scene_continuous_collide, (self._ptr, o), s)
        return _finish(impacts, s, CcdStats)

    def nearest_features(
        self,
        distance: float,
        mode: str = "triangles",
        max_pairs: int = 0,
        threads: int = 0,
        max_depth: int = 0,
        budget: int = 0,
        stats: bool = False,
    ):
        """Every vertex-face and edge-edge stencil within ``distance`` between two objects the
        filters allow, and within each object with self-contact on, at the objects' current
        geometry (the end of their steps), as a structured array of
        :data:`SCENE_NEAR_PAIR_DTYPE`, sorted by ``(object_a, object_b)`` then as
        :func:`nearest_features` sorts: for each pair exactly what :func:`nearest_features` (or
        :func:`self_nearest_features`) reports. Options as :func:`nearest_features`; with
        ``stats=True`` returns ``(stencils, QueryStats)``, the counters summed over the pairs
        (``pairs``: the stencils reported)."""
        if self._near is None:
            self._near = _Results(lib.dvh_scene_near_pairs_new, lib.dvh_scene_near_pairs_free,
                                  lib.dvh_scene_near_pairs_len, lib.dvh_scene_near_pairs_data,
                                  SCENE_NEAR_PAIR_DTYPE, 1, "dvh_scene_near_pairs_new")
        d = _distance(distance)
        o = _options(mode, max_pairs, threads, max_depth, budget)
        s = _stats_out(stats)
        near = self._near.run(lib.dvh_scene_nearest_features, (self._ptr, d, o), s)
        return _finish(near, s, QueryStats)

    def distance(self, max_distance: float = float("inf"), rel_err: float = 0.0,
                 abs_err: float = 0.0, threads: int = 0):
        """The closest pair of distinct objects the filters allow, as ``(object_a, object_b,
        Distance)`` with ``object_a < object_b`` (the lower id's mesh first), exactly (ties to
        the least pair); ``None`` when none lies within ``max_distance``. See
        :func:`distance`."""
        from ._distance import scene_distance

        return scene_distance(self._ptr, max_distance, rel_err, abs_err, threads)

    def object_distance(self, obj: int, max_distance: float = float("inf"), rel_err: float = 0.0,
                        abs_err: float = 0.0, threads: int = 0):
        """The object closest to ``obj`` among those the filters allow it to meet, as ``(other,
        Distance)`` with ``obj``'s mesh first; ``None`` when none lies within
        ``max_distance``."""
        from ._distance import scene_object_distance

        return scene_object_distance(self._ptr, obj, max_distance, rel_err, abs_err, threads)

    def remove(self, obj: int) -> None:
        """Removes object ``obj``; its id may be given to a later object."""
        obj = _count("obj", obj, _U32_MAX)
        _raise_for(lib.dvh_scene_remove(self._ptr, obj))
        self._vertices.pop(obj, None)

    def exclude_pair(self, a: int, b: int) -> None:
        """Never tests objects ``a`` and ``b`` against each other."""
        a, b = _count("a", a, _U32_MAX), _count("b", b, _U32_MAX)
        _raise_for(lib.dvh_scene_exclude_pair(self._ptr, a, b))

    def set_lazy_refit(self, lazy: bool) -> None:
        """With ``lazy``, a deformable object with box volumes refits only the parts of its tree
        a query reaches."""
        _raise_for(lib.dvh_scene_set_lazy_refit(self._ptr, bool(lazy)))

    def collide(
        self,
        mode: str = "triangles",
        max_pairs: int = 0,
        threads: int = 0,
        max_depth: int = 0,
        budget: int = 0,
        stats: bool = False,
    ):
        """Every contact of the frame as a structured array of :data:`CONTACT_DTYPE`, sorted by
        ``(object_a, object_b, a, b)``. Options as :func:`collide`; with ``stats=True`` returns
        ``(contacts, SceneStats)``."""
        o = _options(mode, max_pairs, threads, max_depth, budget)
        s = ffi.new("DvhSceneStats *")
        contacts = self._contacts.run(lib.dvh_scene_collide, (self._ptr, o), s)
        if not stats:
            return contacts
        st = SceneStats(
            s.objects, s.object_pairs_tested, s.object_pairs_colliding, s.bv_tests,
            s.triangle_tests, s.nodes_refit, s.contacts, bool(s.truncated),
        )
        return contacts, st


# ---------------------------------------------------------------------------------------------
# Closest-point stencils

#: :data:`NEAR_PAIR_DTYPE`'s ``feature_a``/``feature_b``: corner 0 of the primitive (a vertex
#: primitive is always here).
FEATURE_VERTEX_0: int = int(lib.DVH_FEATURE_VERTEX_0)
#: Corner 1.
FEATURE_VERTEX_1: int = int(lib.DVH_FEATURE_VERTEX_1)
#: Corner 2 (of a triangle).
FEATURE_VERTEX_2: int = int(lib.DVH_FEATURE_VERTEX_2)
#: The open edge from corner 0 to corner 1 (an edge primitive's interior).
FEATURE_EDGE_01: int = int(lib.DVH_FEATURE_EDGE_01)
#: The open edge from corner 1 to corner 2.
FEATURE_EDGE_12: int = int(lib.DVH_FEATURE_EDGE_12)
#: The open edge from corner 2 to corner 0.
FEATURE_EDGE_20: int = int(lib.DVH_FEATURE_EDGE_20)
#: The interior of a triangle.
FEATURE_INTERIOR: int = int(lib.DVH_FEATURE_INTERIOR)

_NEAR_FIELDS = (
    ("kind", "=u4", ()),
    ("a0", "=u4", ()),
    ("a1", "=u4", ()),
    ("b0", "=u4", ()),
    ("b1", "=u4", ()),
    ("feature_a", "=u4", ()),
    ("feature_b", "=u4", ()),
    ("distance", "=f8", ()),
    ("closest_a", "=f8", (3,)),
    ("closest_b", "=f8", (3,)),
    ("weights_a", "=f8", (3,)),
    ("weights_b", "=f8", (3,)),
)

#: The dtype of :func:`nearest_features`' stencils, the layout of the C ``DvhNearPair``: ``kind``
#: and ``a0, a1, b0, b1`` as in :data:`IMPACT_DTYPE`; ``feature_a``, ``feature_b`` (``FEATURE_*``
#: constants: where each closest point lies, numbered on its primitive's own corners);
#: ``distance``; ``closest_a``, ``closest_b`` (world coordinates, shape 3); ``weights_a``,
#: ``weights_b`` (barycentric on the primitive's corners, shape 3: a vertex ``(1, 0, 0)``, an edge
#: ``(1 - s, s, 0)``, a triangle three weights summing to one). Fields ending in ``_a`` describe
#: the primitive named by ``a0, a1``. Its offsets and size (136 bytes) are the C struct's.
NEAR_PAIR_DTYPE = np.dtype(
    {
        "names": [f[0] for f in _NEAR_FIELDS],
        "formats": [(f[1], f[2]) if f[2] else f[1] for f in _NEAR_FIELDS],
        "offsets": [ffi.offsetof("DvhNearPair", f[0]) for f in _NEAR_FIELDS],
        "itemsize": ffi.sizeof("DvhNearPair"),
    }
)


_NearResult = Union[np.ndarray, Tuple[np.ndarray, QueryStats]]


def _scene_dtype(struct: str, inner: str, inner_type: str, fields) -> np.dtype:
    """A flat dtype over the C `struct`: `object_a`, `object_b`, then the fields of its
    `inner` member (of C type `inner_type`), at the C offsets."""
    base = ffi.offsetof(struct, inner)
    names = ["object_a", "object_b"] + [f[0] for f in fields]
    formats = ["=u4", "=u4"] + [(f[1], f[2]) if f[2] else f[1] for f in fields]
    offsets = [ffi.offsetof(struct, "object_a"), ffi.offsetof(struct, "object_b")] + [
        base + ffi.offsetof(inner_type, f[0]) for f in fields
    ]
    return np.dtype(
        {"names": names, "formats": formats, "offsets": offsets, "itemsize": ffi.sizeof(struct)}
    )


#: The dtype of :meth:`Scene.continuous_collide`'s impacts, the layout of the C
#: ``DvhSceneImpact`` with its ``impact`` member's fields flattened: ``object_a <= object_b``
#: (equal for an object's impact with itself), then ``kind, a0, a1, b0, b1, toi`` as in
#: :data:`IMPACT_DTYPE`, the first mesh ``object_a``'s.
SCENE_IMPACT_DTYPE = _scene_dtype(
    "DvhSceneImpact",
    "impact",
    "DvhImpact",
    [(f, "=f8" if f == "toi" else "=u4", ()) for f in ("kind", "a0", "a1", "b0", "b1", "toi")],
)

#: The dtype of :meth:`Scene.nearest_features`' stencils, the layout of the C
#: ``DvhSceneNearPair`` with its ``pair`` member's fields flattened: ``object_a <= object_b``,
#: then the fields of :data:`NEAR_PAIR_DTYPE`.
SCENE_NEAR_PAIR_DTYPE = _scene_dtype("DvhSceneNearPair", "pair", "DvhNearPair", _NEAR_FIELDS)


def nearest_features(
    a: Mesh,
    b: Mesh,
    distance: float,
    pose_a=None,
    pose_b=None,
    mode: str = "triangles",
    max_pairs: int = 0,
    threads: int = 0,
    max_depth: int = 0,
    budget: int = 0,
    stats: bool = False,
) -> _NearResult:
    """Every vertex-face and edge-edge pair of ``a`` and ``b`` (each placed by its pose) whose
    distance is at most ``distance``, with the distance, the closest point on each primitive,
    its barycentric weights and the feature it lies on: the stencils a simulator builds
    repulsion, barrier or constraint forces from.

    Returns a structured array of :data:`NEAR_PAIR_DTYPE`, sorted by ``(kind, a0, a1, b0, b1)``:
    each vertex of ``a`` against each triangle of ``b`` (:data:`IMPACT_VERTEX_FACE`), each
    triangle of ``a`` against each vertex of ``b`` (:data:`IMPACT_FACE_VERTEX`), each edge of
    ``a`` against each edge of ``b`` (:data:`IMPACT_EDGE_EDGE`, lower vertex first; an edge is
    reported once). The decision "distance <= d" is exact (0 gives the touching pairs); the
    distance is within one unit in the last place of the correctly rounded one, points and
    weights within two of the exact ones. Where closest points are not unique (parallel edges)
    the pair is taken at an end, tried in the order a0, a1, b0, b1, the first of the closest kept.

    ``mode``: ``"triangles"`` (every stencil), ``"first_hit"`` (at most one, the same for any
    thread count); ``"leaves"``, ``"depth"``, ``"budget"`` change only where the traversal stops
    (the stencils are the same). ``max_pairs``, ``threads`` and ``stats`` as :func:`collide`
    (in the statistics, ``triangle_tests`` counts the primitive pairs tested exactly)."""
    pa, pb = _mesh("a", a), _mesh("b", b)
    d = _distance(distance)
    ka, kb = _pose("pose_a", pose_a), _pose("pose_b", pose_b)
    o = _options(mode, max_pairs, threads, max_depth, budget)
    s = _stats_out(stats)
    near = _buffers.near_pairs.run(lib.dvh_nearest_features, (pa, ka, pb, kb, d, o), s)
    return _finish(near, s, QueryStats)


def self_nearest_features(
    mesh: Mesh,
    distance: float,
    mode: str = "triangles",
    max_pairs: int = 0,
    threads: int = 0,
    max_depth: int = 0,
    budget: int = 0,
    stats: bool = False,
) -> _NearResult:
    """One mesh's stencils with itself: each vertex against each triangle that does not contain
    it (:data:`IMPACT_VERTEX_FACE`, the vertex in ``a0``), each pair of edges sharing no vertex
    (:data:`IMPACT_EDGE_EDGE`, ``(a0, a1) < (b0, b1)``), within ``distance``. Options and result
    as :func:`nearest_features`."""
    p = _mesh("mesh", mesh)
    d = _distance(distance)
    o = _options(mode, max_pairs, threads, max_depth, budget)
    s = _stats_out(stats)
    near = _buffers.near_pairs.run(lib.dvh_self_nearest_features, (p, d, o), s)
    return _finish(near, s, QueryStats)


# Last: the result dtypes the buffers use are defined above.
_buffers = _Buffers()
