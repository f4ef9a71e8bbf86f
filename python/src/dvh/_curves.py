"""Intersection curves through the C ABI: where two meshes, or one mesh with itself, cross."""

from __future__ import annotations

import threading
from dataclasses import dataclass
from typing import List, Optional, Tuple, Union

import numpy as np

from ._api import QueryStats, _mesh, _options, _pose, _raise_for
from ._dvh import ffi, lib

#: :data:`DEGENERATE_DTYPE`'s ``kind``: the pair meets in one point only.
DEGENERATE_POINT: int = int(lib.DVH_DEGENERATE_KIND_POINT)
#: :data:`DEGENERATE_DTYPE`'s ``kind``: coplanar triangles that meet (in an area, a segment or a
#: point), or a degenerate triangle meeting the other in its plane.
DEGENERATE_COPLANAR: int = int(lib.DVH_DEGENERATE_KIND_COPLANAR)


def _dtype(struct: str, fields) -> np.dtype:
    names = [n for n, _ in fields]
    return np.dtype(
        {
            "names": names,
            "formats": [f for _, f in fields],
            "offsets": [ffi.offsetof(struct, n) for n in names],
            "itemsize": ffi.sizeof(struct),
        }
    )


#: The dtype of :attr:`Curves.segments`, the layout of the C ``DvhCurveSegment``: the triangle
#: of the first mesh (of one mesh: the lower index), of the second (the higher), the curve it
#: belongs to, and its ``start`` and ``end`` points in world coordinates (each coordinate the
#: exact one rounded to the nearest double; the end of a segment is, bit for bit, the start of
#: the next on its curve).
SEGMENT_DTYPE = _dtype(
    "DvhCurveSegment",
    [
        ("triangle_a", "=u4"),
        ("triangle_b", "=u4"),
        ("curve", "=u4"),
        ("start", ("=f8", (3,))),
        ("end", ("=f8", (3,))),
    ],
)

#: The dtype of :attr:`Curves.degenerate`, the layout of the C ``DvhDegeneratePair``: an
#: intersecting triangle pair with no segment, and its ``kind`` (:data:`DEGENERATE_POINT` or
#: :data:`DEGENERATE_COPLANAR`).
DEGENERATE_DTYPE = _dtype(
    "DvhDegeneratePair", [("triangle_a", "=u4"), ("triangle_b", "=u4"), ("kind", "=u4")]
)


@dataclass(frozen=True)
class Curves:
    """The curves along which two meshes (or one mesh with itself) cross.

    ``segments`` (:data:`SEGMENT_DTYPE`) holds one segment per intersecting triangle pair that
    meets in a segment, curve by curve, each curve's in chain order. ``ranges`` is a ``(k, 2)``
    int64 array: curve ``i`` is ``segments[ranges[i, 0]:ranges[i, 1]]``; ``closed[i]`` says
    whether it returns to its start (an open curve ends on a boundary edge, beside a degenerate
    pair, or where more than two segments meet). Curves are ordered by their least
    ``(triangle_a, triangle_b)`` segment; a closed curve starts there and runs along
    ``n_a x n_b`` of that pair. ``degenerate`` (:data:`DEGENERATE_DTYPE`) lists the intersecting
    pairs that have no segment, sorted.

    With ``gradient=True``, ``gradient_a`` and ``gradient_b`` (``(n, 3)`` float64, one row per
    vertex; of one mesh, ``gradient_a`` alone) hold the gradient of the curves' total length
    with respect to the vertices' world positions: the direction of intersection contour
    minimisation (moving the vertices a small step against it shortens the curves, and surfaces
    that cross come apart as the curves shrink to nothing)."""

    segments: np.ndarray
    ranges: np.ndarray
    closed: np.ndarray
    degenerate: np.ndarray
    gradient_a: Optional[np.ndarray] = None
    gradient_b: Optional[np.ndarray] = None

    def __len__(self) -> int:
        """The number of curves."""
        return len(self.ranges)

    def curve(self, i: int) -> np.ndarray:
        """The segments of curve ``i``, in chain order."""
        first, stop = self.ranges[i]
        return self.segments[first:stop]

    def polyline(self, i: int) -> np.ndarray:
        """Curve ``i`` as an ``(n + 1, 3)`` array of points: its segments' starts, then the
        last one's end (for a closed curve, its first point again)."""
        s = self.curve(i)
        return np.vstack([s["start"], s["end"][-1:]])

    def polylines(self) -> List[np.ndarray]:
        """Every curve as :meth:`polyline` gives it."""
        return [self.polyline(i) for i in range(len(self))]

    @property
    def lengths(self) -> np.ndarray:
        """Each curve's length: the sum of its segments' lengths (from the rounded points)."""
        d = np.linalg.norm(self.segments["end"] - self.segments["start"], axis=1)
        return np.add.reduceat(d, self.ranges[:, 0]) if len(self.ranges) else d[:0]

    def write_obj(self, path) -> None:
        """Writes the curves to ``path`` as OBJ polylines: one ``l`` line per curve over its
        points (a closed curve's line returns to its first point)."""
        with open(path, "w", encoding="utf-8") as f:
            f.write(f"# {len(self)} intersection curves, {len(self.segments)} segments\n")
            base = 1
            for i in range(len(self)):
                points = self.polyline(i)
                if self.closed[i]:
                    points = points[:-1]
                for p in points:
                    f.write("v {!r} {!r} {!r}\n".format(*map(float, p)))
                idx = list(range(base, base + len(points)))
                if self.closed[i]:
                    idx.append(base)
                f.write("l " + " ".join(map(str, idx)) + "\n")
                base += len(points)


