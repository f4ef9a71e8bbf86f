"""`python -m dvh check --batch`: many meshes or the frames of one, on processes here or on a
Dask cluster, each input's counts against the library's own queries and brute force, and every
bad input reported with its reason while the rest of the batch runs."""

import csv
import io
import json
import os
import re

import numpy as np
import pytest

import dvh
from dvh.__main__ import main
from dvh._batch import expand
from conftest import brute_collide, soup, uv_sphere
from test_check import write_obj, write_off


def batch_json(capsys, *argv):
    """The exit status and the JSON rows of `check --batch ARGV --json`."""
    status = main(["check", "--batch", *map(str, argv), "--json"])
    return status, json.loads(capsys.readouterr().out)


@pytest.fixture
def folder(tmp_path):
    """A folder of meshes: two that intersect themselves, one that does not, one with a NaN
    coordinate, one that is not a mesh file; and a sphere to check them against."""
    d = tmp_path / "meshes"
    d.mkdir()
    meshes = {
        "soup_a.off": soup(24, 1),
        "soup_b.obj": soup(30, 2, scale=0.5),
        "sphere.off": uv_sphere(8, 0.5, (0.6, 0.5, 0.5)),
    }
    write_off(d / "soup_a.off", *meshes["soup_a.off"])
    write_obj(d / "soup_b.obj", *meshes["soup_b.obj"])
    write_off(d / "sphere.off", *meshes["sphere.off"])
    pos, tris = uv_sphere(5)
    pos[3, 2] = np.nan
    write_off(d / "nan.off", pos, tris)
    (d / "garbage.off").write_text("this is not a mesh\n")
    (d / "notes.txt").write_text("not a mesh either, and not taken: no mesh extension\n")
    against = uv_sphere(10, 0.45, (0.5, 0.5, 0.5))
    write_off(tmp_path / "against.off", *against)
    return d, meshes, against


def test_expand_takes_files_directories_and_globs(tmp_path):
    for name in ("f10.off", "f2.off", "f1.obj", "skip.txt"):
        (tmp_path / name).write_text("")
    (tmp_path / "empty").mkdir()
    got = expand([str(tmp_path), str(tmp_path / "f1*.o*"), str(tmp_path / "none*.off"),
                  str(tmp_path / "missing.off"), str(tmp_path / "empty")])
    names = [(os.path.basename(f), why) for f, why in got]
    # Directory entries in name order, digit runs by value; the glob's matches; then each path
    # that names nothing, with its reason.
    assert names[:3] == [("f1.obj", None), ("f2.off", None), ("f10.off", None)]
    assert names[3:5] == [("f1.obj", None), ("f10.off", None)]
    assert names[5][0] == "none*.off" and "matches no file" in names[5][1]
    assert names[6][0] == "missing.off" and "no such file" in names[6][1]
    assert names[7][0] == "empty" and "no mesh files" in names[7][1]


def test_a_folder_is_checked_file_by_file(folder, capsys):
    d, meshes, against = folder
    status, rows = batch_json(capsys, d, "--against", d.parent / "against.off")
    assert status == 2  # two inputs could not be checked
    by = {os.path.basename(r["file"]): r for r in rows}
    assert sorted(by) == ["garbage.off", "nan.off", "soup_a.off", "soup_b.obj", "sphere.off"]
    assert all(r["frame"] is None for r in rows)
    for name, (pos, tris) in meshes.items():
        r = by[name]
        assert r["error"] is None
        mesh = dvh.Mesh(pos, tris)
        assert r["self_intersections"] == len(dvh.self_collide(mesh))
        assert r["intersections"] == len(brute_collide(dvh, pos, tris, *against))
    assert by["soup_a.off"]["self_intersections"] > 0 and by["sphere.off"]["self_intersections"] == 0
    assert by["sphere.off"]["intersections"] > 0
    nan = by["nan.off"]
    assert nan["self_intersections"] is None and nan["intersections"] is None
    assert "vertex 3" in nan["error"] and "NaN" in nan["error"]
    assert by["garbage.off"]["error"].startswith("cannot read the mesh")


def test_exit_status_says_what_was_found(tmp_path, capsys):
    write_off(tmp_path / "clean.off", *uv_sphere(6))
    assert main(["check", "--batch", str(tmp_path / "clean.off"), "--json"]) == 0
    write_off(tmp_path / "hits.off", *soup(20, 3))
    assert main(["check", "--batch", str(tmp_path / "*.off"), "--json"]) == 1
    assert main(["check", "--batch", str(tmp_path), str(tmp_path / "gone.off"), "--json"]) == 2
    rows = json.loads(capsys.readouterr().out.splitlines()[-1])
    assert rows[-1]["error"] == "no such file or directory"
    assert [r["error"] for r in rows[:-1]] == [None, None]


def frames_of(tmp_path, count=12):
    """A sphere squeezed frame by frame until its cap passes through the other side, written as
    frame files named without zero padding (so that name order is not text order)."""
    pos, tris = uv_sphere(10)
    d = tmp_path / "frames"
    d.mkdir()
    frames = []
    for k in range(count):
        q = pos.copy()
        q[q[:, 2] > 0.5, 2] -= 0.25 * k
        frames.append(q)
        write_off(d / f"frame{k}.off", q, tris)
    return d, frames, tris


