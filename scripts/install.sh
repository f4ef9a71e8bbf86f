#!/usr/bin/env bash
# Builds the release library and installs it the way C users expect:
#   PREFIX/lib/libdvh.so.X.Y.Z with the links libdvh.so.SOVERSION and libdvh.so, PREFIX/lib/libdvh.a,
#   PREFIX/include/dvh.h and dvh.hpp (the C++ layer), PREFIX/lib/pkgconfig/dvh.pc.
# Usage: scripts/install.sh [PREFIX]   (default /usr/local; DESTDIR is honoured for staging)
set -euo pipefail
cd "$(dirname "$0")/.."
prefix="${1:-/usr/local}"
dest="${DESTDIR:-}"
version=$(sed -n 's/^version = "\(.*\)"/\1/p' Cargo.toml | head -n 1)
major=${version%%.*}
rest=${version#*.}
minor=${rest%%.*}
if [ "$major" = "0" ]; then soversion="0.$minor"; else soversion="$major"; fi

target="${CARGO_TARGET_DIR:-target}"
# One build of the library's three kinds (rlib, cdylib, staticlib) that also reports the system
# libraries a static link needs (cargo repeats the report when the build is already fresh). A
# second command asking for the staticlib alone would compile the whole crate again.
build=$(cargo rustc --release --quiet --lib -- --print native-static-libs 2>&1) || {
    echo "$build" >&2
    exit 1
}
static_libs=$(sed -n 's/.*native-static-libs: //p' <<<"$build" | tail -n 1)
[ -n "$static_libs" ] || { echo "rustc did not report the static link's libraries" >&2; exit 1; }

libdir="$dest$prefix/lib"
install -d "$libdir/pkgconfig" "$dest$prefix/include"
install -m 0755 "$target/release/libdvh.so" "$libdir/libdvh.so.$version"
ln -sf "libdvh.so.$version" "$libdir/libdvh.so.$soversion"
ln -sf "libdvh.so.$soversion" "$libdir/libdvh.so"
install -m 0644 "$target/release/libdvh.a" "$libdir/libdvh.a"
install -m 0644 include/dvh.h "$dest$prefix/include/dvh.h"
install -m 0644 include/dvh.hpp "$dest$prefix/include/dvh.hpp"
cat > "$libdir/pkgconfig/dvh.pc" <<PC
prefix=$prefix
libdir=\${prefix}/lib
includedir=\${prefix}/include

Name: dvh
Description: Collision detection between deformable triangle meshes (DVH sphere hierarchy)
Version: $version
Libs: -L\${libdir} -ldvh
Libs.private: $static_libs
Cflags: -I\${includedir}
PC
echo "installed dvh $version into $dest$prefix"
