#!/usr/bin/env python3
"""A cloth simulation kept free of intersections by a dvh scene alone (the Python twin of
``examples/cloth_scene.rs``).

A square cloth falls onto a rigid paddle that turns about the vertical axis and onto a soft
pillow that breathes (a deformable object whose shape is scripted), drapes over both, slides off
and folds onto itself on the floor. The scene holds four objects: the floor, the paddle (rigid,
given a start and an end pose each step), the pillow (deformable, given a motion each step) and
the cloth (deformable, self-contact on). The obstacles are tested only against the cloth (groups
and masks); the cloth against everything, itself included.

Each step:

1. **Predict** (position-based dynamics, Müller et al. 2007): gravity, then Jacobi passes over
   stretch and bending constraints.
2. **Repel** (the stencils): ``Scene.nearest_features`` at the cloth's thickness; every stencil
   closer than the thickness is pushed apart to it along the line between its closest points,
   the move shared over the cloth's corners by their barycentric weights (an obstacle does not
   give way). A few rounds, interleaved with the constraints.
3. **Cut** (continuous collision): ``Scene.continuous_collide(earliest_only=True)``, the cloth
   moving from its last positions to the predicted ones while the paddle turns and the pillow
   breathes; when the cloth meets itself before the end of the step, its motion is cut to 80%
   of the time of impact (a line search) and repelled again; an impact with an obstacle (or a
   cut grown too small) moves the cloth corners of every impact as the obstacle moves over the
   step (or keeps them where they were), and the scene is asked again until the step is free.
4. **Check**: ``Scene.collide`` (self-contact on) must find no intersecting triangle pair.

    python python/examples/cloth_scene.py [--cells N] [--steps K] [--out DIR]

Writes DIR/frame_NNNN.obj every tenth step (the cloth and the obstacles) and DIR/cloth.svg (per
step, the least distance of the cloth to anything and the number of stencils); prints the time
per step spent in the scene's queries and in the rest.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

import dvh

GRAVITY = np.array([0.0, 0.0, -9.81])
DT = 1.0 / 100.0
ITERATIONS = 10
CONTACT_ROUNDS = 3
FLOOR = -0.3


def grid(cells: int, size: float = 1.0, z: float = 0.25):
    """A `cells` × `cells` grid of quads, two triangles each, `size` wide, at height `z`, tilted
    a little so that it slides off to one side and folds as it lands."""
    n = cells + 1
    u = np.arange(n) / cells
    X, Y = np.meshgrid(u, u, indexing="xy")
    x, y = (X.ravel() - 0.5) * size, (Y.ravel() - 0.5) * size
    V = np.column_stack([x, y, z + 0.08 * x])
    j, i = np.meshgrid(np.arange(cells), np.arange(cells), indexing="ij")
    a = (j * n + i).ravel()
    b, c, d = a + 1, a + n + 1, a + n
    F = np.empty((2 * len(a), 3), dtype=np.uint32)
    F[0::2] = np.column_stack([a, b, c])
    F[1::2] = np.column_stack([a, c, d])
    return V, F


def cuboid(h):
    """A closed box of half-sizes `h`, centred at the origin: 8 corners, 12 triangles."""
    V = np.array([[h[a] if k >> a & 1 else -h[a] for a in range(3)] for k in range(8)], float)
    F = np.array([[0, 2, 3], [0, 3, 1], [4, 5, 7], [4, 7, 6], [0, 1, 5], [0, 5, 4],
                  [2, 6, 7], [2, 7, 3], [0, 4, 6], [0, 6, 2], [1, 3, 7], [1, 7, 5]], np.uint32)
    return V, F


def sphere(rings: int):
    """A UV sphere of radius 1, `rings` rings of `2 rings` segments, closed at the poles."""
    seg = 2 * rings
    V = [[0.0, 0.0, 1.0]]
    for r in range(1, rings):
        th = np.pi * r / rings
        for s in range(seg):
            ph = 2 * np.pi * s / seg
            V.append([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)])
    V.append([0.0, 0.0, -1.0])
    at = lambda r, s: 1 + (r - 1) * seg + s % seg  # noqa: E731
    last = len(V) - 1
    F = []
    for s in range(seg):
        F.append([0, at(1, s), at(1, s + 1)])
        for r in range(1, rings - 1):
            F += [[at(r, s), at(r + 1, s), at(r + 1, s + 1)], [at(r, s), at(r + 1, s + 1), at(r, s + 1)]]
        F.append([at(rings - 1, s), last, at(rings - 1, s + 1)])
    return np.array(V), np.array(F, np.uint32)


def paddle_pose(t: float) -> np.ndarray:
    """The paddle at time `t`: turning about the vertical axis through its centre (4x4)."""
    a = 0.8 * t
    P = np.eye(4)
    P[:3, :3] = [[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0], [0.0, 0.0, 1.0]]
    P[:3, 3] = [-0.12, 0.0, -0.12]
    return P


def pillow_at(rest: np.ndarray, t: float) -> np.ndarray:
    """The pillow at time `t`: a squashed sphere on the floor, breathing."""
    s = 1.0 + 0.15 * np.sin(4.0 * t)
    return np.column_stack([0.3 + 0.16 * s * rest[:, 0], 0.1 + 0.16 * s * rest[:, 1],
                            FLOOR + 0.1 * s * (rest[:, 2] + 1.0)])


def constraints(cells: int, V: np.ndarray):
    """Stretch (grid edges and diagonals) and bending (two apart along a row or a column)
    constraints: index pairs and rest lengths."""
    n = cells + 1
    idx = np.arange(n * n).reshape(n, n)
    pairs = [(idx[:, :-1], idx[:, 1:]), (idx[:-1, :], idx[1:, :]), (idx[:-1, :-1], idx[1:, 1:])]
    bends = [(idx[:, :-2], idx[:, 2:]), (idx[:-2, :], idx[2:, :])]

    def stack(ps):
        P = np.column_stack([np.concatenate([a.ravel() for a, _ in ps]),
                             np.concatenate([b.ravel() for _, b in ps])])
        return P, np.linalg.norm(V[P[:, 1]] - V[P[:, 0]], axis=1)

    return stack(pairs), stack(bends)


def project_lengths(P, pairs, rest, stiffness):
    """One Jacobi pass over distance constraints, each vertex's corrections averaged."""
    a, b = pairs[:, 0], pairs[:, 1]
    d = P[b] - P[a]
    length = np.linalg.norm(d, axis=1)
    ok = length > 1e-12
    c = np.where(ok, (length - rest) / np.where(ok, length, 1.0), 0.0)[:, None] * d * (0.5 * stiffness)
    delta = np.zeros_like(P)
    count = np.zeros(len(P))
    np.add.at(delta, a, c)
    np.add.at(delta, b, -c)
    np.add.at(count, a, 1.0)
    np.add.at(count, b, 1.0)
    return P + delta / np.maximum(count, 1.0)[:, None]