def test_frames_are_refit_in_name_order_and_match_separate_checks(tmp_path, capsys):
    d, frames, tris = frames_of(tmp_path)
    status, rows = batch_json(capsys, d, "--frames")
    assert [r["frame"] for r in rows] == list(range(len(frames)))
    assert [os.path.basename(r["file"]) for r in rows] == [f"frame{k}.off" for k in range(len(frames))]
    expected = [len(dvh.self_collide(dvh.Mesh(p, tris))) for p in frames]
    assert [r["self_intersections"] for r in rows] == expected
    assert expected[0] == 0 and max(expected) > 0 and status == 1


def test_bad_frames_are_reported_and_the_rest_still_run(tmp_path, capsys):
    d, frames, tris = frames_of(tmp_path, 8)
    # Frame 3: one vertex more; frame 5: other triangles; frame 6: a NaN; frame 7 unreadable.
    write_off(d / "frame3.off", np.vstack([frames[3], [[9.0, 9.0, 9.0]]]), tris)
    write_off(d / "frame5.off", frames[5], tris[::-1])
    bad = frames[6].copy()
    bad[7, 0] = np.nan
    write_off(d / "frame6.off", bad, tris)
    (d / "frame7.off").write_text("OFF\n")
    for jobs in ("1", "2"):
        status, rows = batch_json(capsys, d, "--frames", "--jobs", jobs)
        assert status == 2
        errors = {r["frame"]: r["error"] for r in rows if r["error"] is not None}
        assert sorted(errors) == [3, 5, 6, 7], errors
        assert "vertices, where frame 0" in errors[3]
        assert "other triangles than frame 0" in errors[5]
        assert "vertex 7" in errors[6] and "NaN" in errors[6]
        assert errors[7].startswith("cannot read the mesh")
        good = [r for r in rows if r["error"] is None]
        assert [r["self_intersections"] for r in good] == [
            len(dvh.self_collide(dvh.Mesh(frames[r["frame"]], tris))) for r in good
        ]


def test_processes_give_the_same_rows_as_one(folder, tmp_path, capsys):
    d, _, _ = folder
    fd, _, _ = frames_of(tmp_path)
    for args in ([d, "--against", d.parent / "against.off"], [fd, "--frames"]):
        one = batch_json(capsys, *args)
        assert batch_json(capsys, *args, "--jobs", "2") == one
        assert batch_json(capsys, *args, "--jobs", "3", "--threads", "2") == one


def test_csv_has_the_json_columns(folder, capsys):
    d, _, _ = folder
    _, rows = batch_json(capsys, d)
    assert main(["check", "--batch", str(d), "--csv"]) == 2
    table = list(csv.reader(io.StringIO(capsys.readouterr().out)))
    assert table[0] == ["file", "frame", "self_intersections", "intersections", "error"]
    assert len(table) == len(rows) + 1
    for r, line in zip(rows, table[1:]):
        cell = lambda v: "" if v is None else str(v)  # noqa: E731
        assert line == [cell(r[k]) for k in table[0]]


def test_the_report_for_people_lists_findings(folder, capsys):
    d, _, _ = folder
    assert main(["check", "--batch", str(d), "--against", str(d.parent / "against.off")]) == 2
    out = capsys.readouterr().out
    assert "check --batch (exact): 5 inputs on 1 process" in out
    assert re.search(r"could not be checked +2\n", out) and re.search(r"self-intersecting +2\n", out)
    assert re.search(r"intersecting against.off +3\n", out)
    assert "garbage.off" in out and "cannot read the mesh" in out


def test_batch_arguments_are_checked(tmp_path, capsys):
    write_off(tmp_path / "s.off", *uv_sphere(5))
    s = str(tmp_path / "s.off")
    for argv in (
        ["check", s, "--batch", s],
        ["check", s, "--frames"],
        ["check", s, "--jobs", "2"],
        ["check", "--batch", s, "--jobs", "0"],
        ["check", "--batch", s, "--jobs", "2", "--dask", "tcp://127.0.0.1:1"],
        ["check", "--batch", s, "--json", "--csv"],
        ["check", "--batch", s, "--curves", str(tmp_path / "c.obj")],
        ["check"],
    ):
        with pytest.raises(SystemExit) as e:
            main(argv)
        assert e.value.code == 2, argv
    capsys.readouterr()


def test_a_dask_cluster_gives_the_same_rows(folder, tmp_path, capsys):
    if os.environ.get("DVH_REQUIRE_DASK"):
        import distributed
    else:
        distributed = pytest.importorskip("distributed")
    d, _, _ = folder
    fd, _, _ = frames_of(tmp_path)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        for args in ([d, "--against", d.parent / "against.off"], [fd, "--frames"]):
            here = batch_json(capsys, *args)
            assert batch_json(capsys, *args, "--dask", cluster.scheduler_address) == here
        assert main(["check", "--batch", str(fd), "--frames", "--dask", cluster.scheduler_address]) == 1
        assert "on the Dask cluster at" in capsys.readouterr().out
