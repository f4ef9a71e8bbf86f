#!/usr/bin/env bash
# The Python package's tests, as a new user meets it: a fresh virtual environment, then
# `pip install ./python` (which builds the library with cargo and bundles it in the wheel; the
# package's Python dependencies, and maturin and cffi for the build, come from PyPI), then
# `import dvh`, the pytest suite (every query against brute force, the closest-point stencils
# also against IPC Toolkit's distance functions, `pip install ipctk`; the errors, the arrays,
# the GIL, `python -m dvh check` with its built-in readers and through meshio and trimesh) and the
# README's Python example, run on the installed package.
#
#   scripts/python.sh          about 3 minutes from a clean build on 2 cores, 40 seconds once built
#   scripts/python.sh --full   and the peer benchmark's quick run, without the peers (they are
#                              skipped when not installed), so that it keeps working; 20 s more
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
"${pip[@]}" install "./python[test]"
# IPC Toolkit's distance functions: the closest-point tests' second, floating-point reference.
"${pip[@]}" install ipctk
export DVH_REQUIRE_IPCTK=1
# The readers `python -m dvh check` uses for PLY, STL and the rest, each tested; pinned pure-Python
# wheels, so that the install is a download, never a build.
"${pip[@]}" install --only-binary=:all: meshio==5.3.5 trimesh==5.2.0
export DVH_REQUIRE_READERS=1
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
fi
echo "Python package tests passed"
