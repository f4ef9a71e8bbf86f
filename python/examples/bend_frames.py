#!/usr/bin/env python3
"""Writes the frames of an animation to check: a mesh whose far half bends, frame by frame,
about a vertical axis through its middle, until it passes through the near half.

    python python/examples/bend_frames.py MESH OUT_DIR [--frames N] [--angle DEGREES]

Writes OUT_DIR/frame_0000.off ... (N frames, default 60; the far half turned from 0 to
``--angle`` degrees, default 170). Every frame has the mesh's triangles; only the positions
change, so ``python -m dvh check --batch OUT_DIR --frames`` refits one hierarchy instead of
building one per frame, and reports the frames from which the mesh meets itself.
"""

import argparse
import os

import numpy as np

import dvh


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mesh", help="an OFF or OBJ file (PLY, STL and more with meshio)")
    parser.add_argument("out", help="the directory to write the frames to")
    parser.add_argument("--frames", type=int, default=60)
    parser.add_argument("--angle", type=float, default=170.0)
    args = parser.parse_args()
    positions, triangles = dvh.read_mesh(args.mesh)
    positions = positions - positions.mean(axis=0)
    x, z = positions[:, 0], positions[:, 2]
    # The turn grows from nothing at the middle to its full angle a fifth of the way to the far
    # end, so the mesh bends without tearing.
    share = np.clip(x / (0.2 * x.max()), 0.0, 1.0)
    os.makedirs(args.out, exist_ok=True)
    for k in range(args.frames):
        turn = np.radians(args.angle) * k / max(args.frames - 1, 1) * share
        p = positions.copy()
        p[:, 0] = np.cos(turn) * x - np.sin(turn) * z
        p[:, 2] = np.sin(turn) * x + np.cos(turn) * z
        with open(os.path.join(args.out, f"frame_{k:04d}.off"), "w") as f:
            f.write(f"OFF\n{len(p)} {len(triangles)} 0\n")
            np.savetxt(f, p, fmt="%.17g")
            np.savetxt(f, np.hstack([np.full((len(triangles), 1), 3), triangles]), fmt="%d")
    print(f"wrote {args.frames} frames of {len(triangles)} triangles to {args.out}")


if __name__ == "__main__":
    main()
