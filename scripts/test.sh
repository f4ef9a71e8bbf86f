#!/usr/bin/env bash
# The whole test suite, as CI runs it. Installs the Debian packages it needs when missing.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/ensure-packages.sh libcgal-demo valgrind pkg-config

cargo fmt --all -- --check
cargo clippy --all-targets -- -D warnings
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --quiet
# Unit, property, integration and documentation tests; a missing mesh archive is a failure here.
DVH_REQUIRE_CGAL_DATA=1 cargo test
# The C ABI: C tests under sanitizers and valgrind, install, pkg-config, Python ctypes.
ctests/run.sh
# The cross-check against FCL, judged by CGAL: the short version (every scene kind, small meshes).
cross_check/run.sh | sed -n "/^Summary/,\$p"
# The main job must keep working.
cargo run --release --quiet --example demo -- --frames 4 >/dev/null
echo "all tests passed"
