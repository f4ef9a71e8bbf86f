#!/usr/bin/env bash
# The Python package's tests, as a new user meets it: the wheel built for distribution
# (scripts/wheel.sh: manylinux, stripped, with its licences) installed into a fresh virtual
# environment where no Rust toolchain is on the path, its Python dependencies from PyPI; then
# `import dvh`, the pytest suite (every query against brute force, the closest-point stencils
# also against IPC Toolkit's distance functions, `pip install ipctk`; the errors, the arrays,
# the GIL, `python -m dvh check` with its built-in readers and through meshio and trimesh, its
# batch checks on processes and on a local Dask cluster) and the README's Python example, run
# on the installed package from outside the repository.
#
#   scripts/python.sh          about 4 minutes from a clean build on 2 cores, a minute once built
#   scripts/python.sh --full   and the peer benchmarks' quick runs, without the peers (they are
#                              skipped when not installed), so that they keep working; and the
#                              sdist installed by pip into another fresh environment, built from
#                              source with cargo, as where no wheel fits (3 minutes more)
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
scripts/wheel.sh "$work/dist" 2>"$work/wheel.log" || {
    cat "$work/wheel.log" >&2
    exit 1
}
wheel=$(ls "$work"/dist/*.whl)
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
