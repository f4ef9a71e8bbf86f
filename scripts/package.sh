#!/usr/bin/env bash
# The crate as crates.io would receive it: `cargo package` (which builds the packaged sources
# alone), `cargo publish --dry-run`, then from the unpacked package: the documentation as docs.rs
# builds it (its metadata's features, warnings denied), every example and the README's and the
# API's documentation tests with the features they name. Fails when the package holds a file it
# should not (tests, benchmarks, fuzzing, the cross-check, the runner, the Python package).
#
#   scripts/package.sh      about 4 minutes on 2 cores from a clean build
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
target="${CARGO_TARGET_DIR:-$root/target}"
cargo package --quiet --locked --allow-dirty --package dvh
cargo publish --quiet --locked --dry-run --allow-dirty --package dvh
version=$(sed -n 's/^version = "\(.*\)"/\1/p' Cargo.toml | head -n 1)
crate="$target/package/dvh-$version.crate"
files=$(tar -tzf "$crate")
if grep -E "^dvh-$version/(tests|benches|fuzz|cross_check|runner|python|ctests|scripts|docs)/" <<<"$files"; then
    echo "the package holds files users do not need (above)" >&2
    exit 1
fi
for f in src/lib.rs include/dvh.h include/dvh.hpp README.md CHANGELOG.md LICENSE-MIT LICENSE-APACHE THIRD-PARTY-LICENSES.txt; do
    grep -qx "dvh-$version/$f" <<<"$files" || {
        echo "the package lacks $f" >&2
        exit 1
    }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
tar -xzf "$crate" -C "$work"
cd "$work/dvh-$version"
# Built apart from the repository's target directory, whose features differ; kept between runs.
export CARGO_TARGET_DIR="$target/package-check"
features=$(sed -n '/^\[package.metadata.docs.rs\]/,/^\[/s/^features = \[\(.*\)\]/\1/p' Cargo.toml | tr -d '" ')
RUSTDOCFLAGS="-D warnings" cargo doc --quiet --locked --no-deps --features "$features"
cargo build --quiet --locked --examples --features fixtures,nalgebra
cargo test --quiet --locked --doc --features fixtures,nalgebra
echo "dvh $version packages: $(wc -l <<<"$files") files, $(du -k "$crate" | cut -f1) kB; docs, examples and documentation tests build from it"
