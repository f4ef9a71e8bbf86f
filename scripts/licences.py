#!/usr/bin/env python3
"""The licences of dvh's dependencies, from `cargo metadata`.

    scripts/licences.py check    every crate the build can pull in has a licence that allows
                                 dvh's (MIT OR Apache-2.0): what the library bundles (its
                                 dependencies, with every feature) a permissive one, tools that
                                 only build or test it (cbindgen, criterion, ...) also MPL-2.0;
                                 and THIRD-PARTY-LICENSES.txt is what `write` would make
    scripts/licences.py write    THIRD-PARTY-LICENSES.txt: the licence notices of the crates
                                 compiled into the C library and the Python package (the
                                 default features' dependencies), which both ship with it

Licence expressions are SPDX (`A OR B`, `A AND B`, `A WITH exception`, parentheses; the old
`A/B` form reads as `A OR B`). Standard library only, so that it runs before anything is
installed.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from typing import List, Set

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
NOTICES = os.path.join(ROOT, "THIRD-PARTY-LICENSES.txt")

#: Licences that let dvh's users use, change and redistribute what dvh bundles under MIT or
#: Apache-2.0 terms, keeping notices.
PERMISSIVE = {
    "MIT", "MIT-0", "Apache-2.0", "BSD-2-Clause", "BSD-3-Clause", "ISC", "Zlib", "BSL-1.0",
    "CC0-1.0", "Unlicense", "Unicode-3.0", "Unicode-DFS-2016",
}
#: Also allowed for crates that only build or test dvh and are never distributed with it.
TOOLS_ONLY = PERMISSIVE | {"MPL-2.0"}
#: The licence whose notice is kept for a crate that offers several, in this order of preference.
PREFERRED = ("MIT", "Apache-2.0", "BSD-3-Clause", "BSD-2-Clause", "ISC", "Zlib", "Unicode-3.0")
LICENCE_FILE = {
    "MIT": r"licen[cs]e[-_.]?mit",
    "Apache-2.0": r"licen[cs]e[-_.]?apache",
}


def allows(expression: str, allowed: Set[str]) -> bool:
    """Does the SPDX `expression` hold when the licences in `allowed` are acceptable?"""
    text = expression.replace("/", " OR ")
    tokens = re.findall(r"\(|\)|[A-Za-z0-9.+-]+", text)
    pos = 0

    def peek():
        return tokens[pos] if pos < len(tokens) else None

    def take():
        nonlocal pos
        pos += 1
        return tokens[pos - 1]

    def term() -> bool:
        if peek() == "(":
            take()
            v = either()
            if take() != ")":
                raise ValueError(f"unbalanced parentheses in {expression!r}")
            return v
        name = take()
        if peek() == "WITH":
            take()
            take()  # an exception only widens what the licence allows
        return name in allowed

    def joined(word: str, operand, combine) -> bool:
        # Every operand is read, whatever the ones before gave: the parse must reach the end.
        v = operand()
        while peek() == word:
            take()
            v = combine(operand(), v)
        return v

    def both() -> bool:
        return joined("AND", term, lambda x, y: x and y)

    def either() -> bool:
        return joined("OR", both, lambda x, y: x or y)

    result = either()
    if pos != len(tokens):
        raise ValueError(f"cannot read the licence expression {expression!r}")
    return result


def metadata() -> dict:
    out = subprocess.run(
        ["cargo", "metadata", "--format-version", "1", "--locked"],
        cwd=ROOT, check=True, capture_output=True, text=True,
    ).stdout
    return json.loads(out)


def reachable(meta: dict, kinds: Set[object]) -> Set[str]:
    """Package ids reachable from the workspace's members over dependency edges of `kinds`
    (None: normal; "build"; "dev")."""
    nodes = {n["id"]: n for n in meta["resolve"]["nodes"]}
    members = set(meta["workspace_members"])
    seen: Set[str] = set()
    stack = list(members)
    while stack:
        for dep in nodes[stack.pop()]["deps"]:
            if any(k["kind"] in kinds for k in dep["dep_kinds"]) and dep["pkg"] not in seen:
                if dep["pkg"] not in members:
                    seen.add(dep["pkg"])
                    stack.append(dep["pkg"])
    return seen


def bundled() -> List[str]:
    """`name version` of each crate compiled into the C library with its default features."""
    out = subprocess.run(
        ["cargo", "tree", "--locked", "-p", "dvh", "-e", "normal", "--prefix", "none", "-f", "{p}"],
        cwd=ROOT, check=True, capture_output=True, text=True,
    ).stdout
    names = set()
    for line in out.splitlines():
        parts = line.split()
        if len(parts) >= 2 and parts[0] != "dvh":
            names.add(f"{parts[0]} {parts[1].lstrip('v')}")
    return sorted(names)


def check(meta: dict) -> List[str]:
    packages = {p["id"]: p for p in meta["packages"]}
    shipped = reachable(meta, {None})
    tools = reachable(meta, {None, "build", "dev"}) - shipped
    problems = []
    for ids, allowed, what in ((shipped, PERMISSIVE, "a dependency"), (tools, TOOLS_ONLY, "a tool")):
        for i in sorted(ids, key=lambda i: packages[i]["name"]):
            p = packages[i]
            lic = p.get("license")
            if not lic:
                problems.append(f"{p['name']} {p['version']} ({what}) declares no licence")
            elif not allows(lic, allowed):
                problems.append(f"{p['name']} {p['version']} ({what}): {lic} is not allowed")
    for p in meta["packages"]:
        if p["id"] in meta["workspace_members"] and p["name"] == "dvh":
            if p.get("license") != "MIT OR Apache-2.0":
                problems.append(f"dvh's own licence is {p.get('license')!r}, not 'MIT OR Apache-2.0'")
    return problems


def notices(meta: dict) -> str:
    packages = {f"{p['name']} {p['version']}": p for p in meta["packages"]}
    parts = [
        "Third-party licences\n"
        "====================\n\n"
        "The dvh C library (libdvh) and the dvh Python package contain code from these Rust\n"
        "crates. Each is used under the first licence named below that it offers; its notice\n"
        "follows. (Generated by scripts/licences.py write.)\n"
    ]
    for key in bundled():
        p = packages[key]
        lic = p["license"]
        choice = next((c for c in PREFERRED if allows(lic, {c})), None)
        if choice is None:
            raise SystemExit(f"{key}: no preferred licence in {lic!r}")
        folder = os.path.dirname(p["manifest_path"])
        pattern = re.compile(LICENCE_FILE.get(choice, r"licen[cs]e|copying"), re.I)
        files = sorted(f for f in os.listdir(folder) if pattern.match(f))
        if not files and p.get("license_file"):
            files = [p["license_file"]]
        if not files:
            raise SystemExit(f"{key}: no {choice} licence file in its package")
        with open(os.path.join(folder, files[0]), encoding="utf-8") as f:
            text = f.read().strip()
        head = f"{p['name']} {p['version']} ({lic}), used under {choice}"
        if p.get("repository"):
            head += f"\n{p['repository']}"
        parts.append(f"\n{'-' * 78}\n{head}\n\n{text}\n")
    return "".join(parts)


def main(argv: List[str]) -> int:
    if argv[1:] not in (["check"], ["write"]):
        print(__doc__, file=sys.stderr)
        return 2
    meta = metadata()
    if argv[1] == "write":
        with open(NOTICES, "w", encoding="utf-8") as f:
            f.write(notices(meta))
        print(f"wrote {os.path.relpath(NOTICES)}")
        return 0
    problems = check(meta)
    current = open(NOTICES, encoding="utf-8").read() if os.path.exists(NOTICES) else None
    if current != notices(meta):
        problems.append("THIRD-PARTY-LICENSES.txt is out of date: run scripts/licences.py write")
    for p in problems:
        print(f"licences: {p}", file=sys.stderr)
    if not problems:
        count = len(reachable(meta, {None, "build", "dev"}))
        print(f"licences: {count} crates checked; {len(bundled())} bundled, their notices current")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
