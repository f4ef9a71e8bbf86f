#!/usr/bin/env bash
# The test suite. Installs the Debian packages it needs when they are missing (as root, or
# through sudo).
#
#   scripts/test.sh          every part once: formatting, clippy, the documentation, the
#                            dependencies' licences, every Rust test (unit, property,
#                            integration, documentation; the fuzz seeds and regressions), the C
#                            tests under AddressSanitizer and UndefinedBehaviorSanitizer, the
#                            header as C and C++, the C++ layer's tests, the install with its
#                            pkg-config and CMake packages, Python through ctypes, a short
#                            cross-check against FCL judged by CGAL, the Python package (a wheel
#                            packed from the release library, in a fresh virtual environment)
#                            and the demo (about 11 minutes from a fresh clone on 2 cores; the
#                            README has each step's time)
#   scripts/test.sh --full   all of that and the long runs: the randomized tests' long form,
#                            the C tests under valgrind, the manylinux wheel as released (built
#                            by maturin, audited, tested and compared with the packed one), the
#                            soak, the crate as packaged for crates.io (built, documented, its
#                            examples and documentation tests run from the package), the Python
#                            sdist built by pip, the benchmark runner's tests and short runs
#                            (every method and knob, its scenes checked against the
#                            cross-check's), the cross-check on one thread as well as on every
#                            core, the criterion benchmarks' build, the demo's release build,
#                            the Python benchmark scripts' quick runs, and every fuzz target's
#                            corpus replayed (about 47 minutes from a fresh clone on 2 cores;
#                            what CI runs)
set -euo pipefail
cd "$(dirname "$0")/.."
full=false
case "${1:-}" in
--full) full=true ;;
"") ;;
*)
    echo "usage: scripts/test.sh [--full]" >&2
    exit 2
    ;;
esac
started=$SECONDS
# A run from a clean target/ (a new clone, CI) writes no incremental caches it would never read
# again: about 10% of the build. CARGO_INCREMENTAL=1 keeps them for repeated runs.
export CARGO_INCREMENTAL=${CARGO_INCREMENTAL:-0}
# The randomized tests' long form (dvh::fixtures::cases) with the long runs.
$full && export DVH_TEST_FULL=1
step() { echo "== $1 ($((SECONDS - started)) s)"; }

packages=(pkg-config g++ cmake libfcl-dev libccd-dev libeigen3-dev libcgal-dev libcgal-demo libgmp-dev libmpfr-dev)
$full && packages+=(valgrind)
scripts/ensure-packages.sh "${packages[@]}"

# The release library (what the C tests, the cross-check and the Python package use) is built in
# the background while the Rust steps run: its compile is a single thread for about two minutes
# (one codegen unit, LTO), which would otherwise leave a core idle. `scripts/install.sh` later
# finds it built.
release=$(mktemp -d)
# (In a session of its own, so that a failed run stops the build with the script.)
setsid scripts/install.sh "$release/prefix" >"$release/log" 2>&1 &
release_build=$!
trap 'kill -- "-$release_build" 2>/dev/null || true; rm -rf "$release"' EXIT
release_built() {
    wait "$release_build" || {
        cat "$release/log" >&2
        echo "the release build of the library failed (above)" >&2
        exit 1
    }
}

step "formatting, clippy, documentation"
cargo fmt --all -- --check
cargo clippy --workspace --all-targets --quiet -- -D warnings
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --quiet --package dvh

step "licences"
# Every dependency's licence allows dvh's; the bundled code's notices are current.
python3 scripts/licences.py check

step "Rust tests"
# Unit, property, integration and documentation tests; a missing mesh archive is a failure here.
# cargo-nextest (where installed) runs every test binary's tests side by side rather than one
# binary after another, so a long test of one never leaves the other core idle; the
# documentation tests are cargo's alone.
export DVH_REQUIRE_CGAL_DATA=1
if cargo nextest --version >/dev/null 2>&1; then
    cargo nextest run --cargo-quiet --no-fail-fast --status-level fail --final-status-level slow --hide-progress-bar
    cargo test --quiet --doc
