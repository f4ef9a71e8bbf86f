#!/usr/bin/env bash
# Builds the Python package for distribution into DIR:
#   - a wheel for x86-64 Linux that installs on glibc 2.17 and later (manylinux_2_17, the
#     manylinux2014 policy: the distributions of the last decade), for every CPython 3 from 3.9
#     (the package calls the C library through cffi, so one py3-none wheel serves them all),
#     its library stripped of debug information, its licence and third-party notices in
#     dist-info/licenses; built with maturin and zig's C toolchain, which links against that
#     old glibc on a newer system without a manylinux container;
#   - the sdist (dvh-VERSION.tar.gz), which `pip install` builds where a Rust toolchain exists.
# auditwheel checks the wheel's platform tag; the script fails if it is not manylinux_2_28 or
# older.
#
#   scripts/wheel.sh DIR     about 3 minutes on 2 cores from a clean build
#
# The build tools (maturin, ziglang, auditwheel; pinned) are installed from PyPI into a virtual
# environment kept in target/wheel-tools.
set -euo pipefail
[ $# -eq 1 ] || {
    echo "usage: scripts/wheel.sh DIR" >&2
    exit 2
}
out=$(realpath -m "$1")
cd "$(dirname "$0")/.."
root=$PWD
python=${PYTHON:-python3}
if ! "$python" -c "import venv, ensurepip" 2>/dev/null; then
    scripts/ensure-packages.sh python3-venv
fi
tools="${CARGO_TARGET_DIR:-target}/wheel-tools"
if [ ! -x "$tools/bin/maturin" ] || [ ! -x "$tools/bin/auditwheel" ]; then
    rm -rf "$tools"
    "$python" -m venv "$tools"
    "$tools/bin/python" -m pip --disable-pip-version-check --quiet install --only-binary=:all: \
        maturin==1.16.0 ziglang==0.17.1 auditwheel==6.8.2
fi
tools=$(realpath "$tools")
mkdir -p "$out"
build=$(mktemp -d)
trap 'rm -rf "$build"' EXIT
cd python
PATH="$tools/bin:$PATH" maturin build --release --strip --zig --compatibility manylinux_2_17 \
    --out "$build" >&2
PATH="$tools/bin:$PATH" maturin sdist --out "$build" >&2
cd "$root"
wheel=$(ls "$build"/*.whl)
# The tag auditwheel finds from the symbols the library uses must be the one claimed, or older.
shown=$("$tools/bin/auditwheel" show "$wheel")
policy=$(grep -o 'manylinux_2_[0-9]*_x86_64' <<<"$shown" || true)
policy=${policy%%$'\n'*}
glibc_minor=$(sed -n 's/manylinux_2_\([0-9]*\)_x86_64/\1/p' <<<"$policy")
if [ -z "$glibc_minor" ] || [ "$glibc_minor" -gt 28 ]; then
    echo "$shown" >&2
    echo "the wheel's platform is ${policy:-unknown}, not manylinux_2_28 or older" >&2
    exit 1
fi
# No debug information left in the bundled library; the licences in the wheel.
"$python" - "$wheel" "$build/check" <<'PY'
import subprocess, sys, zipfile
wheel, into = sys.argv[1], sys.argv[2]
with zipfile.ZipFile(wheel) as z:
    names = z.namelist()
    libs = [n for n in names if n.startswith("dvh/_dvh/") and n.endswith(".so")]
    assert len(libs) == 1, f"expected one library in the wheel, found {libs}"
    path = z.extract(libs[0], into)
sections = subprocess.run(["readelf", "-S", path], check=True, capture_output=True, text=True).stdout
if ".debug_" in sections:
    sys.exit("the wheel's library still has debug sections")
for f in ("LICENSE-MIT", "LICENSE-APACHE", "THIRD-PARTY-LICENSES.txt"):
    if not any(n.endswith(f".dist-info/licenses/{f}") for n in names):
        sys.exit(f"the wheel lacks {f}")
PY
cp "$build"/*.whl "$build"/*.tar.gz "$out/"
size=$(du -k "$wheel" | cut -f1)
echo "$out/$(basename "$wheel"): $policy, ${size} kB, for CPython >= 3.9 (py3-none: one wheel for all)"
echo "$out/$(basename "$build"/*.tar.gz): the sdist"
