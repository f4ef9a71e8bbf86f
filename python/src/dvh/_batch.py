"""``python -m dvh check --batch``: many meshes, or many frames of one mesh, checked in parallel
on this machine (``--jobs``) or on a Dask cluster (``--dask``), one result per input.

The work is cut into tasks (a file, or a run of consecutive frames) that a worker process runs
on its own: it reads its inputs from the paths (on a cluster, every worker must see them, as on
a shared file system), builds the mesh (a run of frames builds once and refits for the rest),
counts the self-intersecting triangle pairs and, with ``--against``, the pairs against that
mesh, which each worker reads once. An input that cannot be checked gets its reason and the
rest of the batch goes on.
"""

from __future__ import annotations

import csv
import glob
import io
import json
import os
import re
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from typing import Dict, Iterable, Iterator, List, Optional, Sequence, Tuple

import numpy as np

from ._meshfile import MeshFileError, read_mesh

#: Extensions a directory's files are taken by: what the built-in readers, meshio and trimesh
#: read as triangle meshes.
MESH_EXTENSIONS = (".off", ".obj", ".ply", ".stl", ".vtk", ".vtu", ".msh", ".glb", ".gltf", ".3mf")

#: The columns of a result, in ``--csv``'s order.
COLUMNS = ("file", "frame", "self_intersections", "intersections", "error")


def _natural(name: str) -> list:
    """A sort key that orders the digit runs of a name by their value: ``f2`` before ``f10``."""
    return [(0, int(t), t) if t.isdigit() else (1, 0, t) for t in re.split(r"(\d+)", name)]


def expand(paths: Sequence[str]) -> List[Tuple[str, Optional[str]]]:
    """The inputs the paths name, each with ``None`` or why it cannot be checked: a file as it
    is; a directory's mesh files, sorted; a glob's matches, sorted. A path that names nothing
    stays as an input with its reason, so that it is reported like any other failure."""
    out: List[Tuple[str, Optional[str]]] = []
    for p in paths:
        if os.path.isdir(p):
            found = sorted(
                (os.path.join(p, f) for f in os.listdir(p)
                 if f.lower().endswith(MESH_EXTENSIONS) and os.path.isfile(os.path.join(p, f))),
                key=_natural,
            )
            if not found:
                out.append((p, f"no mesh files in directory (looked for {', '.join(MESH_EXTENSIONS)})"))
            out += [(f, None) for f in found]
        elif os.path.exists(p):
            out.append((p, None))
        elif glob.has_magic(p):
            found = sorted((f for f in glob.glob(p) if os.path.isfile(f)), key=_natural)
            out += [(f, None) for f in found] or [(p, "the pattern matches no file")]
        else:
            out.append((p, "no such file or directory"))
    return out


def _row(file: str, frame: Optional[int], index: int) -> Dict[str, object]:
    # The keys with a leading underscore are for the report only: not in --json or --csv.
    return {
        "_index": index,
        "_triangles": None,
        "_seconds": None,
        "file": file,
        "frame": frame,
        "self_intersections": None,
        "intersections": None,
        "error": None,
    }


# Meshes a worker process has read for --against, by path: each is read and built once per
# process, whatever the number of tasks it runs.
_AGAINST: Dict[str, object] = {}


def _against_mesh(path: str, volume: str):
    from . import Mesh

    key = f"{volume}:{path}"
    if key not in _AGAINST:
        pos, tris = read_mesh(path)
        _AGAINST[key] = Mesh(pos, tris, volume=volume)
    return _AGAINST[key]


def _counts(mesh, against, threads: int, row: Dict[str, object]) -> None:
    from . import collide, self_collide

    row["self_intersections"] = int(len(self_collide(mesh, threads=threads)))
    if against is not None:
        row["intersections"] = int(len(collide(mesh, against, threads=threads)))


def _reason(e: BaseException) -> str:
    """What went wrong, in words: the library's and the readers' messages say it; an operating
    system's error or a foreign reader's gets its kind."""
    from . import DvhError

    if isinstance(e, (MeshFileError, DvhError, ValueError)):
        return str(e)
    return f"{type(e).__name__}: {e}"


