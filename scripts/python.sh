#!/usr/bin/env bash
# The Python package's tests, as a new user meets it: a wheel installed into a fresh virtual
# environment where no Rust toolchain is on the path, its Python dependencies from PyPI; then
# `import dvh`, the pytest suite (every query against brute force, the closest-point stencils
# also against IPC Toolkit's distance functions, `pip install ipctk`; the errors, the arrays,
# the GIL, `python -m dvh check` with its built-in readers and through meshio and trimesh, its
# batch checks on processes and on a local Dask cluster) and the README's Python example, run
# on the installed package from outside the repository.
#
#   scripts/python.sh          the wheel packed from the release library `scripts/install.sh`
#                              builds (scripts/local_wheel.py: nothing compiled again, so in the
#                              test suite, after the C tests, it costs only the installs and the
#                              tests: about 1.5 minutes on 2 cores)
#   scripts/python.sh --full   the distribution wheel instead (scripts/wheel.sh: manylinux,
#                              stripped, with its licences; a second release build), checked to
#                              hold the same files as the packed one but for the library; the
#                              peer benchmarks' quick runs, without the peers (they are skipped
#                              when not installed), so that they keep working; and the sdist
#                              installed by pip into another fresh environment, built from source
#                              with cargo, as where no wheel fits (about 6 minutes more)
#
# PYTHON names the interpreter (default python3); DVH_PYTHON_VENV keeps the environment in that
# directory instead of a temporary one.
set -euo pipefail
full=false
[ "${1:-}" = "--full" ] && full=true
cd "$(dirname "$0")/.."
root=$PWD
python=${PYTHON:-python3}
if ! "$python" -c "import venv, ensurepip" 2>/dev/null; then
    scripts/ensure-packages.sh python3-venv
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
venv=${DVH_PYTHON_VENV:-$work/venv}
rm -rf "$venv"
"$python" -m venv "$venv"
pip=("$venv/bin/python" -m pip --disable-pip-version-check --quiet)
# cffi (a dependency of the package) makes the packed wheel's declarations; tomli reads its
# metadata where Python has no tomllib.
"${pip[@]}" install --only-binary=:all: cffi 'tomli; python_version < "3.11"'
./scripts/install.sh "$work/prefix" >/dev/null
"$venv/bin/python" scripts/local_wheel.py "$work/prefix/lib/libdvh.so" "$work/packed" >/dev/null
wheel=$(ls "$work"/packed/*.whl)
if $full; then
    scripts/wheel.sh "$work/dist" 2>"$work/wheel.log" || {
        cat "$work/wheel.log" >&2
        exit 1
    }
    # The two routes load the same code: every file of the one is the other's, byte for byte,
    # but the library (the same crate, linked by zig for manylinux and stripped) and the files
    # that describe the wheel itself.
    "$venv/bin/python" - "$wheel" "$work"/dist/*.whl <<'PY'
import sys, zipfile
packed, distributed = (zipfile.ZipFile(p) for p in sys.argv[1:])
own = lambda n: n.endswith((".dist-info/WHEEL", ".dist-info/RECORD", "/lib_dvh.so")) or "/sboms/" in n
a = {n: packed.read(n) for n in packed.namelist() if not own(n)}
b = {n: distributed.read(n) for n in distributed.namelist() if not own(n)}
if a.keys() != b.keys():
    sys.exit(f"the wheels' files differ: {sorted(a.keys() ^ b.keys())}")
differ = sorted(n for n in a if a[n] != b[n])
if differ:
    sys.exit(f"the packed and the distribution wheel differ in {differ}")
PY
    wheel=$(ls "$work"/dist/*.whl)
fi
# Only the system's directories on the path (rustup's cargo and rustc are not among them), and
# binaries only: nothing can be built, so the wheel must install as it is.
clean_path="$venv/bin:/usr/local/bin:/usr/bin:/bin"
(cd "$work" && PATH="$clean_path" "${pip[@]}" install --only-binary=:all: "$wheel[test]")
# IPC Toolkit's distance functions: the closest-point tests' second, floating-point reference.
"${pip[@]}" install ipctk
export DVH_REQUIRE_IPCTK=1
# The readers `python -m dvh check` uses for PLY, STL and the rest, each tested; pinned pure-Python
# wheels, so that the install is a download, never a build.
"${pip[@]}" install --only-binary=:all: meshio==5.3.5 trimesh==5.2.0
export DVH_REQUIRE_READERS=1
# Dask's distributed, for the batch checker's --dask (the tests start a local cluster).
"${pip[@]}" install --only-binary=:all: distributed==2026.8.0
export DVH_REQUIRE_DASK=1
# From outside the repository, so that only the installed package can be imported.
cd "$work"
"$venv/bin/python" -c "import dvh, sys; print('dvh', dvh.__version__, 'for Python', sys.version.split()[0])"
"$venv/bin/python" -m pytest -q -p no:cacheprovider "$root/python/tests"
awk '/^```python$/{on=1; next} /^```$/{on=0} on' "$root/README.md" > readme.py
test -s readme.py
"$venv/bin/python" readme.py >/dev/null
if $full; then
    "$venv/bin/python" "$root/python/bench/peers.py" --quick >/dev/null
    # The scene's step queries against the pairwise ones and ipctk's step (it fails on a mismatch).
    "$venv/bin/python" "$root/python/bench/scene_peers.py" --quick >/dev/null
    # Intersection curves on deforming CGAL demo meshes (skipped without libcgal-demo; against
    # trueform's points when it is installed: it fails on a mismatch).
    "$venv/bin/python" "$root/python/bench/curves_peers.py" --quick >/dev/null
    # Point queries of a deforming mesh (a sphere stands in without libcgal-demo; it checks
    # that the closest points, winding numbers and signed distances agree).
    "$venv/bin/python" "$root/python/bench/points_peers.py" --quick --points 20000 >/dev/null
    # The sdist, as pip builds it where no wheel fits: from source, with cargo.
    "$python" -m venv "$work/sdist-venv"
    sdist=$(ls "$work"/dist/*.tar.gz)
    (cd "$work" && "$work/sdist-venv/bin/python" -m pip --disable-pip-version-check --quiet install "$sdist")
    (cd "$work" && "$work/sdist-venv/bin/python" -c "
import numpy as np, dvh
tri = np.array([[0, 1, 2]])
a = dvh.Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float), tri)
b = dvh.Mesh(np.array([[0.2, 0.2, -1], [0.2, 0.2, 1], [1, 1, 0]], float), tri)
assert dvh.collide(a, b).tolist() == [[0, 0]], 'the sdist build does not find the crossing pair'
print('sdist build: dvh', dvh.__version__)")
fi
echo "Python package tests passed"
