#!/usr/bin/env python3
"""Checks the module structure the workspace promises (ARCHITECTURE.md "Rules"):

1. no import cycle between the files of a crate: file A naming an item of file B (through
   `use crate::…`, `super::…`, `self::…` or an inline `crate::…` path) is an edge A → B, and the
   graph of every crate must be acyclic, except that a folder's `mod.rs` may name its own
   children (re-exports) while they name it;
2. each crate depends only on the workspace crates its layer allows (the `ALLOWED` table), in
   its `Cargo.toml` and in its code;
3. the core crate knows no C type and no command-line parsing: no `repr(C)`, `extern "C"`,
   `clap` or `serde_json` in it.

Run from the repository root; prints every violation and exits 1 if there is one. Used by the
test command (tests/python/test_architecture.py) and by hand:  python3 scripts/check_architecture.py
"""
from __future__ import annotations

import re
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CRATES = ROOT / "crates"

# Which workspace crates each crate may depend on (normal dependencies; dev-dependencies may
# add the test-support crate).
ALLOWED = {
    "uvflat-sparse": set(),
    "uvflat-core": {"uvflat-sparse"},
    "uvflat-capi": {"uvflat-core"},
    "uvflat-cli": {"uvflat-core"},
    "uvflat-test-support": {"uvflat-core"},
}
# Crates (of any origin) the core crate must not use.
CORE_FORBIDDEN = {"clap", "serde_json", "cbindgen", "libc"}

IDENT = r"[A-Za-z_][A-Za-z0-9_]*"


def strip_comments_and_strings(text: str) -> str:
    """The code without comments, string and char literals (their contents become spaces)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            depth, i = 1, i + 2
            while i < n and depth:
                if text.startswith("/*", i):
                    depth, i = depth + 1, i + 2
                elif text.startswith("*/", i):
                    depth, i = depth - 1, i + 2
                else:
                    i += 1
        elif c == "r" and re.match(r'r#*"', text[i:i + 10]) and (i == 0 or not text[i - 1].isalnum()):
            hashes = re.match(r'r(#*)"', text[i:]).group(1)
            end = text.find('"' + hashes, i + len(hashes) + 2)
            i = n if end < 0 else end + 1 + len(hashes)
            out.append('""')
        elif c == '"':
            i += 1
            while i < n and text[i] != '"':
                i += 2 if text[i] == "\\" else 1
            i += 1
            out.append('""')
        elif c == "'" and re.match(r"'(\\.|[^\\'])'", text[i:i + 4]):
            m = re.match(r"'(\\.|[^\\'])'", text[i:])
            i += len(m.group(0))
            out.append("' '")
        else:
            out.append(c)
            i += 1
    return "".join(out)


def expand_use_tree(tree: str) -> list[str]:
    """`a::{b, c::{d, e}}` → ['a::b', 'a::c::d', 'a::c::e'] (aliases and globs dropped)."""
    tree = re.sub(r"\s+", "", tree)
    brace = tree.find("{")
    if brace < 0:
        return [re.sub(r"as" + IDENT + "$", "", tree.split(" as ")[0]).removesuffix("::*")]
    prefix, inner = tree[:brace], tree[brace + 1:tree.rfind("}")]
    parts, depth, start = [], 0, 0
    for k, ch in enumerate(inner):
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append(inner[start:k])
            start = k + 1
    parts.append(inner[start:])
    paths = []
    for part in filter(None, parts):
        for sub in expand_use_tree(part):
            paths.append((prefix + sub).removesuffix("::self").removesuffix("::"))
    return paths


def module_of(src: Path, file: Path) -> tuple[str, ...]:
    rel = file.relative_to(src).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] in ("mod", "lib", "main"):
        parts.pop()
    return tuple(parts)


def referenced_paths(code: str) -> list[str]:
    paths = []
    for m in re.finditer(r"\buse\s+([^;]+);", code):
        paths.extend(expand_use_tree(m.group(1).replace(" as ", " as ")))
    for m in re.finditer(r"(?<![A-Za-z0-9_:])((?:crate|super|self)(?:::(?:super|" + IDENT + "))+)", code):
        paths.append(m.group(1))
    return paths


def resolve(path: str, here: tuple[str, ...], is_mod_file: bool, modules: set) -> tuple | None:
    """The module (file) a path names an item of, or None for other crates and std."""
    segs = path.split("::")
    if segs[0] == "crate":
        base, segs = (), segs[1:]
    elif segs[0] in ("super", "self"):
        # A file `a/b.rs` is module a::b: `self` is a::b and `super` is a. `a/mod.rs` is module a too.
        base = here
        while segs and segs[0] in ("super", "self"):
            if segs[0] == "super":
                base = base[:-1]
            segs = segs[1:]
    else:
        return None
    target = base
    for s in segs:
        if base + (s,) in modules or target + (s,) in modules:
            target = target + (s,)
        else:
            break
    return target


def crate_cycles(src: Path) -> list[list[str]]:
    files = sorted(src.rglob("*.rs"))
    mod_of = {f: module_of(src, f) for f in files}
    modules = set(mod_of.values())
    file_of = {m: f for f, m in mod_of.items()}
    edges: dict[tuple, set] = {m: set() for m in modules}
    for f, here in mod_of.items():
        code = strip_comments_and_strings(f.read_text())
        for p in referenced_paths(code):
            target = resolve(p, here, f.name == "mod.rs", modules)
            if target is None or target == here or target not in modules:
                continue
            # A parent naming its own child (declaring or re-exporting it) is not an import.
            if target[:len(here)] == here:
                continue
            edges[here].add(target)
    return [[shown(file_of[m]) for m in scc] for scc in strongly_connected(edges) if len(scc) > 1]


def shown(path: Path) -> str:
    """The path relative to the repository when it is inside it."""
    return str(path.relative_to(ROOT)) if path.is_relative_to(ROOT) else str(path)


def strongly_connected(edges: dict) -> list[list]:
    """Tarjan's algorithm, iterative."""
    index, low, on_stack, stack, result, counter = {}, {}, set(), [], [], [0]
    for root in edges:
        if root in index:
            continue
        work = [(root, iter(sorted(edges[root])))]
        index[root] = low[root] = counter[0]
        counter[0] += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            advanced = False
            for child in children:
                if child not in index:
                    index[child] = low[child] = counter[0]
                    counter[0] += 1
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(edges[child]))))
                    advanced = True
                    break
                if child in on_stack:
                    low[node] = min(low[node], index[child])
            if advanced:
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                scc = []
                while True:
                    top = stack.pop()
                    on_stack.discard(top)
                    scc.append(top)
                    if top == node:
                        break
                result.append(sorted(scc))
    return result


