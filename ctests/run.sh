#!/usr/bin/env bash
# Builds and runs the C tests against an installed copy of the library (which also tests the
# install, its pkg-config file and its CMake package): under AddressSanitizer + UndefinedBehaviorSanitizer, the
# out-of-memory test unsanitised, the header as C99 and as C++, the C++ layer (dvh.hpp) and its
# test as C++17 and C++20 under the same sanitizers, the README's C and C++ examples, a static
# link, a CMake project using the installed package, and the Python ctypes test.
#
#   ctests/run.sh          all of that (about 3 minutes on 2 cores, the library's build included)
#   ctests/run.sh --full   and the C tests once more under valgrind memcheck (zero errors, zero
#                          leaks but the thread-local storage of the library's pool threads,
#                          alive until exit: ctests/valgrind.supp); about 15 minutes more
set -euo pipefail
cd "$(dirname "$0")/.."
full=false
[ "${1:-}" = "--full" ] && full=true
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"
./scripts/install.sh "$prefix" >/dev/null
export PKG_CONFIG_PATH="$prefix/lib/pkgconfig"
cflags=$(pkg-config --cflags dvh)
libs="$(pkg-config --libs dvh) -Wl,-rpath,$prefix/lib"
warn=(-Wall -Wextra -Wpedantic -Werror)
san=(-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)

echo "every function the header declares is exported, exercised by test_api.c and wrapped by dvh.hpp"
declared=$(grep -oE '\bdvh_[a-z0-9_]+\(' include/dvh.h | tr -d '(' | sort -u)
exported=$(nm -D --defined-only "$prefix/lib/libdvh.so" | awk '$2 == "T" && $3 ~ /^dvh_/ {print $3}' | sort -u)
diff <(echo "$declared") <(echo "$exported")
for f in $declared; do grep -q "\b$f(" ctests/test_api.c || { echo "test_api.c never calls $f"; exit 1; }; done
for f in $declared; do grep -q "\b$f(" include/dvh.hpp || { echo "dvh.hpp never calls $f"; exit 1; }; done

echo "headers: dvh.h as C99, C11, C++11, C++17; dvh.hpp as C++17, C++20"
printf '#include <dvh.h>\nint main(void) { return dvh_version() == 0; }\n' > "$work/header.c"
for std in c99 c11; do gcc -std=$std "${warn[@]}" $cflags "$work/header.c" -o "$work/header_$std" $libs; done
cp "$work/header.c" "$work/header.cpp"
for std in c++11 c++17; do g++ -std=$std "${warn[@]}" $cflags "$work/header.cpp" -o "$work/header_$std" $libs; done
"$work/header_c99"
printf '#include <dvh.hpp>\nint main() { return dvh::version() == nullptr; }\n' > "$work/header_hpp.cpp"
for std in c++17 c++20; do g++ -std=$std "${warn[@]}" $cflags "$work/header_hpp.cpp" -o "$work/header_hpp_$std" $libs; done
"$work/header_hpp_c++17"

echo "C tests under ASan + UBSan"
for t in test_api test_threads; do
    gcc -std=c99 -g "${warn[@]}" "${san[@]}" $cflags ctests/$t.c -o "$work/${t}_san" $libs -lpthread -lm
    ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 "$work/${t}_san"
done

echo "C++ layer (dvh.hpp) tests as C++17 and C++20 under ASan + UBSan"
for std in c++17 c++20; do
    g++ -std=$std -g "${warn[@]}" "${san[@]}" $cflags ctests/test_cpp.cpp -o "$work/test_cpp_$std" $libs
    ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 "$work/test_cpp_$std"
done

if $full; then
    echo "C tests under valgrind memcheck"
    for t in test_api test_threads; do
        gcc -std=c99 -g -O1 "${warn[@]}" $cflags ctests/$t.c -o "$work/$t" $libs -lpthread -lm
        DVH_ONE_THREAD_AT_A_TIME=1 valgrind --quiet --error-exitcode=99 --leak-check=full --show-leak-kinds=definite,indirect,possible \
            --suppressions=ctests/valgrind.supp \
            --errors-for-leak-kinds=definite,indirect,possible "$work/$t"
    done
