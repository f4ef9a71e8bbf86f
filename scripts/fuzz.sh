#!/usr/bin/env bash
# Fuzzing as ROBUSTNESS.md reports it: explore fast, check under AddressSanitizer, keep a
# minimised corpus, and judge a plateau by the source lines of `src/` the inputs reach. Each
# target's minimised corpus is kept in the repository as one archive, fuzz/corpora/<target>.tar.xz,
# and worked on unpacked in fuzz/corpus/<target> (not committed); the repository also keeps the
# seeds (fuzz/seeds/<target>) and every input that once found a fault (fuzz/regressions/<target>).
#
#   scripts/fuzz.sh run <target> [seconds]     explore for that long (default 3600) with a build
#                                              without sanitizers on every core (libFuzzer's fork
#                                              mode), starting from fuzz/corpus/<target> (unpacked
#                                              from its archive when not there yet; from the seeds
#                                              and regressions when there is none); minimise
#                                              the result; replay every new input under
#                                              AddressSanitizer; replace fuzz/corpus/<target>
#                                              with the minimised corpus and pack it into
#                                              fuzz/corpora/<target>.tar.xz
#   scripts/fuzz.sh restore [target...]        unpack every target's archive into fuzz/corpus,
#                                              replacing what is there; fails, naming it, when a
#                                              target has no archive (seconds; no nightly needed)
#   scripts/fuzz.sh pack [target...]           pack fuzz/corpus/<target> into its archive
#                                              (sorted, no times or owners: the same inputs give
#                                              the same archive)
#   scripts/fuzz.sh coverage <target> [dir...] source lines of src/ reached by the inputs in the
#                                              directories (default: the seeds, the corpus and
#                                              the regressions); the lines, as file:line, go to
#                                              fuzz/coverage/<target>/lines.txt for comparing
#                                              two runs with `comm`
#
# Targets: triangle_oracle, c_abi, scene, self_collision, ccd_primitive, ccd_mesh, nearest_mesh,
# curves.
# FUZZ_JOBS sets the processes of `run` (default: one per core). ccd_mesh's inputs spend their
# time in big-integer arithmetic: it explores without trace-compares (which instruments those
# comparisons to no use for inputs made of coordinates, and costs it two thirds of its speed),
# and since AddressSanitizer slows its allocations twenty-fold, it replays under it only the new
# inputs the minimised corpus keeps. `run` and `coverage` need the nightly toolchain; they install
# cargo-fuzz and nightly's llvm-tools when they are missing. Work files go to fuzz/work/<target>.
# The corpora are replayed under `cargo test` by `DVH_FUZZ_CORPUS=fuzz/corpus cargo test --test
# fuzz_replay` (what `scripts/test.sh --full` does after `restore`).
set -euo pipefail
cd "$(dirname "$0")/.."
targets=$(ls fuzz/fuzz_targets | sed 's/\.rs$//')

pack() {
    # Deterministic: sorted names, no times, owners or permissions beyond the defaults.
    tar --sort=name --mtime=@0 --owner=0 --group=0 --numeric-owner --mode=a=r,u+w \
        -C fuzz/corpus -cf - "$1" | xz -9 -T1 >"fuzz/corpora/$1.tar.xz.new"
    mv "fuzz/corpora/$1.tar.xz.new" "fuzz/corpora/$1.tar.xz"
    echo "fuzz/corpora/$1.tar.xz: $(ls "fuzz/corpus/$1" | wc -l) inputs, $(wc -c <"fuzz/corpora/$1.tar.xz") bytes"
}

case "${1:-}" in
restore)
    shift
    for target in ${*:-$targets}; do
        [ -f "fuzz/corpora/$target.tar.xz" ] || {
            echo "no corpus for fuzz target '$target' (fuzz/corpora/$target.tar.xz): a checkout without" \
                "it is incomplete; 'scripts/fuzz.sh run $target' builds one" >&2
            exit 1
        }
        rm -rf "fuzz/corpus/$target"
        mkdir -p fuzz/corpus
        xz -dc "fuzz/corpora/$target.tar.xz" | tar -x -C fuzz/corpus
        echo "fuzz/corpus/$target: $(ls "fuzz/corpus/$target" | wc -l) inputs"
    done
    exit 0
    ;;
