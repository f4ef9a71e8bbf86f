#!/usr/bin/env bash
# Builds the release library and installs it the way C and C++ users expect:
#   PREFIX/lib/libdvh.so.X.Y.Z with the links libdvh.so.SOVERSION and libdvh.so, PREFIX/lib/libdvh.a,
#   PREFIX/include/dvh.h and dvh.hpp (the C++ layer), PREFIX/lib/pkgconfig/dvh.pc,
#   PREFIX/lib/cmake/dvh/ (find_package(dvh CONFIG): imported targets dvh::dvh and
#   dvh::dvh_static), PREFIX/share/doc/dvh/ (the licences, and the notices of the code the
#   library bundles).
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
# The crate is a plain Rust library (what Rust dependents build); the C libraries are asked for
# here, both from one compile, which also reports the system libraries a static link needs
# (cargo repeats the report when the build is already fresh).
build=$(cargo rustc --release --quiet --lib --crate-type cdylib,staticlib -- --print native-static-libs 2>&1) || {
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

# The CMake package. Relocatable: the prefix is found from the file's own place, so a staged or
# moved install still works.
cmakedir="$libdir/cmake/dvh"
install -d "$cmakedir"
link_names=$(sed 's/-l//g' <<<"$static_libs")
cat > "$cmakedir/dvhConfig.cmake" <<CMAKE
# dvh $version: find_package(dvh CONFIG) gives dvh::dvh (the shared library) and dvh::dvh_static,
# each with dvh.h and dvh.hpp (the C++17 layer) on its include path.
get_filename_component(_dvh_prefix "\${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)
if(NOT TARGET dvh::dvh)
  add_library(dvh::dvh SHARED IMPORTED)
  set_target_properties(dvh::dvh PROPERTIES
    IMPORTED_LOCATION "\${_dvh_prefix}/lib/libdvh.so.$version"
    IMPORTED_SONAME "libdvh.so.$soversion"
    INTERFACE_INCLUDE_DIRECTORIES "\${_dvh_prefix}/include")
endif()
if(NOT TARGET dvh::dvh_static)
  add_library(dvh::dvh_static STATIC IMPORTED)
  set_target_properties(dvh::dvh_static PROPERTIES
    IMPORTED_LOCATION "\${_dvh_prefix}/lib/libdvh.a"
    INTERFACE_INCLUDE_DIRECTORIES "\${_dvh_prefix}/include"
    # The system libraries the Rust standard library needs in a static link.
    INTERFACE_LINK_LIBRARIES "$(tr ' ' ';' <<<"$link_names")")
endif()
unset(_dvh_prefix)
set(dvh_VERSION "$version")
CMAKE
cat > "$cmakedir/dvhConfigVersion.cmake" <<CMAKE
# The soname's rule: while the version is 0.x every minor release may change the ABI, so a
# request for 0.MINOR[.PATCH] is met only by 0.MINOR with an equal or later patch; from 1.0 on,
# by any later version of the same major. A range (CMake 3.19) is met by any version inside it.
set(PACKAGE_VERSION "$version")
set(PACKAGE_VERSION_COMPATIBLE FALSE)
if(PACKAGE_FIND_VERSION_RANGE)
  if(PACKAGE_VERSION VERSION_LESS PACKAGE_FIND_VERSION_MIN)
  elseif(PACKAGE_FIND_VERSION_RANGE_MAX STREQUAL "INCLUDE"
         AND PACKAGE_VERSION VERSION_GREATER PACKAGE_FIND_VERSION_MAX)
  elseif(PACKAGE_FIND_VERSION_RANGE_MAX STREQUAL "EXCLUDE"
         AND NOT PACKAGE_VERSION VERSION_LESS PACKAGE_FIND_VERSION_MAX)
  else()
    set(PACKAGE_VERSION_COMPATIBLE TRUE)
  endif()
elseif("\${PACKAGE_FIND_VERSION}" STREQUAL "")
  set(PACKAGE_VERSION_COMPATIBLE TRUE)
elseif(PACKAGE_VERSION VERSION_LESS PACKAGE_FIND_VERSION)
elseif(NOT PACKAGE_FIND_VERSION_MAJOR EQUAL $major)
elseif($major EQUAL 0 AND NOT PACKAGE_FIND_VERSION_MINOR EQUAL $minor)
else()
  set(PACKAGE_VERSION_COMPATIBLE TRUE)
  if(PACKAGE_VERSION VERSION_EQUAL PACKAGE_FIND_VERSION)
    set(PACKAGE_VERSION_EXACT TRUE)
  endif()
endif()
# Built for 64-bit x86-64 Linux: a 32-bit project cannot use it.
if(NOT CMAKE_SIZEOF_VOID_P STREQUAL "" AND NOT CMAKE_SIZEOF_VOID_P EQUAL 8)
  set(PACKAGE_VERSION_UNSUITABLE TRUE)
endif()
CMAKE

docdir="$dest$prefix/share/doc/dvh"
install -d "$docdir"
install -m 0644 LICENSE-MIT LICENSE-APACHE THIRD-PARTY-LICENSES.txt "$docdir/"
echo "installed dvh $version into $dest$prefix"