def corners(kind, first, i0, i1, F, mine=None):
    """The corners of one side of stencils or impacts (`first`: the side named by a0, a1), as
    (k, 3) vertex indices of the mesh whose triangles are `F`, unused slots repeating the first
    corner; rows where `mine` is false (another object's side) are 0."""
    mine = np.ones(len(kind), bool) if mine is None else mine
    vf, fv = kind == dvh.IMPACT_VERTEX_FACE, kind == dvh.IMPACT_FACE_VERTEX
    point = vf if first else fv
    face = fv if first else vf
    tri = F[np.where(face & mine, i0, 0)].astype(np.int64)
    out = np.column_stack([i0, np.where(point, i0, i1), i0]).astype(np.int64)
    return np.where(mine[:, None], np.where(face[:, None], tri, out), 0)


def push_apart(P, near, cloth, F, thickness):
    """One projection of every stencil closer than `thickness`: its closest points moved apart
    to the thickness, the move shared over the cloth's corners by their weights (an obstacle's
    side does not move)."""
    keep = (near["distance"] > 1e-12) & (near["distance"] < thickness)
    near = near[keep]
    if len(near) == 0:
        return P
    dist = near["distance"]
    normal = (near["closest_a"] - near["closest_b"]) / dist[:, None]
    on_a, on_b = near["object_a"] == cloth, near["object_b"] == cloth
    wa = near["weights_a"] * on_a[:, None]
    wb = near["weights_b"] * on_b[:, None]
    s = (thickness - dist) / ((wa * wa).sum(axis=1) + (wb * wb).sum(axis=1))
    ca = corners(near["kind"], True, near["a0"], near["a1"], F, on_a)
    cb = corners(near["kind"], False, near["b0"], near["b1"], F, on_b)
    delta = np.zeros_like(P)
    count = np.zeros(len(P))
    for k in range(3):
        np.add.at(delta, ca[:, k], (s * wa[:, k])[:, None] * normal)
        np.add.at(delta, cb[:, k], -(s * wb[:, k])[:, None] * normal)
        np.add.at(count, ca[:, k], wa[:, k] > 0)
        np.add.at(count, cb[:, k], wb[:, k] > 0)
    return P + delta / np.sqrt(np.maximum(count, 1.0))[:, None]


