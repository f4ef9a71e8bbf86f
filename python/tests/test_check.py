"""`python -m dvh check` and the built-in mesh readers."""

import json
import re
import subprocess
import sys

import numpy as np
import pytest

import dvh
from dvh.__main__ import main
from dvh._meshfile import MeshFileError, read_obj, read_off
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


def test_check_reports_self_intersections_exactly(tmp_path, capsys):
    pos, tris = soup(40, seed=11)
    write_off(tmp_path / "soup.off", pos, tris)
    assert main(["check", str(tmp_path / "soup.off"), "--json"]) == 1
    out = json.loads(capsys.readouterr().out)
    want = {(i, j) for i, j in map(tuple, brute_collide(dvh, pos, tris, pos, tris).tolist()) if i < j}
    assert {tuple(p) for p in out["pairs"]} == want and out["count"] == len(want)


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
