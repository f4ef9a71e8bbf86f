"""Distances through the C ABI: of two meshes, of a mesh to many points (closest points, winding
numbers, signed distances), and of a scene's objects."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional, Tuple, Union

import numpy as np

from ._api import NEAR_PAIR_DTYPE, QueryStats, _count, _float64, _mesh, _pose, _raise_for, _U32_MAX
from ._dvh import ffi, lib

#: The winding number :func:`winding_numbers` reports for a point on the surface (on a
#: triangle, its edges and corners included), where none is defined: ``-2**31``.
WINDING_ON_SURFACE: int = int(lib.DVH_WINDING_ON_SURFACE)

#: The dtype of :func:`closest_points`' results, the layout of the C ``DvhClosestPoint``:
#: ``found`` (0: no triangle within ``max_distance``, every other field 0), the ``triangle`` the
#: closest point lies on (the least of several at the same distance), the ``feature`` of it that
#: holds the point (``FEATURE_*``), the ``distance`` (within one unit in the last place of the
#: exact one correctly rounded), the ``point`` and its barycentric ``weights`` on the triangle.
CLOSEST_POINT_DTYPE = np.dtype(
    {
        "names": ["found", "triangle", "feature", "distance", "point", "weights"],
        "formats": ["=u4", "=u4", "=u4", "=f8", ("=f8", (3,)), ("=f8", (3,))],
        "offsets": [
            ffi.offsetof("DvhClosestPoint", n)
            for n in ("found", "triangle", "feature", "distance", "point", "weights")
        ],
        "itemsize": ffi.sizeof("DvhClosestPoint"),
    }
)


@dataclass(frozen=True)
class Distance:
    """The least distance between two meshes' surfaces (:func:`distance`)."""

    #: Do the meshes intersect (touching counts)? Then ``distance`` is 0, the triangles are the
    #: least intersecting pair and both closest points a point of both (within rounding).
    intersecting: bool
    #: The first mesh's triangle the closest point lies on (the least of several).
    triangle_a: int
    #: The second mesh's.
    triangle_b: int
    #: The distance, within one unit in the last place of the exact one correctly rounded.
    distance: float
    #: The first mesh's closest point, world coordinates, shape ``(3,)``.
    closest_a: np.ndarray
    #: The second mesh's closest point.
    closest_b: np.ndarray
    #: The vertex-face or edge-edge pair that attains the distance, a record of
    #: :data:`NEAR_PAIR_DTYPE` (``None`` for intersecting meshes).
    stencil: Optional[np.void]

    @classmethod
    def _of(cls, d) -> Optional["Distance"]:
        if not d.found:
            return None
        stencil = None
        if not d.intersecting:
            stencil = np.frombuffer(ffi.buffer(ffi.addressof(d, "stencil"), NEAR_PAIR_DTYPE.itemsize),
                                    dtype=NEAR_PAIR_DTYPE).copy()[0]
        return cls(
            intersecting=bool(d.intersecting),
            triangle_a=int(d.triangle_a),
            triangle_b=int(d.triangle_b),
            distance=float(d.distance),
            closest_a=np.array(list(d.closest_a)),
            closest_b=np.array(list(d.closest_b)),
            stencil=stencil,
        )


def _distance_options(max_distance, rel_err, abs_err, threads):
    o = ffi.new("DvhDistanceOptions *", lib.dvh_distance_options_default())
    o.max_distance = float(max_distance)
    o.rel_err = float(rel_err)
    o.abs_err = float(abs_err)
    o.threads = _count("threads", threads, _U32_MAX)
    return o


def _points(points) -> Tuple[np.ndarray, object, int]:
    """``points`` as a C-contiguous ``(n, 3)`` float64 array, a pointer to it and ``n``."""
    arr = np.asarray(points)
    if arr.ndim == 1 and arr.shape[0] == 3:
        arr = arr.reshape(1, 3)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise ValueError(f"points must have shape (n, 3); got {arr.shape}")
    arr = _float64("points", arr)
    return arr, ffi.cast("const double *", arr.ctypes.data), arr.shape[0]


_WithStats = Union[np.ndarray, Tuple[np.ndarray, QueryStats]]


def distance(
    a,
    b,
    pose_a=None,
    pose_b=None,
    max_distance: float = math.inf,
    rel_err: float = 0.0,
    abs_err: float = 0.0,
    threads: int = 0,
    stats: bool = False,
):
    """The least distance between the surfaces of meshes ``a`` and ``b`` (each placed by its
    4x4 or 3x4 pose; ``None``: world coordinates), exactly, as a :class:`Distance`; ``None``
    when they lie farther apart than ``max_distance``. The pair of primitives reported attains
    the exact least distance (of several, the first by ``(kind, a0, a1, b0, b1)``); with
    ``rel_err`` or ``abs_err``, a pair at distance ``d <= (1 + rel_err) m + abs_err`` of the
    least ``m`` may be reported. With ``stats=True`` returns ``(distance, QueryStats)``."""
    o = _distance_options(max_distance, rel_err, abs_err, threads)
    out = ffi.new("DvhDistance *")
    s = ffi.new("DvhQueryStats *")
    _raise_for(lib.dvh_distance(_mesh("a", a), _pose("pose_a", pose_a), _mesh("b", b),
                                _pose("pose_b", pose_b), o, out, s))
    d = Distance._of(out[0])
    return (d, QueryStats._of(s)) if stats else d