def simulate(cells=40, steps=300, threads=0, out=None, keep_frames=False, cut=True):
    """Runs the simulation; returns a dict: per step the least distance of a stencil at the end
    of the step, the stencils, the fraction of the motion kept, the intersecting pairs found by
    the check; the corners moved by the fallback; seconds in the scene and in the rest; with
    `keep_frames`, the cloth's positions and the obstacles' world triangles after each step."""
    cloth_V, cloth_F = grid(cells)
    thickness = 0.25 / cells
    (stretch, rest_s), (bend, rest_b) = constraints(cells, cloth_V)
    floor_V = np.array([[-3, -3, FLOOR], [3, -3, FLOOR], [3, 3, FLOOR], [-3, 3, FLOOR]], float)
    floor_F = np.array([[0, 1, 2], [0, 2, 3]], np.uint32)
    paddle_V, paddle_F = cuboid([0.3, 0.05, 0.05])
    pillow_rest, pillow_F = sphere(10)
    pillow = pillow_at(pillow_rest, 0.0)

    obstacle, cloth_group = 1, 2
    scene = dvh.Scene()
    scene.add_rigid(dvh.Mesh(floor_V, floor_F), None, obstacle, cloth_group)
    paddle = scene.add_rigid(dvh.Mesh(paddle_V, paddle_F), paddle_pose(0.0), obstacle, cloth_group)
    pillow_id = scene.add_deformable(dvh.Mesh(pillow, pillow_F), obstacle, cloth_group)
    cloth = scene.add_deformable(dvh.Mesh(cloth_V, cloth_F), cloth_group, obstacle | cloth_group)
    scene.set_self_contact(cloth, True)

    X = cloth_V.copy()
    vel = np.zeros_like(X)
    report = {"triangles": len(cloth_F), "thickness": thickness, "least": [], "stencils": [],
              "kept": [], "intersecting": [], "moved": 0, "scene_s": 0.0, "rest_s": 0.0,
              "frames": [], "obstacles": [], "cloth_F": cloth_F}
    for step in range(steps):
        t0, t1 = step * DT, (step + 1) * DT
        clock = time.perf_counter()
        scene.set_pose_motion(paddle, paddle_pose(t0), paddle_pose(t1))
        pillow_next = pillow_at(pillow_rest, t1)
        scene.set_motion(pillow_id, pillow, pillow_next)
        report["scene_s"] += time.perf_counter() - clock

        clock = time.perf_counter()
        vel = vel + GRAVITY * DT
        P = X + vel * DT
        for _ in range(ITERATIONS - CONTACT_ROUNDS):
            P = project_lengths(P, stretch, rest_s, 1.0)
            P = project_lengths(P, bend, rest_b, 0.1)
        report["rest_s"] += time.perf_counter() - clock
        kept, rounds = 1.0, 0
        while True:
            for r in range(CONTACT_ROUNDS):
                clock = time.perf_counter()
                P = project_lengths(P, stretch, rest_s, 1.0)
                P = project_lengths(P, bend, rest_b, 0.1)
                report["rest_s"] += time.perf_counter() - clock
                clock = time.perf_counter()
                scene.set_positions(cloth, P)
                near = scene.nearest_features(thickness, threads=threads)
                report["scene_s"] += time.perf_counter() - clock
                if r == 0 and rounds == 0:
                    report["stencils"].append(len(near))
                clock = time.perf_counter()
                P = push_apart(P, near, cloth, cloth_F, thickness)
                report["rest_s"] += time.perf_counter() - clock
            clock = time.perf_counter()
            scene.set_motion(cloth, X, P)
            first, st = scene.continuous_collide(threads=threads, earliest_only=True, stats=True)
            report["scene_s"] += time.perf_counter() - clock
            if len(first) == 0 or not cut:
                break
            rounds += 1
            x = first[0]
            if x["object_a"] == cloth and x["object_b"] == cloth and st.earliest_toi > 1e-3 and rounds < 8:
                alpha = 0.8 * st.earliest_toi
                P = X + alpha * (P - X)
                kept *= alpha
                continue
            clock = time.perf_counter()
            every = scene.continuous_collide(threads=threads)
            report["scene_s"] += time.perf_counter() - clock
            for x in every:
                for first_side, obj, i0, i1 in ((True, x["object_a"], x["a0"], x["a1"]),
                                                (False, x["object_b"], x["b0"], x["b1"])):
                    if obj != cloth:
                        continue
                    other = x["object_b"] if first_side else x["object_a"]
                    vs = np.unique(corners(np.array([x["kind"]]), first_side, np.array([i0]),
                                           np.array([i1]), cloth_F))
                    if other == paddle:
                        M = paddle_pose(t1) @ np.linalg.inv(paddle_pose(t0))
                        P[vs] = X[vs] @ M[:3, :3].T + M[:3, 3]
                    elif other == pillow_id:
                        side = not first_side
                        o0, o1 = (x["a0"], x["a1"]) if side else (x["b0"], x["b1"])
                        ps = np.unique(corners(np.array([x["kind"]]), side, np.array([o0]),
                                               np.array([o1]), pillow_F))
                        P[vs] = X[vs] + (pillow_next[ps] - pillow[ps]).mean(axis=0)
                    else:
                        P[vs] = X[vs]
                    report["moved"] += len(vs)
            if rounds > 64:
                break
        report["kept"].append(kept)
        clock = time.perf_counter()
        vel = (P - X) / DT * 0.995
        X = P
        pillow = pillow_next
        report["rest_s"] += time.perf_counter() - clock
        clock = time.perf_counter()
        scene.set_positions(cloth, X)
        report["intersecting"].append(len(scene.collide(threads=threads)))
        near = scene.nearest_features(thickness, threads=threads)
        report["scene_s"] += time.perf_counter() - clock
        report["least"].append(float(near["distance"].min()) if len(near) else float("inf"))
        if keep_frames or out:
            report["frames"].append(X.copy())
        if keep_frames:
            Pw = paddle_V @ paddle_pose(t1)[:3, :3].T + paddle_pose(t1)[:3, 3]
            report["obstacles"].append(np.concatenate([floor_V[floor_F], Pw[paddle_F], pillow[pillow_F]]))
    if out:
        write_outputs(out, report, paddle_V, paddle_F, pillow_rest, pillow_F)
    return report


