#!/usr/bin/env bash
# Builds and runs the benchmark runner (dvh against FCL and parry, the knobs, the plots).
# Installs what it needs when missing: FCL (to measure it), Debian's CGAL demo meshes.
#
#   runner/run.sh                 short run of everything (small meshes, few frames)
#   runner/run.sh all --full      paper sizes and 200 frames (about 25 minutes)
#   runner/run.sh paper --full --scene large --out DIR
#   runner/run.sh profile --full --scene copy --threads 2   dvh alone, each frame repeated
#   runner/run.sh scenes --full --threads 1   dvh::Scene against the same work pair by pair
#
# Output: target/dvh-runner (or --out DIR): summary.md, CSV files, SVG plots.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/ensure-packages.sh libfcl-dev libccd-dev libeigen3-dev libcgal-demo pkg-config g++
cargo build --release --quiet -p dvh-runner
exec target/release/dvh-runner "$@"
