#!/usr/bin/env python3
"""A scene of many deforming objects over simulation steps: dvh's ``Scene`` against the same
scene merged into one ``ipctk.CollisionMesh`` (what an IPC Toolkit user does with several
objects), and against dvh's own pairwise and self queries called object pair by object pair.

The scene: ``--objects`` deformable icospheres on a jittered grid, each bulging and denting
(smooth random displacement fields that change from step to step) and drifting towards its
neighbours. Every step starts free of intersection (the script checks it with the scene's exact
discrete query) and ends with some objects pressed into others; every object has self-contact
on, so the scene answers what the merged mesh answers: contacts between objects and within each.

Per step, each repeated and the fastest kept, medians over the steps:

- **earliest impact**: ``Scene.set_motion`` for every object and
  ``Scene.continuous_collide(earliest_only=True)``, against
  ``ipctk.compute_collision_free_stepsize(mesh, V0, V1, 0, None, TightInclusionCCD())`` and
  against ``continuous_collide`` / ``self_continuous_collide`` with ``earliest_only`` on every
  object pair and every object (the pairs' meshes refit to the step first);
- **stencils** at the step's start (free of intersection, objects close): ``Scene.set_positions``
  and ``Scene.nearest_features(d)``, against ``ipctk.NormalCollisions().build(mesh, V, d)`` and
  against ``nearest_features`` / ``self_nearest_features`` pair by pair.

Every step checks that the scene's answers equal the pairwise ones and that ipctk's step size is
no later than dvh's exact earliest time. Both libraries use every core.

    python python/bench/scene_peers.py [--objects N] [--level L] [--steps K] [--reps R] [--quick]
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time
from datetime import datetime, timezone
from importlib import metadata

import numpy as np

import dvh

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ccd_peers import blob, fortran, icosphere, ratio, table  # noqa: E402

try:
    import ipctk
except ImportError:  # the dvh rows still run; the ratios need ipctk
    ipctk = None

perf = time.perf_counter


def progress(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


class Objects:
    """`count` icospheres of radius 1 on a jittered grid with gaps of about `gap` that closes in,
    each with its own displacement fields and drift."""

    def __init__(self, count: int, level: int, gap: float, seed: int):
        rng = np.random.default_rng(seed)
        self.rest, F = icosphere(level)
        self.F = F.astype(np.uint32)
        side = int(np.ceil(count ** (1 / 3)))
        cells = [(i, j, k) for k in range(side) for j in range(side) for i in range(side)][:count]
        # Each field sums 6 waves of amplitude `amp`: bulges reach at most 6 `amp` beyond the
        # unit sphere, so centres this far apart keep the objects `gap` apart before the drift.
        self.amp = 0.012
        spacing = 2 * (1 + 6 * self.amp) + gap
        self.centres = np.array(cells, float) * spacing + rng.uniform(-0.1, 0.1, (count, 3)) * gap
        self.seeds = rng.integers(0, 2**31, size=count)
        self.drift = rng.normal(size=(count, 3))
        self.drift *= (0.5 * gap) / np.linalg.norm(self.drift, axis=1)[:, None]
        self.count = count
        # The grid closes in: each step brings neighbours 0.02 closer, so the gaps close
        # within a few steps and objects then press into each other.
        self.shrink = 0.02 / spacing

    def at(self, i: int, step: float) -> np.ndarray:
        """Object i's world positions at (fractional) step `step`: its shape blends between two
        displacement fields, its centre drifts (back and forth, so objects meet and part)."""
        k = int(np.floor(step))
        w = step - k
        a = blob(self.rest, int(self.seeds[i]) + k, amp=self.amp) - self.rest
        b = blob(self.rest, int(self.seeds[i]) + k + 1, amp=self.amp) - self.rest
        shape = self.rest + (1 - w) * a + w * b
        centre = self.centres[i] * (1 - self.shrink * step) + np.sin(0.7 * step) * self.drift[i]
        return np.ascontiguousarray(shape + centre)


def scene_of(meshes):
    s = dvh.Scene()
    for m in meshes:
        o = s.add_deformable(m)
        s.set_self_contact(o, True)
    return s


def best_of(reps: int, fn):
    best, out = float("inf"), None
    for _ in range(reps):
        t0 = perf()
        out = fn()
        best = min(best, perf() - t0)
    return best, out


def run(args) -> str:
    objs = Objects(args.objects, args.level, args.gap, args.seed)
    n = objs.count
    ntri = len(objs.F) * n
    progress(f"{n} objects of {len(objs.F)} triangles ({ntri} in all)")
    states = [[objs.at(i, float(k)) for i in range(n)] for k in range(args.steps + 1)]
    # Steps that start free of intersection: a simulator's states are.
    meshes = [dvh.Mesh(states[0][i], objs.F) for i in range(n)]
    scene = scene_of(meshes)
    every = np.vstack(states[0])
    diag = float(np.linalg.norm(every.max(0) - every.min(0)))
    d = args.distance * diag
    steps = []
    for k in range(args.steps):
        for i in range(n):
            scene.set_positions(i, states[k][i])
        if len(scene.collide()) == 0:
            steps.append(k)
    if not steps:
        raise SystemExit("no step starts free of intersection: make --gap larger")
    progress(f"{len(steps)} of {args.steps} steps start free of intersection; d = {d:.4g}")
    F_all = np.vstack([objs.F.astype(np.int64) + i * len(objs.rest) for i in range(n)])
    cm = ti = None
    if ipctk is not None:
        Fi = np.asfortranarray(F_all.astype(np.int32))
        cm = ipctk.CollisionMesh(fortran(np.vstack(states[0])), np.asfortranarray(ipctk.edges(Fi)), Fi)
        ti = ipctk.TightInclusionCCD()
    pairs = [(i, j) for i in range(n) for j in range(i + 1, n)]
    t = {key: [] for key in ["ccd scene", "ccd pairs", "ccd ipctk", "near scene", "near pairs",
                             "near ipctk"]}
    counts = {"stencils": [], "ipctk stencils": [], "toi": [], "ipctk toi": []}
    for k in steps:
        progress(f"step {k}")
        A, B = states[k], states[k + 1]

        def ccd_scene():
            for i in range(n):
                scene.set_motion(i, A[i], B[i])
            return scene.continuous_collide(earliest_only=True)

        def ccd_pairs():
            for i in range(n):
                meshes[i].refit_motion(A[i], B[i])
            first = None
            for i in range(n):
                for j in range(i, n):
                    if i == j:
                        imp = dvh.self_continuous_collide(meshes[i], earliest_only=True)
                    else:
                        imp = dvh.continuous_collide(meshes[i], meshes[j], earliest_only=True)
                    if len(imp) and (first is None or imp["toi"][0] < first[2]["toi"]):
                        first = (i, j, imp[0])
            return first

        sec, got = best_of(args.reps, ccd_scene)
        t["ccd scene"].append(sec)
        sec, first = best_of(args.reps, ccd_pairs)
        t["ccd pairs"].append(sec)
        # The scene's earliest is the pairs': equal times (the scene breaks ties by its order).
        if (len(got) == 0) != (first is None) or (first is not None and got["toi"][0] != first[2]["toi"]):
            raise SystemExit(f"step {k}: the scene's earliest impact {got} is not the pairs' {first}")
        toi = float(got["toi"][0]) if len(got) else 1.0
        counts["toi"].append(toi)
        if ipctk is not None:
            V0, V1 = fortran(np.vstack(A)), fortran(np.vstack(B))
            sec, step = best_of(args.reps, lambda: ipctk.compute_collision_free_stepsize(cm, V0, V1, 0.0, None, ti))
            t["ccd ipctk"].append(sec)
            counts["ipctk toi"].append(step)
            if step > toi:
                raise SystemExit(f"step {k}: ipctk's step size {step} is after dvh's exact earliest {toi}")

        def near_scene():
            for i in range(n):
                scene.set_positions(i, A[i])
            return scene.nearest_features(d)

        def near_pairs():
            for i in range(n):
                meshes[i].refit(A[i])
            out = []
            for i in range(n):
                near = dvh.self_nearest_features(meshes[i], d)
                if len(near):
                    out.append(near)
                for j in range(i + 1, n):
                    near = dvh.nearest_features(meshes[i], meshes[j], d)
                    if len(near):
                        out.append(near)
            return sum(len(x) for x in out)

        sec, near = best_of(args.reps, near_scene)
        t["near scene"].append(sec)
        sec, total = best_of(args.reps, near_pairs)
        t["near pairs"].append(sec)
        if total != len(near):
            raise SystemExit(f"step {k}: the scene found {len(near)} stencils, pair by pair {total}")
        counts["stencils"].append(len(near))
        if ipctk is not None:
            V = fortran(np.vstack(A))

            def build():
                c = ipctk.NormalCollisions()
                c.build(cm, V, d)
                return len(c)

            sec, m = best_of(args.reps, build)
            t["near ipctk"].append(sec)
            counts["ipctk stencils"].append(m)
    med = {key: float(np.median(v)) * 1e3 if v else float("nan") for key, v in t.items()}
    ms = lambda x: f"{x:.2f}"  # noqa: E731
    lines = [
        f"## A scene of many deforming objects ({n} objects, {ntri:,} triangles)",
        "",
        f"{datetime.now(timezone.utc):%Y-%m-%d}, {platform.machine()}, {os.cpu_count()} cores; "
        f"dvh {metadata.version('dvh')}" + (f", ipctk {metadata.version('ipctk')}" if ipctk else "")
        + f"; {len(steps)} steps, each call's fastest of {args.reps}, medians over the steps (ms). "
        f"Earliest time of impact per step: dvh exact {min(counts['toi']):.4g}-{max(counts['toi']):.4g}"
        + (f", ipctk {min(counts['ipctk toi']):.4g}-{max(counts['ipctk toi']):.4g}" if ipctk else "")
        + f". Stencils within {args.distance:g} of the scene's diagonal: dvh "
        f"{min(counts['stencils'])}-{max(counts['stencils'])}"
        + (f", ipctk {min(counts['ipctk stencils'])}-{max(counts['ipctk stencils'])}" if ipctk else "")
        + ".",
        "",
        table(["query", "dvh Scene", "dvh pair by pair (from Python)", "ipctk, one CollisionMesh",
               "Scene vs pairs", "Scene vs ipctk"],
              [["earliest impact over a step", ms(med["ccd scene"]), ms(med["ccd pairs"]),
                ms(med["ccd ipctk"]), ratio(med["ccd pairs"], med["ccd scene"]),
                ratio(med["ccd ipctk"], med["ccd scene"])],
               ["stencils", ms(med["near scene"]), ms(med["near pairs"]), ms(med["near ipctk"]),
                ratio(med["near pairs"], med["near scene"]),
                ratio(med["near ipctk"], med["near scene"])]]),
    ]
    return "\n".join(lines)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--objects", type=int, default=40)
    p.add_argument("--level", type=int, default=3, help="icosphere subdivisions (20 * 4^L triangles)")
    p.add_argument("--steps", type=int, default=12)
    p.add_argument("--reps", type=int, default=5)
    p.add_argument("--gap", type=float, default=0.05, help="least gap between objects at rest")
    p.add_argument("--distance", type=float, default=0.002, help="stencil distance, of the diagonal")
    p.add_argument("--seed", type=int, default=7)
    p.add_argument("--quick", action="store_true", help="8 objects of 320 triangles, 4 steps")
    args = p.parse_args(argv)
    if args.quick:
        args.objects, args.level, args.steps, args.reps = 8, 2, 4, 2
    print(run(args))
    return 0


if __name__ == "__main__":
    sys.exit(main())