else
    cargo test --quiet
fi

release_built
step "C ABI"
# The C tests under sanitizers (and valgrind with --full), install, pkg-config, Python ctypes.
if $full; then ctests/run.sh --full; else ctests/run.sh; fi

step "cross-check against FCL, judged by CGAL"
# The short version: every scene kind on small meshes; dvh's threaded run on every core (and
# against dvh on one thread). --full runs it again with the threaded run on one thread.
cross_check/run.sh | sed -n "/^Summary/,\$p"
$full && cross_check/run.sh --threads 1 | sed -n "/^Summary/,\$p"

step "Python package"
# The distribution wheel (scripts/wheel.sh) in a fresh virtual environment without Rust, the
# pytest suite and the README's example; --full also builds the sdist with pip.
if $full; then scripts/python.sh --full; else scripts/python.sh; fi

step "demo"
# The build `cargo test` made (the README's command builds it in release: --full runs that).
"${CARGO_TARGET_DIR:-target}/debug/examples/demo" --frames 4 >/dev/null
$full && cargo run --release --quiet --example demo -- --frames 4 >/dev/null

if $full; then
    step "fuzz corpus replay"
    # Every target's minimised corpus, unpacked from its archive in fuzz/corpora (a target
    # without one fails here), replayed through the drivers; the replay names every target and
    # how many inputs it ran.
    scripts/fuzz.sh restore
    DVH_FUZZ_CORPUS=fuzz/corpus cargo test --quiet --test fuzz_replay -- --nocapture --test-threads 2

    step "the criterion benchmarks' build, the runner's tests"
    # In the test profile, which reuses the library the tests built (before the runner's build,
    # with its other features, replaces it): in the release profile (one codegen unit, LTO) three
    # binaries that only need to build cost about 8 minutes.
    cargo test --benches --no-run --quiet
    cargo test -p dvh-runner --quiet

    step "crate package"
    # What crates.io would get: packaged, published dry, built and documented from the package.
    scripts/package.sh

    step "soak"
    scripts/soak.sh --short

    step "benchmark runner"
    # The runner's scenes are the cross-check's, coordinate for coordinate.
    scenes="many|medium|large|coplanar|copy|near-1e-12"
    # Each side to a file first: a comparison of two outputs must not pass because both
    # commands failed and printed nothing.
    sums=target/checksums
    mkdir -p "$sums"
    runner/run.sh checksums >"$sums/runner.txt"
    cross_check/build/cmake/dvh_cross_check --checksums --data "${DVH_CACHE_DIR:-cross_check/build/meshes}" \
        >"$sums/cross_check_all.txt"
    grep -E "^($scenes) " "$sums/cross_check_all.txt" >"$sums/cross_check.txt"
    for side in runner cross_check; do
        [ "$(wc -l <"$sums/$side.txt")" -eq 12 ] || {
            echo "$sums/$side.txt: $(wc -l <"$sums/$side.txt") checksums, not two (first and last frame) for each of the 6 scenes" >&2
            exit 1
        }
    done
    diff "$sums/runner.txt" "$sums/cross_check.txt"
    # Every method, knob and plot, failing if a dvh method is not exact or a conservative mode
    # misses a pair.
    runner/run.sh all --out target/dvh-runner >/dev/null
    # The profiling command (a frame's refit and query repeated) on one thread and on two.
    runner/run.sh profile --frames 2 --repeat 2 >/dev/null
    runner/run.sh profile --scene copy --frames 2 --repeat 2 --threads 2 >/dev/null
    # Scenes against the same work pair by pair (fails if their contacts differ), on both thread
    # counts; self-collision against the naive route.
    runner/run.sh scenes --frames 3 --repeat 1 >/dev/null
    runner/run.sh scenes --frames 3 --repeat 1 --threads 0 >/dev/null
    runner/run.sh self --frames 3 --repeat 1 >/dev/null
    # The distance against parry (fails if a tolerant answer breaks its tolerance).
    runner/run.sh distance --frames 2 >/dev/null
fi

step "done"
echo "all tests passed"