def run_task(task: dict) -> List[Dict[str, object]]:
    """Checks one task's inputs in a worker: ``files`` (paths, with their frame numbers when
    ``frames`` is set), ``against`` (a path or ``None``), ``volume`` and ``threads``. Returns a
    result row per input. Never raises for a bad input: the row carries the reason."""
    from . import DvhError, Mesh

    frames, threads, volume = task["frames"], task["threads"], task["volume"]
    against = None
    against_error = None
    if task["against"] is not None:
        try:
            against = _against_mesh(task["against"], volume)
        except Exception as e:  # noqa: BLE001 (any reader's error, or the library's)
            against_error = f"--against {task['against']}: {_reason(e)}"
    rows = []
    mesh = None
    # What every frame must share: the first readable frame's vertex count and triangles (each
    # run of frames builds its own mesh, so its refits alone would not catch a run's first).
    first = task.get("first")
    for file, frame, index in task["files"]:
        row = _row(file, frame, index)
        rows.append(row)
        try:
            pos, tris = read_mesh(file)
        # meshio and trimesh raise errors of their own kinds on files they cannot read.
        except Exception as e:  # noqa: BLE001
            row["error"] = f"cannot read the mesh: {_reason(e)}"
            continue
        row["_triangles"] = len(tris)
        start = time.perf_counter()
        try:
            if frames:
                if first is not None:
                    (vertices, triangles), (first_file, first_frame) = first
                    if len(pos) != vertices:
                        raise ValueError(
                            f"{len(pos)} vertices, where frame {first_frame} ({first_file}) has "
                            f"{vertices}: frames must be one mesh"
                        )
                    if not np.array_equal(tris, triangles):
                        raise ValueError(
                            f"other triangles than frame {first_frame} ({first_file}): "
                            f"{len(tris)} against {len(triangles)}"
                            + ("" if len(tris) != len(triangles) else ", some indices differ")
                        )
                if mesh is None:
                    mesh = Mesh(pos, tris, volume=volume)
                else:
                    mesh.refit(pos)
                m = mesh
            else:
                m = Mesh(pos, tris, volume=volume)
            _counts(m, against, threads, row)
            row["_seconds"] = time.perf_counter() - start
        except (MeshFileError, OSError, DvhError, ValueError, TypeError) as e:
            row["error"] = _reason(e)
            continue
        if against_error is not None:
            row["error"] = against_error
            row["intersections"] = None
    return rows


def plan(
    inputs: List[Tuple[str, Optional[str]]],
    frames: bool,
    against: Optional[str],
    volume: str,
    threads: int,
    workers: int,
) -> Tuple[List[dict], List[Dict[str, object]]]:
    """The tasks for the inputs that can be read, and the rows of those that cannot (from
    :func:`expand`). Frames (the inputs in name order) are numbered from 0 and cut into runs of
    consecutive frames, a few per worker (each run builds the mesh once); other inputs are a
    task each."""
    failed: List[Dict[str, object]] = []
    numbered = [(f, (i if frames else None), i, why) for i, (f, why) in enumerate(inputs)]
    for f, k, i, why in numbered:
        if why is not None:
            row = _row(f, k, i)
            row["error"] = why
            failed.append(row)
    good = [(f, k, i) for f, k, i, why in numbered if why is None]
    base = {"frames": frames, "against": against, "volume": volume, "threads": threads}
    if not frames:
        return [dict(base, files=[x]) for x in good], failed
    # The vertex count and triangles every frame must have: the first readable frame's.
    first = None
    for f, k, _ in good:
        try:
            pos, tris = read_mesh(f)
        except Exception:  # noqa: BLE001 (any reader's error; its task reports it)
            continue
        first = ((len(pos), tris), (f, k))
        break
    runs = max(1, min(len(good), 4 * workers))
    size = -(-len(good) // runs) if good else 0
    tasks = [
        dict(base, files=good[i : i + size], first=first)
        for i in range(0, len(good), size or 1)
    ]
    return tasks, failed


class _Bar:
    """A one-line progress bar on standard error, drawn only when it is a terminal."""

    def __init__(self, total: int, enabled: bool):
        self.total, self.done, self.enabled = total, 0, enabled
        self.start = time.perf_counter()

    def advance(self, n: int) -> None:
        self.done += n
        if self.enabled:
            width = 30
            filled = width * self.done // max(self.total, 1)
            sys.stderr.write(
                f"\r[{'#' * filled}{'-' * (width - filled)}] {self.done}/{self.total} inputs "
                f"{time.perf_counter() - self.start:7.1f} s"
            )
            sys.stderr.flush()

    def close(self) -> None:
        if self.enabled:
            sys.stderr.write("\r" + " " * 70 + "\r")
            sys.stderr.flush()


def _local(tasks: List[dict], jobs: int, bar: _Bar) -> Iterator[List[Dict[str, object]]]:
    if jobs <= 1:
        for t in tasks:
            rows = run_task(t)
            bar.advance(len(rows))
            yield rows
        return
    import multiprocessing

    # Workers start afresh ("spawn"): a fork would copy a process whose thread pool does not
    # survive it.
    context = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=jobs, mp_context=context) as pool:
        for fut in as_completed([pool.submit(run_task, t) for t in tasks]):
            rows = fut.result()
            bar.advance(len(rows))
            yield rows


def _client(address: str):
    try:
        from distributed import Client
    except ImportError:
        raise RuntimeError(
            "--dask needs Dask's distributed package (pip install 'dvh[dask]' or "
            "pip install distributed)"
        ) from None
    try:
        return Client(address, timeout="20s")
    except (OSError, TimeoutError) as e:
        raise RuntimeError(f"--dask {address}: no scheduler answers there ({e})") from None


def _dask(client, tasks: List[dict], bar: _Bar) -> Iterator[List[Dict[str, object]]]:
    from distributed import as_completed as dask_completed

    # pure=False: two tasks with equal arguments are still two checks.
    futures = client.map(run_task, tasks, pure=False)
    for fut in dask_completed(futures):
        rows = fut.result()
        bar.advance(len(rows))
        yield rows