def closest_points(
    mesh,
    points,
    pose=None,
    max_distance: float = math.inf,
    rel_err: float = 0.0,
    abs_err: float = 0.0,
    threads: int = 0,
    stats: bool = False,
) -> _WithStats:
    """For each row of ``points`` (shape ``(n, 3)``), the closest point of ``mesh`` placed by
    ``pose``, as a structured array of :data:`CLOSEST_POINT_DTYPE`: the triangle (the least of
    several at the same distance), the feature, the distance, the point and its weights, all
    exact as :func:`distance`'s. No triangle within ``max_distance``: ``found`` 0. With
    ``stats=True`` returns ``(results, QueryStats)`` (``pairs``: the points found)."""
    arr, ptr, n = _points(points)
    o = _distance_options(max_distance, rel_err, abs_err, threads)
    out = np.zeros(n, dtype=CLOSEST_POINT_DTYPE)
    s = ffi.new("DvhQueryStats *")
    _raise_for(lib.dvh_closest_points(_mesh("mesh", mesh), _pose("pose", pose), ptr, n, o,
                                      ffi.cast("DvhClosestPoint *", out.ctypes.data), s))
    del arr
    return (out, QueryStats._of(s)) if stats else out


def winding_numbers(mesh, points, pose=None, threads: int = 0) -> np.ndarray:
    """For each row of ``points``, its winding number about the closed surface of ``mesh``
    placed by ``pose``, as an int32 array: +1 inside an outward surface, 0 outside, 2 where a
    folded surface wraps twice, :data:`WINDING_ON_SURFACE` on the surface. Exact for every point.
    A mesh that is not closed raises :class:`DvhError` (``DVH_STATUS_NOT_CLOSED``, naming an
    edge)."""
    arr, ptr, n = _points(points)
    out = np.zeros(n, dtype=np.int32)
    _raise_for(lib.dvh_winding_numbers(_mesh("mesh", mesh), _pose("pose", pose), ptr, n,
                                       _count("threads", threads, _U32_MAX),
                                       ffi.cast("int32_t *", out.ctypes.data)))
    del arr
    return out


def signed_distances(
    mesh,
    points,
    pose=None,
    max_distance: float = math.inf,
    rel_err: float = 0.0,
    abs_err: float = 0.0,
    threads: int = 0,
    stats: bool = False,
) -> _WithStats:
    """For each row of ``points``, its signed distance to the closed surface of ``mesh`` placed
    by ``pose``, as a float64 array: the distance of :func:`closest_points`, negative inside
    (exact winding number not 0), positive outside, 0 on the surface; beyond ``max_distance``,
    an infinity of the point's sign."""
    arr, ptr, n = _points(points)
    o = _distance_options(max_distance, rel_err, abs_err, threads)
    out = np.zeros(n, dtype=np.float64)
    s = ffi.new("DvhQueryStats *")
    _raise_for(lib.dvh_signed_distances(_mesh("mesh", mesh), _pose("pose", pose), ptr, n, o,
                                        ffi.cast("double *", out.ctypes.data), s))
    del arr
    return (out, QueryStats._of(s)) if stats else out


def scene_distance(scene_ptr, max_distance, rel_err, abs_err, threads):
    """The closest allowed pair of a scene: ``(object_a, object_b, Distance)`` or ``None``."""
    o = _distance_options(max_distance, rel_err, abs_err, threads)
    ia, ib = ffi.new("uint32_t *"), ffi.new("uint32_t *")
    out = ffi.new("DvhDistance *")
    _raise_for(lib.dvh_scene_distance(scene_ptr, o, ia, ib, out))
    d = Distance._of(out[0])
    return None if d is None else (int(ia[0]), int(ib[0]), d)


def scene_object_distance(scene_ptr, obj, max_distance, rel_err, abs_err, threads):
    """One object's closest other: ``(other, Distance)`` or ``None``."""
    o = _distance_options(max_distance, rel_err, abs_err, threads)
    other = ffi.new("uint32_t *")
    out = ffi.new("DvhDistance *")
    _raise_for(lib.dvh_scene_object_distance(scene_ptr, _count("obj", obj, _U32_MAX), o, other, out))
    d = Distance._of(out[0])
    return None if d is None else (int(other[0]), d)