pack)
    shift
    mkdir -p fuzz/corpora
    for target in ${*:-$targets}; do
        [ -d "fuzz/corpus/$target" ] || {
            echo "no fuzz/corpus/$target to pack" >&2
            exit 1
        }
        pack "$target"
    done
    exit 0
    ;;
esac

usage() {
    # The header comment above, whatever its length.
    awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"
    exit 2
}
[ $# -ge 2 ] || usage
what=$1
target=$2
shift 2
[ -f "fuzz/fuzz_targets/$target.rs" ] || {
    echo "no fuzz target '$target' (fuzz/fuzz_targets/ has: $(ls fuzz/fuzz_targets | sed 's/\.rs$//' | tr '\n' ' '))" >&2
    exit 2
}
cargo +nightly --version >/dev/null 2>&1 || {
    echo "the nightly toolchain is needed: rustup toolchain install nightly" >&2
    exit 2
}
cargo +nightly fuzz --version >/dev/null 2>&1 || cargo install --locked cargo-fuzz --version 0.13.2
host=$(rustc +nightly -vV | sed -n 's/^host: //p')
corpus=fuzz/corpus/$target
work=fuzz/work/$target

case "$what" in
run)
    seconds=${1:-3600}
    jobs=${FUZZ_JOBS:-$(nproc)}
    flags=()
    dir=
    if [ "$target" = ccd_mesh ]; then
        flags=(--no-trace-compares)
        dir=/no-trace-compares
    fi
    # The build without sanitizers explores five to seven times faster; what it keeps is then
    # replayed under AddressSanitizer, which catches what the fast build cannot see.
    cargo +nightly fuzz build -s none "${flags[@]}" --target-dir "fuzz/target/fast$dir" "$target"
    fast=fuzz/target/fast$dir/$host/release/$target
    rm -rf "$work"
    mkdir -p "$work/live" "$work/new" "$work/min"
    if [ ! -d "$corpus" ] && [ -f "fuzz/corpora/$target.tar.xz" ]; then
        mkdir -p fuzz/corpus
        xz -dc "fuzz/corpora/$target.tar.xz" | tar -x -C fuzz/corpus
    fi
    # (A corpus directory a stopped run left empty counts as none.)
    if [ -d "$corpus" ] && [ -n "$(ls -A "$corpus")" ]; then
        cp -r "$corpus/." "$work/live/"
    else
        cp -r "fuzz/seeds/$target/." "$work/live/"
        [ -d "fuzz/regressions/$target" ] && cp -r "fuzz/regressions/$target/." "$work/live/"
    fi
    ls "$work/live" | sort >"$work/before.txt"
    # Which new inputs are replayed under AddressSanitizer: all (live), or those kept (min).
    replay=live
    [ "$target" = ccd_mesh ] && replay=min
    echo "exploring $target for $seconds s on $jobs processes from $(wc -l <"$work/before.txt") inputs (log: $work/run.log)"
    status=0
    "$fast" "$work/live" -fork="$jobs" -max_len=2048 -max_total_time="$seconds" \
        -artifact_prefix="$work/" -print_final_stats=1 >"$work/run.log" 2>&1 || status=$?
    grep -E '^#[0-9]+' "$work/run.log" | tail -1
    if [ "$status" -ne 0 ]; then
        echo "the fuzzer stopped with status $status: a finding; its input is in $work/ (see $work/run.log)" >&2
        exit 1
    fi
    # Minimise: keep the inputs that add coverage features (the live directory began as a copy
    # of the kept corpus, so it alone holds every input).
    "$fast" -merge=1 "$work/min" "$work/live" >"$work/merge.log" 2>&1
    ls "$work/$replay" | sort >"$work/after.txt"
    comm -13 "$work/before.txt" "$work/after.txt" | while read -r f; do cp "$work/$replay/$f" "$work/new/"; done
    echo "replaying $(ls "$work/new" | wc -l) new inputs under AddressSanitizer"
    # In batches of 400, each in a process of its own: one process replaying thousands of
    # inputs grows past libFuzzer's 2 GB limit on AddressSanitizer's quarantine and caches alone
    # (2,541 scene inputs did, each of them under 400 MB alone).
    ls "$work/new" | split -l 400 - "$work/batch."
    for list in "$work"/batch.*; do
        rm -rf "$work/replay"
        mkdir -p "$work/replay"
        while read -r f; do cp "$work/new/$f" "$work/replay/"; done <"$list"
        cargo +nightly fuzz run "${flags[@]}" --target-dir "fuzz/target$dir" "$target" "$work/replay" -- -runs=0 \
            >"$work/asan.log" 2>&1 || {
            echo "an input fails under AddressSanitizer: see $work/asan.log" >&2
            exit 1
        }
    done
    rm -rf "$work/replay" "$work"/batch.*
    # Replace the kept corpus.
    mkdir -p "$corpus"
    rm -f "$corpus"/*
    cp -r "$work/min/." "$corpus/"
    echo "kept $(ls "$corpus" | wc -l) inputs in $corpus"
    mkdir -p fuzz/corpora
    pack "$target"
    ;;
coverage)
    dirs=("$@")
    if [ ${#dirs[@]} -eq 0 ]; then
        dirs=("fuzz/seeds/$target")
        [ -d "$corpus" ] && dirs+=("$corpus")
        [ -d "fuzz/regressions/$target" ] && dirs+=("fuzz/regressions/$target")
    fi
    rustup component list --toolchain nightly --installed | grep -q '^llvm-tools' ||
        rustup component add llvm-tools --toolchain nightly
    bin=$(rustc +nightly --print sysroot)/lib/rustlib/$host/bin
    rm -rf "fuzz/coverage/$target"
    mkdir -p fuzz/coverage
    # Without libFuzzer's 2 GB limit: cargo-fuzz replays the inputs in large batches, one process
    # each, and the scene corpus's batches grow past it (each input alone stays far below).
    cargo +nightly fuzz coverage --target-dir fuzz/target/coverage "$target" "${dirs[@]}" \
        -- -rss_limit_mb=0 >"fuzz/coverage/$target.log" 2>&1 || {
        echo "the coverage replay failed: see fuzz/coverage/$target.log" >&2
        exit 1
    }
    exe=fuzz/target/coverage/$host/release/$target
    profile=fuzz/coverage/$target/coverage.profdata
    # Only dvh's own sources: not the standard library, dependencies or the fuzz drivers.
    ignore='(/\.cargo/|/rustc/|/fuzz/)'
    "$bin/llvm-cov" export -format=lcov "$exe" -instr-profile="$profile" \
        -ignore-filename-regex="$ignore" >"fuzz/coverage/$target/lcov.info"
    awk -v root="$PWD/" '
        /^SF:/ { file = substr($0, 4); if (index(file, root) == 1) file = substr(file, length(root) + 1) }
        /^DA:/ { split(substr($0, 4), f, ","); if (f[2] > 0) print file ":" f[1] }
    ' "fuzz/coverage/$target/lcov.info" | sort -u >"fuzz/coverage/$target/lines.txt"
    "$bin/llvm-cov" report "$exe" -instr-profile="$profile" -ignore-filename-regex="$ignore" |
        awk '!/^-/ { print $1, $8, $9, $10 }' | column -t
    total=$(grep -c '^DA:' "fuzz/coverage/$target/lcov.info")
    echo "$(find "${dirs[@]}" -type f | wc -l) inputs reach $(wc -l <"fuzz/coverage/$target/lines.txt") of $total source lines of src/ (the list: fuzz/coverage/$target/lines.txt)"
    ;;
*)
    usage
    ;;
esac