class _Buffer(threading.local):
    """One curve buffer per thread, kept for its workspace: the results are copied out."""

    def get(self):
        buf = getattr(self, "buf", None)
        if buf is None:
            raw = lib.dvh_curves_new()
            if raw == ffi.NULL:
                raise MemoryError("dvh_curves_new: out of memory")
            buf = self.buf = ffi.gc(raw, lib.dvh_curves_free)
        return buf


_buffer = _Buffer()


def _copy(data, n: int, dtype: np.dtype) -> np.ndarray:
    if n == 0:
        return np.empty(0, dtype=dtype)
    raw = np.frombuffer(ffi.buffer(data, n * dtype.itemsize), dtype=np.uint8).copy()
    return raw.view(dtype)


def _run(query, args, stats: bool, gradient=None):
    """The curves of ``query(*args, buffer, stats)``; ``gradient``: the meshes (and poses) for
    their length gradient, or None."""
    buf = _buffer.get()
    s = ffi.new("DvhQueryStats *") if stats else ffi.NULL
    status = query(*args, buf, s)
    if status:
        _raise_for(status)
    segments = _copy(lib.dvh_curves_data(buf), lib.dvh_curves_len(buf), SEGMENT_DTYPE)
    degenerate = _copy(
        lib.dvh_curves_degenerate_data(buf), lib.dvh_curves_degenerate_len(buf), DEGENERATE_DTYPE
    )
    k = lib.dvh_curves_curve_count(buf)
    ranges = np.empty((k, 2), dtype=np.int64)
    closed = np.empty(k, dtype=bool)
    first, count, is_closed = ffi.new("size_t *"), ffi.new("size_t *"), ffi.new("bool *")
    for i in range(k):
        status = lib.dvh_curves_curve(buf, i, first, count, is_closed)
        if status:
            _raise_for(status)
        ranges[i] = (first[0], first[0] + count[0])
        closed[i] = is_closed[0]
    ga = gb = None
    if gradient is not None:
        ga = np.zeros((gradient[0].vertex_count, 3))
        pa = ffi.cast("double *", ga.ctypes.data)
        if len(gradient) == 1:
            status = lib.dvh_curves_self_length_gradient(buf, gradient[0]._ptr, pa, len(ga))
        else:
            a, ka, b, kb = gradient
            gb = np.zeros((b.vertex_count, 3))
            pb = ffi.cast("double *", gb.ctypes.data)
            status = lib.dvh_curves_length_gradient(
                buf, a._ptr, ka, b._ptr, kb, pa, len(ga), pb, len(gb)
            )
        if status:
            _raise_for(status)
    curves = Curves(segments, ranges, closed, degenerate, ga, gb)
    return curves if s == ffi.NULL else (curves, QueryStats._of(s))


_CurvesResult = Union[Curves, Tuple[Curves, QueryStats]]


def intersection_curves(
    a,
    b,
    pose_a=None,
    pose_b=None,
    max_pairs: int = 0,
    threads: int = 0,
    stats: bool = False,
    gradient: bool = False,
) -> _CurvesResult:
    """The curves along which ``a`` and ``b`` (each placed by its pose, as :func:`collide`)
    cross, as :class:`Curves`.

    Every pair :func:`collide` reports gives a segment (a pair that is not coplanar and meets in
    more than one point) or a degenerate pair. A segment's ends are where an edge of one triangle
    meets the other (or a vertex lies in it), decided exactly and rounded once to doubles;
    segments join where their ends are the same exact point, decided from the mesh features that
    meet there, never from rounded coordinates. ``max_pairs`` bounds segments plus degenerate
    pairs (0: no limit); ``threads`` as :func:`collide` (the answer is the same for any count).
    With ``stats=True`` returns ``(curves, QueryStats)``; ``QueryStats.pairs`` counts segments
    plus degenerate pairs. With ``gradient=True`` the result carries the length gradient
    (:attr:`Curves.gradient_a`, :attr:`Curves.gradient_b`)."""
    pa, pb = _mesh("a", a), _mesh("b", b)
    ka, kb = _pose("pose_a", pose_a), _pose("pose_b", pose_b)
    o = _options("triangles", max_pairs, threads, 0, 0)
    g = (a, ka, b, kb) if gradient else None
    return _run(lib.dvh_intersection_curves, (pa, ka, pb, kb, o), stats, g)


def self_intersection_curves(
    mesh, max_pairs: int = 0, threads: int = 0, stats: bool = False, gradient: bool = False
) -> _CurvesResult:
    """The curves along which ``mesh`` crosses itself: those of the pairs :func:`self_collide`
    reports (a pair sharing a vertex gives a segment from that vertex to where the two part).
    Segments are ``(lower, higher)`` triangle pairs. Otherwise as :func:`intersection_curves`
    (the gradient, with respect to the mesh's vertices, in :attr:`Curves.gradient_a`)."""
    p = _mesh("mesh", mesh)
    o = _options("triangles", max_pairs, threads, 0, 0)
    g = (mesh,) if gradient else None
    return _run(lib.dvh_self_intersection_curves, (p, o), stats, g)