fi

echo "out-of-memory test"
gcc -std=c99 -g -O1 "${warn[@]}" $cflags ctests/test_oom.c -o "$work/test_oom" $libs
"$work/test_oom"

echo "static link"
static_libs=$(pkg-config --static --libs dvh | sed 's/-ldvh\b//')
gcc -std=c99 -O1 "${warn[@]}" $cflags ctests/test_api.c -o "$work/test_api_static" "$prefix/lib/libdvh.a" $static_libs
"$work/test_api_static" >/dev/null

echo "CMake package: a consumer project, find_package(dvh) and the imported targets"
version=$(sed -n 's/^version = "\(.*\)"/\1/p' Cargo.toml | head -n 1)
IFS=. read -r major minor patch <<<"$version"
# The ABI the install names (libdvh.so -> libdvh.so.SOVERSION), as install.sh decided it.
abi=$(readlink "$prefix/lib/libdvh.so")
abi=${abi#libdvh.so.}
# From a copy of the install elsewhere: the package finds its files from its own place.
cp -a "$prefix" "$work/moved"
cmake -S ctests/cmake_consumer -B "$work/consumer" -DCMAKE_PREFIX_PATH="$work/moved" \
    -DDVH_WANTED="$abi" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/consumer" >/dev/null
"$work/consumer/consumer_cpp"
"$work/consumer/consumer_c_static"
# (ldd's output taken whole: `ldd | grep -q` fails under pipefail when grep stops reading early.)
loads=$(ldd "$work/consumer/consumer_cpp")
grep -q "$work/moved/lib/libdvh.so" <<<"$loads" || { echo "consumer_cpp does not load the moved install's libdvh: $loads"; exit 1; }
loads=$(ldd "$work/consumer/consumer_c_static")
if grep -q libdvh <<<"$loads"; then echo "consumer_c_static loads libdvh: $loads"; exit 1; fi
# The version file follows the soname: another ABI is refused, the same ABI with any patch found.
if [ "$major" = 0 ]; then refused=("0.$((minor + 1))" "1.0" "0.$minor.$((patch + 1))"); else refused=("$((major + 1)).0" "$major.$((minor + 1))"); fi
[ "$major.$minor" != "0.0" ] && [ "$minor" != 0 ] && refused+=("$major.$((minor - 1))")
for wanted in "${refused[@]}"; do
    if cmake -S ctests/cmake_consumer -B "$work/refused" -DCMAKE_PREFIX_PATH="$prefix" -DDVH_WANTED="$wanted" >/dev/null 2>&1; then
        echo "find_package(dvh $wanted) accepted dvh $version"
        exit 1
    fi
    rm -rf "$work/refused"
done
for wanted in "$abi" "$version" ""; do
    cmake -S ctests/cmake_consumer -B "$work/accepted" -DCMAKE_PREFIX_PATH="$prefix" -DDVH_WANTED="$wanted" >/dev/null ||
        { echo "find_package(dvh $wanted) refused dvh $version"; exit 1; }
    rm -rf "$work/accepted"
done
test -s "$prefix/share/doc/dvh/THIRD-PARTY-LICENSES.txt"

echo "README C example"
awk '/^```c$/{on=1; next} /^```$/{on=0} on' README.md > "$work/readme.c"
test -s "$work/readme.c"
gcc -std=c99 "${warn[@]}" $cflags "$work/readme.c" -o "$work/readme" $libs
"$work/readme"

echo "README C++ example"
awk '/^```cpp$/{on=1; next} /^```$/{on=0} on' README.md > "$work/readme.cpp"
test -s "$work/readme.cpp"
g++ -std=c++17 "${warn[@]}" $cflags "$work/readme.cpp" -o "$work/readme_cpp" $libs
"$work/readme_cpp"

echo "Python ctypes"
DVH_LIBRARY="$prefix/lib/libdvh.so" python3 ctests/test_ctypes.py
echo "C ABI tests passed"
