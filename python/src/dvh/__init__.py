"""dvh: exact collision detection between deformable triangle meshes.

Build a :class:`Mesh` from NumPy arrays, query it with :func:`collide`, :func:`self_collide`,
:func:`proximity` and :func:`self_proximity`, refit it as it deforms with :meth:`Mesh.refit`;
many objects at once go into a :class:`Scene`. Triangle pairs come back as ``(k, 2)`` uint32
arrays. Every decision is exact (touching counts as intersecting). Bad input raises
``ValueError``/``TypeError`` before any call, or :class:`DvhError` with the library's message;
a failed call changes nothing. The GIL is released while the library works.
"""

from ._api import (
    CONTACT_DTYPE,
    DvhError,
    Mesh,
    QueryStats,
    RefitStats,
    Scene,
    SceneStats,
    TreeStats,
    collide,
    proximity,
    self_collide,
    self_proximity,
    triangles_intersect,
    version,
)

__all__ = [
    "CONTACT_DTYPE",
    "DvhError",
    "Mesh",
    "QueryStats",
    "RefitStats",
    "Scene",
    "SceneStats",
    "TreeStats",
    "collide",
    "proximity",
    "self_collide",
    "self_proximity",
    "triangles_intersect",
    "version",
]

__version__ = version()
