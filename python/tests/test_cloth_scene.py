"""The Python simulation example's short form: a small cloth over the turning paddle, the breathing
pillow and the floor stays free of intersections with the scene's queries alone, by the scene's
own check every step and by a brute force (boxes, then the exact triangle test) every tenth step;
without the cut at impacts, both find intersections."""

import os
import sys

import numpy as np
import pytest

import dvh

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "examples"))
import cloth_scene  # noqa: E402


def brute_force(report, k):
    """Intersecting triangle pairs after step `k`: the cloth against itself (pairs sharing no
    vertex) and against the obstacles, every pair whose boxes meet given to the exact test."""
    X, F = report["frames"][k], report["cloth_F"].astype(np.int64)
    cloth = X[F]
    others = report["obstacles"][k]
    found = 0
    for group, against_self in ((cloth, True), (others, False)):
        lo_a, hi_a = cloth.min(axis=1), cloth.max(axis=1)
        lo_b, hi_b = group.min(axis=1), group.max(axis=1)
        meet = np.all((lo_a[:, None, :] <= hi_b[None, :, :]) & (lo_b[None, :, :] <= hi_a[:, None, :]), axis=2)
        for i, j in zip(*np.nonzero(meet)):
            if against_self and (j <= i or np.intersect1d(F[i], F[j]).size):
                continue
            found += dvh.triangles_intersect(cloth[i], group[j])
    return found


@pytest.fixture(scope="module")
def cut():
    return cloth_scene.simulate(cells=10, steps=120, keep_frames=True)


def test_the_cloth_never_intersects_anything(cut):
    assert len(cut["intersecting"]) == 120
    assert sum(cut["intersecting"]) == 0
    for k in range(9, 120, 10):
        assert brute_force(cut, k) == 0, f"step {k}"
    # Not vacuous: the cloth came into contact and impacts were handled.
    assert sum(s > 0 for s in cut["stencils"]) > 40
    assert sum(k < 1 for k in cut["kept"]) + cut["moved"] > 0


def test_without_the_cut_the_checks_find_intersections():
    r = cloth_scene.simulate(cells=10, steps=120, keep_frames=True, cut=False)
    assert sum(r["intersecting"]) > 0
    assert sum(brute_force(r, k) for k in range(120) if r["intersecting"][k]) > 0