def crate_dependencies(manifest: Path) -> tuple[str, set, set]:
    data = tomllib.loads(manifest.read_text())
    name = data["package"]["name"]
    deps = set(data.get("dependencies", {}))
    dev = set(data.get("dev-dependencies", {}))
    return name, deps, dev


def violations(crates: Path = CRATES) -> list[str]:
    """Every violation of the rules in the crates under `crates`, one line each."""
    problems = []
    for manifest in sorted(crates.glob("*/Cargo.toml")):
        name, deps, dev = crate_dependencies(manifest)
        src = manifest.parent / "src"
        for scc in crate_cycles(src):
            problems.append(f"{name}: import cycle between {' , '.join(scc)}")
        workspace = {d for d in deps if d in ALLOWED}
        if name in ALLOWED and not workspace <= ALLOWED[name]:
            problems.append(f"{name}: depends on {sorted(workspace - ALLOWED[name])}, allowed {sorted(ALLOWED[name])}")
        if name == "uvflat-core":
            for bad in sorted(deps & CORE_FORBIDDEN):
                problems.append(f"{name}: depends on {bad}")
            for f in sorted(src.rglob("*.rs")):
                code = strip_comments_and_strings(f.read_text())
                for pattern in (r"repr\s*\(\s*C", r'extern\s+""', r"\bclap::", r"\bserde_json::"):
                    if re.search(pattern, code):
                        problems.append(f"{shown(f)}: core code matches {pattern!r}")
    if not list(crates.glob("*/Cargo.toml")):
        problems.append(f"no crates under {shown(crates)}")
    return problems


def main() -> int:
    problems = violations()
    for p in problems:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
