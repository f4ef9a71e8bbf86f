"""Reading triangle meshes from files: OFF and OBJ built in; PLY, STL and the rest through
meshio or trimesh when one of them is installed."""

from __future__ import annotations

import os
from typing import List, Tuple

import numpy as np


class MeshFileError(ValueError):
    """A mesh file that cannot be read, with the file, the line and what was wrong."""


def _fan(face: List[int], out: List[List[int]]) -> None:
    for k in range(1, len(face) - 1):
        out.append([face[0], face[k], face[k + 1]])


def _off_of_triangles(text: str):
    """The common OFF file, read in bulk: an `OFF` header, three coordinates per vertex and
    triangles only, no comments or colours. `None` for anything else, which the line-by-line
    reader reads (and where it fails, says which line)."""
    if "#" in text:
        return None
    tok = text.split()
    if len(tok) < 4 or tok[0] != "OFF":
        return None
    try:
        nv, nf = int(tok[1]), int(tok[2])
        if nv < 0 or nf < 0 or len(tok) != 4 + 3 * nv + 4 * nf:
            return None
        # Each string converted as float() converts it: the nearest double, as the reader below.
        positions = np.array(tok[4 : 4 + 3 * nv], dtype=np.float64).reshape(-1, 3)
        faces = np.array(tok[4 + 3 * nv :], dtype=np.int64).reshape(-1, 4)
    except ValueError:
        return None
    if not np.all(faces[:, 0] == 3):
        return None
    return positions, faces[:, 1:].copy()


def read_off(path: str) -> Tuple[np.ndarray, np.ndarray]:
    """An OFF file's vertices and triangles (polygons split into fans; colours ignored)."""
    with open(path, "r", encoding="utf-8", errors="replace") as f:
        text = f.read()
    bulk = _off_of_triangles(text)
    if bulk is not None:
        return bulk
    lines = [(n, ln.split("#", 1)[0].split()) for n, ln in enumerate(text.splitlines(), 1)]
    lines = [(n, tok) for n, tok in lines if tok]
    if not lines or not lines[0][1][0].endswith("OFF"):
        raise MeshFileError(f"{path}: not an OFF file (no OFF header)")
    it = iter(lines)
    n, head = next(it)
    counts = head[1:] or next(it, (n, []))[1]
    try:
        nv, nf = int(counts[0]), int(counts[1])
    except (IndexError, ValueError):
        raise MeshFileError(f"{path}:{n}: expected vertex and face counts") from None
    positions = []
    for _ in range(nv):
        entry = next(it, None)
        if entry is None:
            raise MeshFileError(f"{path}: fewer vertices than the {nv} announced")
        n, tok = entry
        try:
            positions.append([float(x) for x in tok[:3]])
        except ValueError as e:
            raise MeshFileError(f"{path}:{n}: bad coordinate: {e}") from None
        if len(positions[-1]) != 3:
            raise MeshFileError(f"{path}:{n}: a vertex needs three coordinates")
    triangles: List[List[int]] = []
    for _ in range(nf):
        entry = next(it, None)
        if entry is None:
            raise MeshFileError(f"{path}: fewer faces than the {nf} announced")
        n, tok = entry
        try:
            k = int(tok[0])
            face = [int(x) for x in tok[1 : 1 + k]]
        except (IndexError, ValueError) as e:
            raise MeshFileError(f"{path}:{n}: bad face: {e}") from None
        if k < 3 or len(face) != k:
            raise MeshFileError(f"{path}:{n}: a face with {k} corners and {len(face)} indices")
        _fan(face, triangles)
    return np.array(positions, dtype=np.float64).reshape(-1, 3), np.array(
        triangles, dtype=np.int64
    ).reshape(-1, 3)


def read_obj(path: str) -> Tuple[np.ndarray, np.ndarray]:
    """An OBJ file's vertices (`v`) and faces (`f`, split into fans; negative indices count from
    the end; texture and normal indices ignored)."""
    positions: List[List[float]] = []
    triangles: List[List[int]] = []
    with open(path, "r", encoding="utf-8", errors="replace") as f:
        for n, line in enumerate(f, 1):
            tok = line.split("#", 1)[0].split()
            if not tok:
                continue
            try:
                if tok[0] == "v":
                    positions.append([float(x) for x in tok[1:4]])
                    if len(positions[-1]) != 3:
                        raise ValueError("a vertex needs three coordinates")
                elif tok[0] == "f":
                    face = []
                    for t in tok[1:]:
                        i = int(t.split("/", 1)[0])
                        face.append(i - 1 if i > 0 else len(positions) + i)
                    if len(face) < 3:
                        raise ValueError(f"a face with {len(face)} corners")
                    _fan(face, triangles)
            except ValueError as e:
                raise MeshFileError(f"{path}:{n}: {e}") from None
    return np.array(positions, dtype=np.float64).reshape(-1, 3), np.array(
        triangles, dtype=np.int64
    ).reshape(-1, 3)


def _welded(positions: np.ndarray, triangles: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """One vertex for each set of corners at exactly the same point. STL stores every triangle's
    corners apart: unwelded, every two neighbours would share no vertex and touch along their
    edge, which a self-intersection check must report."""
    if len(positions) == 0:
        return positions, triangles
    unique, inverse = np.unique(positions, axis=0, return_inverse=True)
    return unique, inverse.reshape(-1)[triangles]


def read_mesh(path: str) -> Tuple[np.ndarray, np.ndarray]:
    """Vertices and triangles of a mesh file, by its extension: OFF and OBJ with the built-in
    readers (which read every decimal exactly and name the line of any error); any other format
    through meshio or else trimesh, when one of them is installed, an STL file's corners at
    exactly the same point made one vertex. (The built-in readers come first for their formats:
    meshio 5.3 never returns from a truncated OFF file.)"""
    ext = os.path.splitext(path)[1].lower()
    if not os.path.isfile(path):
        raise MeshFileError(f"{path}: no such file")
    if ext == ".off":
        return read_off(path)
    if ext == ".obj":
        return read_obj(path)
    mesh = None
    try:
        import meshio  # type: ignore

        m = meshio.read(path)
        tris = [c.data for c in m.cells if c.type == "triangle"]
        if not tris:
            raise MeshFileError(f"{path}: no triangles")
        mesh = np.asarray(m.points, dtype=np.float64)[:, :3], np.vstack(tris).astype(np.int64)
    except ImportError:
        pass
    if mesh is None:
        try:
            import trimesh  # type: ignore

            t = trimesh.load(path, force="mesh", process=False)
            mesh = np.asarray(t.vertices, dtype=np.float64), np.asarray(t.faces, dtype=np.int64)
        except ImportError:
            pass
    if mesh is not None:
        return _welded(*mesh) if ext == ".stl" else mesh
    raise MeshFileError(
        f"{path}: {ext or 'this'} files need meshio or trimesh (pip install meshio); "
        "OFF and OBJ are read without them"
    )