def write_outputs(out, report, paddle_V, paddle_F, pillow_rest, pillow_F):
    os.makedirs(out, exist_ok=True)
    frames = report["frames"]
    for k, X in enumerate(frames):
        if k % 10 != 9 and k + 1 != len(frames):
            continue
        t = (k + 1) * DT
        P = paddle_pose(t)
        parts = [("cloth", X, report["cloth_F"]),
                 ("paddle", paddle_V @ P[:3, :3].T + P[:3, 3], paddle_F),
                 ("pillow", pillow_at(pillow_rest, t), pillow_F)]
        lines, base = [], 1
        for name, V, F in parts:
            lines.append(f"o {name}")
            lines += [f"v {a} {b} {c}" for a, b, c in V]
            lines += [f"f {a + base} {b + base} {c + base}" for a, b, c in F]
            base += len(V)
        with open(os.path.join(out, f"frame_{k + 1:04d}.obj"), "w") as f:
            f.write("\n".join(lines) + "\n")
    w, h = 900, 420
    svg = [f"<svg xmlns='http://www.w3.org/2000/svg' width='{w}' height='{h}' font-family='sans-serif' "
           "font-size='12'><rect width='100%' height='100%' fill='white'/>"]

    def plot(y0, label, values, top):
        x0, pw, ph = 60, 800, 150
        svg.append(f"<text x='{x0}' y='{y0 - 6}'>{label}</text>")
        svg.append(f"<rect x='{x0}' y='{y0}' width='{pw}' height='{ph}' fill='none' stroke='#999'/>")
        pts = " ".join(f"{x0 + pw * i / max(len(values), 1):.1f},{y0 + ph * (1 - min(max(v / top, 0), 1)):.1f}"
                       for i, v in enumerate(values))
        svg.append(f"<polyline points='{pts}' stroke='#d62728' fill='none'/>")
        svg.append(f"<text x='10' y='{y0 + 10}'>{top:g}</text><text x='10' y='{y0 + ph}'>0</text>")

    least = [d / report["thickness"] if np.isfinite(d) else 1.0 for d in report["least"]]
    plot(40, "least distance of the cloth to anything, in thicknesses (1: none closer)", least, 1.0)
    plot(240, "stencils within the thickness per step", report["stencils"], max(max(report["stencils"]), 1))
    svg.append("</svg>")
    with open(os.path.join(out, "cloth.svg"), "w") as f:
        f.write("\n".join(svg) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cells", type=int, default=40)
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--out", default="cloth_scene_out")
    args = ap.parse_args()
    clock = time.perf_counter()
    r = simulate(args.cells, args.steps, out=args.out)
    n = len(r["kept"])
    bad = sum(r["intersecting"])
    print(f"{r['triangles']} triangles, {n} steps in {time.perf_counter() - clock:.1f} s: scene "
          f"queries {1e3 * r['scene_s'] / n:.2f} ms a step, the rest {1e3 * r['rest_s'] / n:.2f} ms; "
          f"{sum(k < 1 for k in r['kept'])} steps cut by an impact, {r['moved']} corners moved; "
          f"{bad} intersecting pairs at the ends of steps; frames and cloth.svg in {args.out}")
    if bad:
        raise SystemExit("the cloth intersected something")


if __name__ == "__main__":
    main()