def run(
    paths: Sequence[str],
    against: Optional[str] = None,
    frames: bool = False,
    jobs: int = 1,
    dask: Optional[str] = None,
    volume: str = "aabb",
    threads: Optional[int] = None,
    progress: bool = False,
) -> Tuple[List[Dict[str, object]], str]:
    """Checks every input the paths name (see :func:`expand`) on ``jobs`` processes, or on the
    Dask cluster whose scheduler is at ``dask``. Returns a row per input, in the inputs' order
    (frames: in frame order): ``file``, ``frame`` (``None`` without ``frames``),
    ``self_intersections`` and ``intersections`` (counts, ``None`` when not checked), ``error``
    (``None`` or the reason), and for the report ``_triangles`` and ``_seconds`` (the time of
    the input's build or refit and queries); and where the work ran, in words."""
    inputs = expand(paths)
    if frames:
        inputs.sort(key=lambda x: _natural(x[0]))
    if threads is None:
        # One process per core already fills the machine: each query keeps to its own.
        threads = 0 if (dask is None and jobs <= 1) else 1
    bar = _Bar(len(inputs), progress)
    client = _client(dask) if dask is not None else None
    try:
        if client is not None:
            workers = max(1, len(client.scheduler_info()["workers"]))
            where = f"the Dask cluster at {dask} ({workers} workers)"
        else:
            workers = jobs
            where = f"{jobs} process{'es' if jobs > 1 else ''}"
        tasks, rows = plan(inputs, frames, against, volume, threads, workers)
        bar.advance(len(rows))
        source = _local(tasks, jobs, bar) if client is None else _dask(client, tasks, bar)
        for r in source:
            rows += r
    finally:
        bar.close()
        if client is not None:
            client.close()
    rows.sort(key=lambda r: r["_index"])
    return rows, where


def exit_status(rows: Iterable[Dict[str, object]]) -> int:
    """2 when an input could not be checked, else 1 when anything intersects, else 0."""
    rows = list(rows)
    if any(r["error"] is not None for r in rows):
        return 2
    hit = any((r["self_intersections"] or 0) > 0 or (r["intersections"] or 0) > 0 for r in rows)
    return 1 if hit else 0


def to_json(rows: List[Dict[str, object]]) -> str:
    return json.dumps([{k: r[k] for k in COLUMNS} for r in rows])


def to_csv(rows: List[Dict[str, object]]) -> str:
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(COLUMNS)
    for r in rows:
        w.writerow(["" if r[k] is None else r[k] for k in COLUMNS])
    return out.getvalue()


def summary(
    rows: List[Dict[str, object]],
    against: Optional[str],
    frames: bool,
    where: str,
    seconds: float,
    listed: int = 40,
) -> str:
    """The report for people: totals, then a table of the inputs (all of them up to ``listed``;
    beyond, those that intersect or failed)."""
    from . import version

    failed = [r for r in rows if r["error"] is not None]
    selfs = [r for r in rows if (r["self_intersections"] or 0) > 0]
    hit = lambda r: (  # noqa: E731
        r["error"] is not None or (r["self_intersections"] or 0) > 0 or (r["intersections"] or 0) > 0
    )
    totals = [("checked", len(rows) - len(failed)), ("self-intersecting", len(selfs))]
    if against is not None:
        hits = [r for r in rows if (r["intersections"] or 0) > 0]
        totals.append((f"intersecting {os.path.basename(against)}", len(hits)))
    totals.append(("could not be checked", len(failed)))
    label = max(len(k) for k, _ in totals)
    lines = [
        f"dvh {version()} check --batch (exact): {len(rows)} "
        f"{'frames' if frames else 'inputs'} on {where} in {seconds:.2f} s"
    ] + [f"  {k:<{label}}  {v}" for k, v in totals]
    shown = rows
    if len(rows) > listed:
        shown = [r for r in rows if hit(r)]
        lines.append(f"  the {len(shown)} inputs that intersect or failed:")
    if shown:
        width = min(max(len(str(r["file"])) for r in shown), 60)
        cell = lambda v: "-" if v is None else str(v)  # noqa: E731
        head = f"  {'file':<{width}}  {'frame':>5}  {'triangles':>9}  {'ms':>7}  {'self':>7}"
        head += f"  {'against':>7}" if against is not None else ""
        lines.append(head + "  error")
        for r in shown:
            ms = "-" if r["_seconds"] is None else f"{r['_seconds'] * 1e3:.1f}"
            line = f"  {str(r['file'])[-width:]:<{width}}  {cell(r['frame']):>5}"
            line += f"  {cell(r['_triangles']):>9}  {ms:>7}  {cell(r['self_intersections']):>7}"
            line += f"  {cell(r['intersections']):>7}" if against is not None else ""
            lines.append(line + f"  {r['error'] or ''}")
    return "\n".join(lines)
