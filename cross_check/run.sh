#!/usr/bin/env bash
# Builds and runs the dvh / FCL / CGAL cross-check. Installs the Debian packages it needs when
# they are missing, installs dvh into the build directory, unpacks the CGAL demo meshes into a
# cache, and runs the harness.
#
#   cross_check/run.sh           short version (small meshes, 4 frames, every scene kind, dvh's whole
#                                set against CGAL's exact set on coplanar, near-1e-15 and medium; then
#                                the self-collision run, 5 frames, the proximity run, 2 frames, the
#                                curves run against CGAL's surface_intersection, 4 frames, and the
#                                distance run against FCL's distance(), 2 frames)
#   cross_check/run.sh --full    paper sizes, 200 frames, whole sets on every 10th (self-collision:
#                                larger meshes, 40 frames; proximity: the short meshes, every scene,
#                                10 frames)
#   extra arguments go to the harness: --frames N (every run), --scene NAME (of any run), --threads N
#   (dvh's threaded run; default 0, every core; dvh also runs on one thread, and both must agree),
#   --scene-run-only (only the run of whole scenes: one DvhScene against FCL's broad phase, on every
#   scene chosen), --self-run-only (only the self-collision and proximity runs: dvh_self_collide
#   against FCL's model collided with itself, dvh_proximity and dvh_self_proximity, all against
#   CGAL's exact sets), --distance-run-only (only the distance run)
#
# Results: cross_check/build/results/{frames.csv,summary.json} (pairwise run),
# {scene_frames.csv,scene_summary.json} (scene run), {self_frames.csv,self_summary.json}
# (self-collision run), {proximity_frames.csv,proximity_summary.json} (proximity run),
# curves_frames.csv (curves run), distance_frames.csv (distance run),
# mismatches.txt (the triangle pairs on which dvh differs from an exact set, if any) and the
# printed summaries.
set -euo pipefail
cd "$(dirname "$0")"
root=$(cd .. && pwd)

"$root/scripts/ensure-packages.sh" libfcl-dev libccd-dev libcgal-dev libcgal-demo libgmp-dev libmpfr-dev \
    libeigen3-dev cmake g++ pkg-config

build="$PWD/build"
mkdir -p "$build/results"
"$root/scripts/install.sh" "$build/prefix" >/dev/null
export PKG_CONFIG_PATH="$build/prefix/lib/pkgconfig"

meshes="${DVH_CACHE_DIR:-$build/meshes}"
mkdir -p "$meshes"
archive="${DVH_CGAL_DATA:-/usr/share/doc/libcgal-demo/data.tar.gz}"
for name in elephant mannequin-devil armadillo lion refined_elephant bunny00; do
    if [ ! -f "$meshes/$name.off" ]; then
        tar -xzf "$archive" -C "$meshes" --strip-components=2 "data/meshes/$name.off"
    fi
done

cmake -S . -B "$build/cmake" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build/cmake" -j 2 >/dev/null
"$build/cmake/dvh_cross_check" --data "$meshes" --out "$build/results" "$@"
