"""The benchmarks' cloth simulation (python/bench/cloth_steps.py): dvh's stencils and continuous
collision alone keep the sheet free of self-intersection through a fall into folded, resting
self-contact."""

import os
import sys

import dvh

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "bench"))
import cloth_steps  # noqa: E402


def test_the_simulated_cloth_never_intersects_itself():
    steps = []
    F, motions, states, info = cloth_steps.simulate(cells=16, steps=120, check=True, log=steps.append)
    assert len(motions) == len(states) == 120
    # Self-contact happened: impacts held vertices back and stencils pushed layers apart.
    assert info["cuts"] >= 10, info
    assert sum(" 0 stencils" not in s for s in steps) >= 20
    # A later state has layers resting within the thickness somewhere (not scripted: simulated).
    mesh = dvh.Mesh(states[-1], F)
    assert len(dvh.self_nearest_features(mesh, info["thickness"])) > 0
    assert len(dvh.self_collide(mesh)) == 0
