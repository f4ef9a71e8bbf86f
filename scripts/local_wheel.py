#!/usr/bin/env python3
"""Builds the Python package as a wheel for this machine from a library already built.

    scripts/local_wheel.py LIBRARY DIR

LIBRARY is a release build of the C library (what `scripts/install.sh` installs); DIR receives
`dvh-VERSION-py3-none-PLATFORM.whl`. The wheel holds what the distribution wheel of
`scripts/wheel.sh` holds, file for file: the package's Python sources, the cffi declarations of
`include/dvh.h` (made as maturin makes them: cffi's recompiler over the header without its
preprocessor lines), the loader, the library, the metadata from `python/pyproject.toml` and the
licences. It only packs: nothing is compiled, so the test suite's quick run tests the package on
the library it has already built, and leaves maturin's manylinux build (a second release build
of the crate, with zig's linker) to `scripts/test.sh --full`, which also checks that the two
wheels hold the same files.

Needs cffi (the declarations) and, before Python 3.11, tomli.
"""

import base64
import hashlib
import re
import sys
import sysconfig
import tempfile
import zipfile
from pathlib import Path

try:
    import tomllib
except ImportError:  # Python before 3.11: the same parser, as a package
    import tomli as tomllib

ROOT = Path(__file__).resolve().parent.parent
PYTHON = ROOT / "python"
# The extension module's name and the library's file name inside it, as maturin names them for
# `module-name = "dvh._dvh"` with cffi bindings.
MODULE = "dvh/_dvh"
LIBRARY_NAME = "lib_dvh.so"
LOADER = f"""__all__ = ["lib", "ffi"]

import os
from .ffi import ffi

lib = ffi.dlopen(os.path.join(os.path.dirname(__file__), '{LIBRARY_NAME}'))
del os
"""


def version() -> str:
    """The crate's version, which the package takes (`dynamic = ["version"]`)."""
    with open(ROOT / "Cargo.toml", "rb") as f:
        return tomllib.load(f)["package"]["version"]


def declarations(header: Path) -> str:
    """The cffi declarations of the C header: its text without the include guard, the includes
    and the C++ wrapper, which cffi does not read (maturin has cbindgen leave them out); the
    integer `#define`s stay, as cffi reads them."""
    keep = []
    for line in header.read_text().splitlines():
        stripped = line.strip()
        if stripped.startswith("#"):
            if re.fullmatch(r"#define\s+\w+\s+\S.*", stripped):
                keep.append(line)
            continue
        if stripped in ('extern "C" {', '}  // extern "C"'):
            continue
        keep.append(line)
    return "\n".join(keep) + "\n"


def ffi_module(header: Path) -> bytes:
    """`ffi.py`: the out-of-line ABI-mode module cffi's recompiler writes."""
    import cffi
    from cffi import recompiler

    ffi = cffi.FFI()
    ffi.cdef(declarations(header))
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "ffi.py"
        recompiler.make_py_source(ffi, "ffi", str(out))
        return out.read_bytes()


def metadata(project: dict, readme: str, licences: list) -> str:
    """The core metadata (2.4) of `[project]`."""
    lines = [
        "Metadata-Version: 2.4",
        f"Name: {project['name']}",
        f"Version: {version()}",
    ]
    lines += [f"Classifier: {c}" for c in project.get("classifiers", [])]
    lines += [f"Requires-Dist: {d}" for d in project.get("dependencies", [])]
    extras = project.get("optional-dependencies", {})
    for extra, deps in extras.items():
        lines += [f"Requires-Dist: {d} ; extra == '{extra}'" for d in deps]
    lines += [f"Provides-Extra: {extra}" for extra in extras]
    lines += [f"License-File: {name}" for name in licences]
    lines += [
        f"Summary: {project['description']}",
        f"License-Expression: {project['license']}",
        f"Requires-Python: {project['requires-python']}",
        "Description-Content-Type: text/markdown; charset=UTF-8; variant=GFM",
        "",
        readme,
    ]
    return "\n".join(lines) + "\n"


def record_line(name: str, data: bytes) -> str:
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{name},sha256={digest},{len(data)}"


def build(library: Path, out: Path) -> Path:
    with open(PYTHON / "pyproject.toml", "rb") as f:
        project = tomllib.load(f)["project"]
    name, ver = project["name"], version()
    platform = sysconfig.get_platform().replace("-", "_").replace(".", "_")
    tag = f"py3-none-{platform}"
    dist_info = f"{name}-{ver}.dist-info"
    licences = project.get("license-files", [])

    files = []  # (name in the wheel, bytes, executable)
    package = PYTHON / "src" / "dvh"
    for path in sorted(package.rglob("*")):
        if path.is_file() and "__pycache__" not in path.parts:
            files.append((f"dvh/{path.relative_to(package).as_posix()}", path.read_bytes(), False))
    files.append((f"{MODULE}/__init__.py", LOADER.encode(), False))
    files.append((f"{MODULE}/ffi.py", ffi_module(ROOT / "include" / "dvh.h"), False))
    files.append((f"{MODULE}/{LIBRARY_NAME}", library.read_bytes(), True))
    readme = (PYTHON / project["readme"]).read_text()
    files.append((f"{dist_info}/METADATA", metadata(project, readme, licences).encode(), False))
    wheel = f"Wheel-Version: 1.0\nGenerator: dvh local_wheel.py\nRoot-Is-Purelib: false\nTag: {tag}\n"
    files.append((f"{dist_info}/WHEEL", wheel.encode(), False))
    for licence in licences:
        files.append((f"{dist_info}/licenses/{licence}", (PYTHON / licence).read_bytes(), False))

    out.mkdir(parents=True, exist_ok=True)
    target = out / f"{name}-{ver}-{tag}.whl"
    record = [record_line(n, data) for n, data, _ in files] + [f"{dist_info}/RECORD,,"]
    with zipfile.ZipFile(target, "w", zipfile.ZIP_DEFLATED) as z:
        for n, data, executable in files:
            info = zipfile.ZipInfo(n, date_time=(1980, 1, 1, 0, 0, 0))
            info.external_attr = (0o755 if executable else 0o644) << 16
            info.compress_type = zipfile.ZIP_DEFLATED
            z.writestr(info, data)
        z.writestr(f"{dist_info}/RECORD", "\n".join(record) + "\n")
    return target


def main() -> int:
    if len(sys.argv) != 3:
        print("usage: scripts/local_wheel.py LIBRARY DIR", file=sys.stderr)
        return 2
    library = Path(sys.argv[1])
    if not library.is_file():
        print(f"local_wheel.py: {library}: no such library", file=sys.stderr)
        return 2
    print(build(library.resolve(), Path(sys.argv[2])))
    return 0


if __name__ == "__main__":
    sys.exit(main())
