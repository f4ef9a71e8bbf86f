#!/usr/bin/env bash
# The whole test suite, as CI runs it. Installs the Debian packages it needs when missing.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/ensure-packages.sh libcgal-demo valgrind pkg-config libfcl-dev libccd-dev libeigen3-dev g++

cargo fmt --all -- --check
cargo clippy --all-targets -- -D warnings
cargo clippy -p dvh-runner --all-targets -- -D warnings
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --quiet
# Unit, property, integration and documentation tests; a missing mesh archive is a failure here.
DVH_REQUIRE_CGAL_DATA=1 cargo test
cargo test -p dvh-runner --quiet
# The criterion benchmarks must keep compiling.
cargo bench --no-run --quiet
# The C ABI: C tests under sanitizers and valgrind, install, pkg-config, Python ctypes.
ctests/run.sh
scripts/soak.sh --short
# The cross-check against FCL, judged by CGAL: the short version (every scene kind, small meshes),
# dvh's threaded runs on one thread, then on every core (each also against dvh on one thread).
cross_check/run.sh --threads 1 | sed -n "/^Summary/,\$p"
cross_check/run.sh | sed -n "/^Summary/,\$p"
# The benchmark runner's scenes are the cross-check's, coordinate for coordinate.
scenes="many|medium|large|coplanar|copy|near-1e-12"
diff <(runner/run.sh checksums) \
    <(cross_check/build/cmake/dvh_cross_check --checksums --data "${DVH_CACHE_DIR:-cross_check/build/meshes}" \
        | grep -E "^($scenes) ")
# The runner's short run: every method, knob and plot, failing if a dvh method is not exact or a
# conservative mode misses a pair.
runner/run.sh all --out target/dvh-runner >/dev/null
# The profiling command (a frame's refit and query repeated) on one thread and on two.
runner/run.sh profile --frames 2 --repeat 2 >/dev/null
runner/run.sh profile --scene copy --frames 2 --repeat 2 --threads 2 >/dev/null
# Scenes against the same work pair by pair (fails if their contacts differ), on both thread counts.
runner/run.sh scenes --frames 3 --repeat 1 >/dev/null
runner/run.sh scenes --frames 3 --repeat 1 --threads 0 >/dev/null
runner/run.sh self --frames 3 --repeat 1 >/dev/null
# The main job must keep working.
cargo run --release --quiet --example demo -- --frames 4 >/dev/null
echo "all tests passed"
