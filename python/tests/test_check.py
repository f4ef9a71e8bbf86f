"""`python -m dvh check` and its mesh readers: the built-in OFF and OBJ ones, meshio and trimesh."""

import importlib
import json
import os
import re
import subprocess
import sys

import numpy as np
import pytest

import dvh
from dvh.__main__ import main
from dvh._meshfile import MeshFileError, read_mesh, read_obj, read_off
from conftest import brute_collide, soup, uv_sphere


def write_off(path, pos, tris, quads=False):
    with open(path, "w") as f:
        f.write(f"OFF\n# a comment\n{len(pos)} {len(tris)} 0\n")
        for p in pos:
            f.write(" ".join(repr(float(x)) for x in p) + "\n")
        for t in tris:
            f.write("3 " + " ".join(map(str, t)) + "\n")


def write_obj(path, pos, tris):
    with open(path, "w") as f:
        for p in pos:
            f.write("v " + " ".join(repr(float(x)) for x in p) + "\n")
        for t in tris:
            f.write("f " + " ".join(f"{i + 1}/{i + 1}" for i in t) + "\n")


def write_ply(path, pos, tris):
    """An ASCII PLY file, each coordinate written as the shortest decimal that reads back exactly."""
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\ncomment written by dvh's tests\n")
        f.write(f"element vertex {len(pos)}\nproperty double x\nproperty double y\nproperty double z\n")
        f.write(f"element face {len(tris)}\nproperty list uchar int vertex_indices\nend_header\n")
        for p in pos:
            f.write(" ".join(repr(float(x)) for x in p) + "\n")
        for t in tris:
            f.write("3 " + " ".join(map(str, t)) + "\n")


