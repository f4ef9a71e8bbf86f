"""dvh: exact collision detection between deformable triangle meshes.

Build a :class:`Mesh` from NumPy arrays, query it with :func:`collide`, :func:`self_collide`,
:func:`proximity` and :func:`self_proximity`, refit it as it deforms with :meth:`Mesh.refit`;
many objects at once go into a :class:`Scene`. Triangle pairs come back as ``(k, 2)`` uint32
arrays. Every decision is exact (touching counts as intersecting). Bad input raises
``ValueError``/``TypeError`` before any call, or :class:`DvhError` with the library's message;
a failed call changes nothing. The GIL is released while the library works.

Continuous collision: give meshes a motion over one step with :meth:`Mesh.refit_motion`, then
:func:`continuous_collide` and :func:`self_continuous_collide` return every vertex-face and
edge-edge pair that meets during the step, with its earliest time of impact, as a structured
array of :data:`IMPACT_DTYPE`; :func:`ccd_vertex_face` and :func:`ccd_edge_edge` test one pair
of primitives.

Closest-point stencils: :func:`nearest_features` and :func:`self_nearest_features` return every
vertex-face and edge-edge pair within a distance, with the distance, closest points, barycentric
weights and features, as a structured array of :data:`NEAR_PAIR_DTYPE`.

Intersection curves: :func:`intersection_curves` and :func:`self_intersection_curves` return
where the surfaces cross as :class:`Curves`: exact segments (one per intersecting triangle pair,
structured array of :data:`SEGMENT_DTYPE`) chained into curves, and the pairs that meet without
a segment (:data:`DEGENERATE_DTYPE`).

Distances: :func:`distance` gives the least distance between two meshes, exactly, with the
closest points and the pair of primitives that attains it (0 and the least intersecting pair
for meshes that intersect); :func:`closest_points`, :func:`winding_numbers` and
:func:`signed_distances` answer for many points at once against one mesh (exact integer winding
numbers and signs for closed meshes: :attr:`Mesh.is_closed`); :meth:`Scene.distance` and
:meth:`Scene.object_distance` find a scene's closest objects.

Files: :func:`read_mesh` reads OFF and OBJ (and, with meshio or trimesh installed, PLY, STL and
more); ``python -m dvh check`` checks one or two mesh files, or with ``--batch`` a whole data
set or an animation's frames on several processes or a Dask cluster.
"""

from ._api import (
    CONTACT_DTYPE,
    FEATURE_EDGE_01,
    FEATURE_EDGE_12,
    FEATURE_EDGE_20,
    FEATURE_INTERIOR,
    FEATURE_VERTEX_0,
    FEATURE_VERTEX_1,
    FEATURE_VERTEX_2,
    IMPACT_DTYPE,
    IMPACT_EDGE_EDGE,
    IMPACT_FACE_VERTEX,
    IMPACT_VERTEX_FACE,
    NEAR_PAIR_DTYPE,
    SCENE_IMPACT_DTYPE,
    SCENE_NEAR_PAIR_DTYPE,
    CcdStats,
    DvhError,
    Mesh,
    QueryStats,
    RefitStats,
    Scene,
    SceneStats,
    TreeStats,
    ccd_edge_edge,
    ccd_vertex_face,
    collide,
    continuous_collide,
    nearest_features,
    proximity,
    self_collide,
    self_continuous_collide,
    self_nearest_features,
    self_proximity,
    triangles_intersect,
    version,
)
from ._meshfile import MeshFileError, read_mesh
from ._distance import (
    CLOSEST_POINT_DTYPE,
    WINDING_ON_SURFACE,
    Distance,
    closest_points,
    distance,
    signed_distances,
    winding_numbers,
)
from ._curves import (
    DEGENERATE_COPLANAR,
    DEGENERATE_DTYPE,
    DEGENERATE_POINT,
    SEGMENT_DTYPE,
    Curves,
    intersection_curves,
    self_intersection_curves,
)

__all__ = [
    "CLOSEST_POINT_DTYPE",
    "CONTACT_DTYPE",
    "DEGENERATE_COPLANAR",
    "DEGENERATE_DTYPE",
    "DEGENERATE_POINT",
    "FEATURE_EDGE_01",
    "FEATURE_EDGE_12",
    "FEATURE_EDGE_20",
    "FEATURE_INTERIOR",
    "FEATURE_VERTEX_0",
    "FEATURE_VERTEX_1",
    "FEATURE_VERTEX_2",
    "IMPACT_DTYPE",
    "IMPACT_EDGE_EDGE",
    "IMPACT_FACE_VERTEX",
    "IMPACT_VERTEX_FACE",
    "NEAR_PAIR_DTYPE",
    "SCENE_IMPACT_DTYPE",
    "SCENE_NEAR_PAIR_DTYPE",
    "SEGMENT_DTYPE",
    "WINDING_ON_SURFACE",
    "CcdStats",
    "Curves",
    "Distance",
    "DvhError",
    "Mesh",
    "MeshFileError",
    "QueryStats",
    "RefitStats",
    "Scene",
    "SceneStats",
    "TreeStats",
    "ccd_edge_edge",
    "ccd_vertex_face",
    "closest_points",
    "collide",
    "continuous_collide",
    "distance",
    "intersection_curves",
    "nearest_features",
    "proximity",
    "read_mesh",
    "self_collide",
    "self_continuous_collide",
    "self_intersection_curves",
    "self_nearest_features",
    "self_proximity",
    "signed_distances",
    "triangles_intersect",
    "version",
    "winding_numbers",
]

__version__ = version()
