#!/usr/bin/env bash
# The soak (ROBUSTNESS.md): examples/soak.rs through the C ABI, then a shorter run of
# it under valgrind memcheck (zero errors, zero definite or indirect leaks).
#
#   scripts/soak.sh           10,000 frames of a deforming mesh pair and of a 100-object scene,
#                             brute force every 500 frames, a 10-million-triangle mesh
#                             (about 3 minutes on 2 cores; 3 GiB of memory at the peak)
#   scripts/soak.sh --short   what CI runs: 1,000 frames, a 1-million-triangle mesh, a short
#                             valgrind run
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/ensure-packages.sh valgrind
cargo build --release --quiet --example soak
soak=target/release/examples/soak
if [ "${1:-}" = "--short" ]; then
    "$soak" --frames 1000 --check-every 250 --big 1000000
    frames=60
else
    "$soak"
    frames=300
fi
echo "under valgrind memcheck: $frames frames, 30 objects"
valgrind --quiet --error-exitcode=1 --leak-check=full --show-leak-kinds=definite,indirect \
    --errors-for-leak-kinds=definite,indirect --suppressions=ctests/valgrind.supp \
    "$soak" --frames "$frames" --objects 30 --check-every 30 --big 20000 --no-memory-check
