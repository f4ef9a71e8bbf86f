"""``python -m dvh check FILE [FILE2]``: a mesh's self-intersections, or two meshes'
intersections and their least distance, decided exactly, and whether each surface is closed
(what winding numbers and signed distances need); with ``--curves OUT.obj``, the curves along which they cross,
written as OBJ polylines. ``python -m dvh check --batch PATH...``: many meshes (files,
directories, globs), or the frames of one mesh with ``--frames``, each checked for
self-intersections and with ``--against FILE`` against that mesh, on several processes
(``--jobs N``) or a Dask cluster (``--dask ADDRESS``).

Exit status: 0 when nothing intersects, 1 when something does, 2 for a file or argument error
(with ``--batch``: when any input could not be checked).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import threading
import time
from typing import Callable, List, Tuple

import numpy as np

from . import (
    DvhError,
    Mesh,
    collide,
    distance,
    intersection_curves,
    proximity,
    self_collide,
    self_intersection_curves,
    self_proximity,
    version,
)
from ._meshfile import MeshFileError, read_mesh


class _Progress:
    """A one-line progress display on standard error (only when it is a terminal): the stage,
    a bar over the stages, and the time the current one has taken while it runs."""

    def __init__(self, stages: int, enabled: bool):
        self.stages, self.done, self.enabled = stages, 0, enabled

    def run(self, label: str, work: Callable):
        start = time.perf_counter()
        if not self.enabled:
            result = work()
        else:
            box: List = []
            # The library releases the GIL, so the display keeps moving while it works.
            t = threading.Thread(target=lambda: box.append(_capture(work)), daemon=True)
            t.start()
            while t.is_alive():
                self._draw(label, time.perf_counter() - start)
                t.join(0.1)
            ok, result = box[0]
            if not ok:
                self._clear()
                raise result
        self.done += 1
        elapsed = time.perf_counter() - start
        if self.enabled:
            self._draw(label, elapsed)
        return result, elapsed

    def _draw(self, label: str, seconds: float) -> None:
        width = 24
        filled = width * self.done // self.stages
        bar = "#" * filled + "-" * (width - filled)
        sys.stderr.write(f"\r[{bar}] {self.done}/{self.stages} {label:<36} {seconds:7.2f} s")
        sys.stderr.flush()

    def _clear(self) -> None:
        sys.stderr.write("\r" + " " * 80 + "\r")
        sys.stderr.flush()

    def finish(self) -> None:
        if self.enabled:
            self._clear()


def _capture(work: Callable) -> Tuple[bool, object]:
    try:
        return True, work()
    except BaseException as e:  # re-raised on the main thread
        return False, e


def _table(rows: List[Tuple[str, str]]) -> str:
    width = max(len(k) for k, _ in rows)
    return "\n".join(f"  {k:<{width}}  {v}" for k, v in rows)


def check(args: argparse.Namespace) -> int:
    files = args.files
    stages = 2 * len(files) + 1 + (len(files) == 2) + (args.curves is not None)
    progress = _Progress(stages, sys.stderr.isatty() and not args.json)
    meshes, rows = [], []
    try:
        for f in files:
            (pos, tris), t_read = progress.run(f"reading {f}", lambda f=f: read_mesh(f))
            mesh, t_build = progress.run(
                f"building {f}", lambda p=pos, t=tris: Mesh(p, t, volume=args.volume)
            )
            meshes.append(mesh)
            rows += [
                (f"{f}", f"{mesh.vertex_count} vertices, {mesh.triangle_count} triangles"),
                ("  read, build", f"{t_read * 1e3:.1f} ms, {t_build * 1e3:.1f} ms"),
                ("  closed", "yes" if mesh.is_closed else "no (an edge has no reverse)"),
            ]
        d = args.distance
        if len(meshes) == 1:
            what = "self-intersecting triangle pairs" if d is None else f"triangle pairs within {d}"
            query = (
                (lambda: self_collide(meshes[0], threads=args.threads, stats=True))
                if d is None
                else (lambda: self_proximity(meshes[0], d, threads=args.threads, stats=True))
            )
        else:
            what = "intersecting triangle pairs" if d is None else f"triangle pairs within {d}"
            query = (
                (lambda: collide(meshes[0], meshes[1], threads=args.threads, stats=True))
                if d is None
                else (lambda: proximity(meshes[0], meshes[1], d, threads=args.threads, stats=True))
            )
        (pairs, stats), t_query = progress.run("querying", query)
        apart = None
        if len(meshes) == 2:
            apart, t_distance = progress.run(
                "distance", lambda: distance(meshes[0], meshes[1], threads=args.threads)
            )
        curves = None
        if args.curves is not None:
            curves, t_curves = progress.run(
                "intersection curves",
                (lambda: self_intersection_curves(meshes[0], threads=args.threads))
                if len(meshes) == 1
                else (lambda: intersection_curves(meshes[0], meshes[1], threads=args.threads)),
            )
            curves.write_obj(args.curves)
    except (MeshFileError, OSError) as e:
        progress.finish()
        print(f"dvh check: {e}", file=sys.stderr)
        return 2
    except (DvhError, ValueError, TypeError) as e:
        progress.finish()
        print(f"dvh check: {files[len(meshes)] if len(meshes) < len(files) else 'query'}: {e}",
              file=sys.stderr)
        return 2
    progress.finish()
    if args.json:
        json.dump(
            {
                "files": files,
                "pairs": pairs.tolist(),
                "count": int(len(pairs)),
                "query_seconds": t_query,
                "triangle_tests": stats.triangle_tests,
                "closed": [m.is_closed for m in meshes],
                **({} if apart is None else {"distance": _distance_json(apart)}),
                **({} if curves is None else {"curves": _curves_json(curves, args.curves)}),
            },
            sys.stdout,
        )
        print()
        return 1 if len(pairs) else 0
    rows += [
        ("query", f"{t_query * 1e3:.1f} ms ({stats.triangle_tests} exact triangle tests)"),
        (what, f"{len(pairs)}"),
    ]
    if len(pairs):
        involved = [np.unique(pairs[:, 0])] + ([np.unique(pairs[:, 1])] if len(meshes) == 2 else [])
        if len(meshes) == 1:
            involved = [np.unique(pairs)]
        rows.append(("triangles involved", ", ".join(str(len(x)) for x in involved)))
    if apart is not None:
        rows.append(
            (
                "least distance",
                "0 (they intersect)"
                if apart.intersecting
                else f"{apart.distance:.17g}, triangles {apart.triangle_a} and {apart.triangle_b}"
                f" ({t_distance * 1e3:.1f} ms)",
            )
        )
    if curves is not None:
        c = _curves_json(curves, args.curves)
        rows += [
            (
                "intersection curves",
                f"{c['count']} ({c['closed']} closed), {c['segments']} segments, "
                f"{c['degenerate']} pairs without a segment, in {t_curves * 1e3:.1f} ms",
            ),
            ("  written to", args.curves),
        ]
    print(f"dvh {version()} check (exact)")
    print(_table(rows))
    if len(pairs):
        shown = pairs[: args.show]
        print(f"  first {len(shown)} of {len(pairs)} pairs (triangle indices, sorted):")
        for a, b in shown:
            print(f"    {a} {b}")
    return 1 if len(pairs) else 0


def _distance_json(d) -> dict:
    return {
        "distance": d.distance,
        "intersecting": d.intersecting,
        "triangles": [d.triangle_a, d.triangle_b],
        "closest": [d.closest_a.tolist(), d.closest_b.tolist()],
    }


def _curves_json(curves, path: str) -> dict:
    return {
        "file": path,
        "count": len(curves),
        "closed": int(curves.closed.sum()),
        "segments": len(curves.segments),
        "degenerate": len(curves.degenerate),
        "lengths": curves.lengths.tolist(),
    }


def batch(args: argparse.Namespace) -> int:
    from . import _batch

    start = time.perf_counter()
    try:
        rows, where = _batch.run(
            args.batch,
            against=args.against,
            frames=args.frames,
            jobs=args.jobs,
            dask=args.dask,
            volume=args.volume,
            threads=args.threads,
            progress=sys.stderr.isatty() and not (args.json or args.csv),
        )
    except (RuntimeError, OSError) as e:
        print(f"dvh check: {e}", file=sys.stderr)
        return 2
    seconds = time.perf_counter() - start
    if args.json:
        print(_batch.to_json(rows))
    elif args.csv:
        sys.stdout.write(_batch.to_csv(rows))
    else:
        print(_batch.summary(rows, args.against, args.frames, where, seconds))
    return _batch.exit_status(rows)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m dvh", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    c = sub.add_parser(
        "check",
        help="report a mesh's self-intersections, or two meshes' intersections, exactly",
        description="Reads OFF and OBJ (PLY, STL and more with meshio or trimesh installed) and "
        "reports the triangle pairs that intersect: of one mesh with itself (triangles that share "
        "a vertex or an edge count only where they also meet elsewhere), or of two meshes. "
        "Exit status 0: none; 1: some; 2: an error.",
    )
    c.add_argument("files", nargs="*", metavar="FILE", help="one or two mesh files")
    c.add_argument("--distance", type=float, help="report pairs within this distance instead")
    c.add_argument("--volume", default="aabb", choices=["aabb", "dvh", "sbv"])
    c.add_argument(
        "--threads",
        type=int,
        default=None,
        help="threads of each query; 0: every core (the default, but 1 per process with "
        "--jobs or --dask)",
    )
    c.add_argument("--show", type=int, default=10, help="pairs listed (default 10)")
    c.add_argument("--json", action="store_true", help="print the result as JSON")
    c.add_argument(
        "--curves",
        metavar="OUT.obj",
        help="also write the exact intersection curves to OUT.obj as polylines",
    )
    b = c.add_argument_group(
        "batch checks",
        "--batch PATH... checks every mesh the paths name (files, directories: their mesh files, "
        "globs), one result per input; the positional FILEs are then not given.",
    )
    b.add_argument("--batch", nargs="+", metavar="PATH", help="the meshes to check")
    b.add_argument("--against", metavar="FILE", help="also check each input against this mesh")
    b.add_argument(
        "--frames",
        action="store_true",
        help="the inputs, sorted by name, are frames of one mesh (same triangles; refit, not "
        "rebuilt), numbered from 0",
    )
    where = b.add_mutually_exclusive_group()
    where.add_argument("--jobs", type=int, default=1, metavar="N", help="processes here (default 1)")
    where.add_argument(
        "--dask", metavar="ADDRESS", help="run on the Dask cluster whose scheduler is at ADDRESS"
    )
    b.add_argument("--csv", action="store_true", help="print the results as CSV")
    args = parser.parse_args(argv)
    if args.batch is not None:
        if args.files:
            parser.error("--batch takes its inputs after it: no FILE before it")
        if args.curves is not None or args.distance is not None:
            parser.error("--curves and --distance are for one or two files, not --batch")
        if args.json and args.csv:
            parser.error("--json and --csv: choose one")
        if args.jobs < 1:
            parser.error(f"--jobs must be at least 1; got {args.jobs}")
        return batch(args)
    for flag, given in (("--against", args.against is not None), ("--frames", args.frames),
                        ("--dask", args.dask is not None), ("--csv", args.csv),
                        ("--jobs", args.jobs != 1)):
        if given:
            parser.error(f"{flag} goes with --batch")
    if not 1 <= len(args.files) <= 2:
        parser.error("check takes one or two files (or --batch PATH...)")
    if args.threads is None:
        args.threads = 0
    if args.curves is not None and args.distance is not None:
        parser.error("--curves is for intersections: it does not go with --distance")
    return check(args)


if __name__ == "__main__":
    try:
        status = main()
        sys.stdout.flush()
    except BrokenPipeError:
        # The reader stopped early (`| head`): not an error of the check. Standard output is
        # pointed at nothing so that the interpreter's own flush at exit stays quiet.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        status = 0
    sys.exit(status)