def write_stl(path, pos, tris):
    """A binary STL file: every triangle's corners as float32, so `pos` must hold float32 values."""
    assert np.array_equal(pos.astype(np.float32), pos)
    facets = np.zeros(len(tris), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    facets["v"] = pos[tris]
    with open(path, "wb") as f:
        f.write(b"written by dvh's tests".ljust(80, b" "))
        f.write(np.uint32(len(tris)).tobytes())
        f.write(facets.tobytes())


READERS = ("meshio", "trimesh")


@pytest.fixture(params=("built-in",) + READERS)
def reader(request, monkeypatch):
    """The reader `read_mesh` is left to: the other readers hidden. Under scripts/python.sh
    (DVH_REQUIRE_READERS set) a missing meshio or trimesh is a failure, elsewhere a skip."""
    name = request.param
    if name != "built-in":
        if os.environ.get("DVH_REQUIRE_READERS"):
            try:
                importlib.import_module(name)
            except ImportError as e:
                pytest.fail(f"{name} is required (DVH_REQUIRE_READERS is set): {e}")
        else:
            pytest.importorskip(name)
    for other in READERS:
        if other != name:
            # A None entry makes `import other` raise ImportError.
            monkeypatch.setitem(sys.modules, other, None)
    return name


def spy_on(reader, monkeypatch):
    """Counts the calls of `reader`'s load function, to show `read_mesh` went through it."""
    calls = []
    if reader == "built-in":
        return calls
    module = importlib.import_module(reader)
    name = "read" if reader == "meshio" else "load"
    real = getattr(module, name)

    def counted(*args, **kwargs):
        calls.append(args[0])
        return real(*args, **kwargs)

    monkeypatch.setattr(module, name, counted)
    return calls


def check_json(capsys, *paths):
    status = main(["check", *map(str, paths), "--json"])
    out = json.loads(capsys.readouterr().out)
    assert status == (1 if out["count"] else 0) and out["count"] == len(out["pairs"])
    return {tuple(p) for p in out["pairs"]}


def test_readers_round_trip(tmp_path):
    pos, tris = uv_sphere(6)
    write_off(tmp_path / "s.off", pos, tris)
    write_obj(tmp_path / "s.obj", pos, tris)
    for read, name in ((read_off, "s.off"), (read_obj, "s.obj")):
        p, t = read(str(tmp_path / name))
        assert np.array_equal(p, pos) and np.array_equal(t, tris)
    (tmp_path / "quad.off").write_text("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n")
    assert read_off(str(tmp_path / "quad.off"))[1].tolist() == [[0, 1, 2], [0, 2, 3]]
    (tmp_path / "bad.off").write_text("OFF\n3 1 0\n0 0 0\n1 0 x\n0 1 0\n3 0 1 2\n")
    with pytest.raises(MeshFileError, match=r"bad.off:4: bad coordinate"):
        read_off(str(tmp_path / "bad.off"))


def dyadic_soup(count, seed):
    """A soup whose coordinates float32 holds exactly, so that an STL file keeps them."""
    pos, tris = soup(count, seed)
    return np.round(pos * 1024) / 1024, tris


def test_check_reports_self_intersections_exactly(tmp_path, capsys, reader, monkeypatch):
    pos, tris = dyadic_soup(40, seed=11)
    want = {(i, j) for i, j in map(tuple, brute_collide(dvh, pos, tris, pos, tris).tolist()) if i < j}
    assert want
    files = [tmp_path / "soup.off", tmp_path / "soup.obj"]
    write_off(files[0], pos, tris)
    write_obj(files[1], pos, tris)
    if reader != "built-in":
        files += [tmp_path / "soup.ply", tmp_path / "soup.stl"]
        write_ply(files[2], pos, tris)
        write_stl(files[3], pos, tris)
    calls = spy_on(reader, monkeypatch)
    for f in files:
        assert check_json(capsys, f) == want, f
        # Every triangle, corner by corner, whether or not a reader merges repeated vertices.
        p, t = read_mesh(str(f))
        assert np.array_equal(p[t], pos[tris]), f
    # OFF and OBJ always through the built-in readers; the other formats through `reader`.
    assert len(calls) == 2 * (len(files) - 2)


def test_stl_corners_at_one_point_are_one_vertex(tmp_path, capsys, reader):
    """STL keeps each triangle's corners apart; read as they are, neighbours would share no
    vertex and touch along every edge. Welded, a closed sphere does not meet itself."""
    if reader == "built-in":
        pytest.skip("STL needs meshio or trimesh")
    pos, tris = uv_sphere(8)
    pos = pos.astype(np.float32).astype(np.float64)
    write_stl(tmp_path / "sphere.stl", pos, tris)
    p, t = read_mesh(str(tmp_path / "sphere.stl"))
    assert len(p) == len(pos) and np.array_equal(p[t], pos[tris])
    assert check_json(capsys, tmp_path / "sphere.stl") == set()


def test_check_two_meshes_through_every_reader(tmp_path, capsys, reader, monkeypatch):
    (pa, ta), (pb, tb) = dyadic_soup(40, seed=12), dyadic_soup(40, seed=13)
    want = {tuple(p) for p in brute_collide(dvh, pa, ta, pb, tb).tolist()}
    assert want
    write_off(tmp_path / "a.off", pa, ta)
    write_off(tmp_path / "b.off", pb, tb)
    if reader == "built-in":
        files = [tmp_path / "a.off", tmp_path / "b.off"]
    else:
        write_ply(tmp_path / "a.ply", pa, ta)
        write_stl(tmp_path / "b.stl", pb, tb)
        files = [tmp_path / "a.ply", tmp_path / "b.stl"]
    calls = spy_on(reader, monkeypatch)
    assert check_json(capsys, *files) == want
    assert len(calls) == (0 if reader == "built-in" else 2)
    # The other way round: the pairs swap.
    assert check_json(capsys, *files[::-1]) == {(j, i) for i, j in want}


def test_a_format_without_its_reader_is_an_error(tmp_path, capsys, monkeypatch):
    for name in READERS:
        monkeypatch.setitem(sys.modules, name, None)
    pos, tris = uv_sphere(5)
    write_ply(tmp_path / "s.ply", pos, tris)
    assert main(["check", str(tmp_path / "s.ply")]) == 2
    assert "need meshio or trimesh" in capsys.readouterr().err


def test_check_two_meshes_and_a_clean_one(tmp_path, capsys):
    pa, ta = uv_sphere(8)
    pb, tb = uv_sphere(8, centre=(1.0, 0.0, 0.0))
    write_off(tmp_path / "a.off", pa, ta)
    write_obj(tmp_path / "b.obj", pb, tb)
    assert main(["check", str(tmp_path / "a.off")]) == 0
    assert re.search(r"self-intersecting triangle pairs\s+0\n", capsys.readouterr().out)
    assert main(["check", str(tmp_path / "a.off"), str(tmp_path / "b.obj")]) == 1
    out = capsys.readouterr().out
    n = len(dvh.collide(dvh.Mesh(pa, ta), dvh.Mesh(pb, tb)))
    assert re.search(rf"\n  intersecting triangle pairs\s+{n}\n", out) and n > 0
    assert re.search(r"least distance\s+0 \(they intersect\)", out)
    assert re.search(r"closed\s+yes", out)


def test_check_reports_the_least_distance_and_closedness(tmp_path, capsys):
    pa, ta = uv_sphere(8)
    pb, tb = uv_sphere(8, centre=(3.0, 0.0, 0.0))
    write_off(tmp_path / "a.off", pa, ta)
    write_off(tmp_path / "b.off", pb, tb)
    # An open surface: the sphere without its last triangle.
    write_off(tmp_path / "open.off", pa, ta[:-1])
    assert main(["check", str(tmp_path / "a.off"), str(tmp_path / "b.off"), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    want = dvh.distance(dvh.Mesh(pa, ta), dvh.Mesh(pb, tb))
    assert out["distance"]["distance"] == want.distance and not out["distance"]["intersecting"]
    assert out["distance"]["triangles"] == [want.triangle_a, want.triangle_b]
    assert out["closed"] == [True, True] and 0.9 < want.distance < 1.1
    assert main(["check", str(tmp_path / "open.off"), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["closed"] == [False] and "distance" not in out
    assert main(["check", str(tmp_path / "a.off"), str(tmp_path / "b.off")]) == 0
    assert re.search(rf"least distance\s+{want.distance:.17g}, triangles", capsys.readouterr().out)


def test_check_writes_the_intersection_curves(tmp_path, capsys):
    pa, ta = uv_sphere(12)
    pb, tb = uv_sphere(9, 0.8, centre=(0.9, 0.1, 0.05))
    write_off(tmp_path / "a.off", pa, ta)
    write_off(tmp_path / "b.off", pb, tb)
    out_obj = tmp_path / "curves.obj"
    args = ["check", str(tmp_path / "a.off"), str(tmp_path / "b.off"), "--curves", str(out_obj)]
    assert main(args) == 1
    out = capsys.readouterr().out
    curves = dvh.intersection_curves(dvh.Mesh(pa, ta), dvh.Mesh(pb, tb))
    assert re.search(rf"intersection curves\s+{len(curves)} \({len(curves)} closed\), "
                     rf"{len(curves.segments)} segments", out)
    lines = [line for line in out_obj.read_text().splitlines() if line.startswith("l ")]
    assert len(lines) == len(curves) > 0
    assert main(args + ["--json"]) == 1
    report = json.loads(capsys.readouterr().out)
    assert report["curves"]["count"] == len(curves)
    assert report["curves"]["segments"] == len(curves.segments)
    assert np.allclose(report["curves"]["lengths"], curves.lengths)
    # A mesh alone: its self-intersection curves (none for a sphere: an empty file).
    assert main(["check", str(tmp_path / "a.off"), "--curves", str(out_obj)]) == 0
    assert "intersection curves" in capsys.readouterr().out
    assert not [line for line in out_obj.read_text().splitlines() if line.startswith("l ")]
    with pytest.raises(SystemExit):
        main(args + ["--distance", "0.1"])
    assert "does not go with --distance" in capsys.readouterr().err


def test_check_errors_exit_with_2(tmp_path, capsys):
    assert main(["check", str(tmp_path / "missing.off")]) == 2
    assert "no such file" in capsys.readouterr().err
    pos, tris = uv_sphere(5)
    tris[2, 1] = 999
    write_off(tmp_path / "broken.off", pos, tris)
    assert main(["check", str(tmp_path / "broken.off")]) == 2
    assert "vertex index 999" in capsys.readouterr().err


def test_module_runs_as_a_command(tmp_path):
    pos, tris = uv_sphere(6)
    write_off(tmp_path / "s.off", pos, tris)
    r = subprocess.run(
        [sys.executable, "-m", "dvh", "check", str(tmp_path / "s.off")], capture_output=True, text=True
    )
    assert r.returncode == 0 and "check (exact)" in r.stdout, r.stderr
