"""Every example in the README and docs/ runs: each fenced block tagged ``sh``/``bash``, ``c``,
``cpp`` or ``python`` in ``README.md``, ``docs/**/*.md``, ``bindings/python/README.md`` and
``blender_addon/README.md`` is executed, so a documented command or program cannot rot.

- ``sh``: ``bash -euo pipefail`` at the repository root, with the library and CLI under test
  (``UVFLAT_LIBRARY``, ``uvflat`` first on ``PATH``, ``target/release`` holding the release
  build of ``scripts/dist.sh``); files a block creates at the root are removed afterwards.
- ``c`` (C99, ``-Wall -Wextra -Werror -pedantic``) and ``cpp`` (C++17): compiled against
  ``include/`` and ``bindings/cpp/`` and the library under test, then run from the root.
- ``python``: run by this interpreter (the test venv, with the binding installed).

A block that must not run here (it installs system-wide, needs a GUI, or is the test command
itself) is preceded by a line ``<!-- not run: REASON -->``; the reason is required.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path
from typing import List, NamedTuple

import pytest

from conftest import REPO, cli_file, library_file

RUN_TAGS = {"sh": "sh", "bash": "sh", "shell": "sh", "c": "c", "cpp": "cpp", "c++": "cpp", "python": "python", "py": "python"}
FENCE = re.compile(r"^(\s*)```\s*([A-Za-z0-9_+-]*)\s*$")
NOT_RUN = re.compile(r"<!--\s*not run:\s*(\S.*?)\s*-->")


class Block(NamedTuple):
    file: str
    line: int
    kind: str
    code: str
    skip_reason: str


def doc_files() -> List[Path]:
    files = [REPO / "README.md", REPO / "bindings" / "python" / "README.md", REPO / "blender_addon" / "README.md"]
    files += sorted((REPO / "docs").rglob("*.md"))
    return [f for f in files if f.exists()]


def blocks_of(path: Path) -> List[Block]:
    lines = path.read_text().splitlines()
    found, i = [], 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        indent, tag, start = m.group(1), m.group(2).lower(), i
        j = i + 1
        while j < len(lines) and not re.match(rf"^{re.escape(indent)}```\s*$", lines[j]):
            j += 1
        if tag in RUN_TAGS:
            previous = next((lines[k] for k in range(start - 1, -1, -1) if lines[k].strip()), "")
            skip = NOT_RUN.search(previous)
            code = "\n".join(l[len(indent):] if l.startswith(indent) else l for l in lines[start + 1 : j])
            found.append(Block(str(path.relative_to(REPO)), start + 1, RUN_TAGS[tag], code + "\n", skip.group(1) if skip else ""))
        i = j + 1
    return found


BLOCKS = [b for f in doc_files() for b in blocks_of(f)]


def test_the_docs_have_examples_to_run():
    runnable = [b for b in BLOCKS if not b.skip_reason]
    assert len(runnable) >= 10, [f"{b.file}:{b.line}" for b in BLOCKS]
    assert {b.kind for b in runnable} >= {"sh", "c", "python"}, {b.kind for b in runnable}


def untracked() -> set:
    out = subprocess.run(["git", "ls-files", "--others", "--exclude-standard", "-z"], cwd=REPO, capture_output=True, text=True, check=True)
    return {p for p in out.stdout.split("\0") if p}


def uvflat_major() -> str:
    """The crate's major version (Cargo.toml), the number in the library's SONAME."""
    return re.search(r'^version = "(\d+)\.', (REPO / "Cargo.toml").read_text(), re.M).group(1)


@pytest.fixture
def user_env(tmp_path):
    """The environment of the examples: the library and CLI under test first, a private HOME."""
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    (bin_dir / "uvflat").symlink_to(cli_file())
    lib_dir = tmp_path / "lib"
    lib_dir.mkdir()
    for name in ("libuvflat.so", f"libuvflat.so.{uvflat_major()}"):  # the SONAME the loader looks for
        (lib_dir / name).symlink_to(library_file())
    env = dict(os.environ)
    env["PATH"] = f"{bin_dir}{os.pathsep}{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"
    env["UVFLAT_LIBRARY"] = str(library_file())
    env["HOME"] = str(tmp_path / "home")
    env["CARGO_HOME"] = os.environ.get("CARGO_HOME", str(Path.home() / ".cargo"))
    env["RUSTUP_HOME"] = os.environ.get("RUSTUP_HOME", str(Path.home() / ".rustup"))
    return env, lib_dir


def compile_and_run(block: Block, tmp_path: Path, env: dict, lib_dir: Path) -> subprocess.CompletedProcess:
    cpp = block.kind == "cpp"
    source = tmp_path / ("example.cpp" if cpp else "example.c")
    source.write_text(block.code)
    exe = tmp_path / "example"
    compiler = ["g++", "-std=c++17"] if cpp else ["cc", "-std=c99", "-pedantic"]
    build = compiler + ["-Wall", "-Wextra", "-Werror", f"-I{REPO / 'include'}", f"-I{REPO / 'bindings' / 'cpp'}", str(source), "-o", str(exe),
                        f"-L{lib_dir}", f"-Wl,-rpath,{lib_dir}", "-luvflat", "-lm"]
    built = subprocess.run(build, capture_output=True, text=True, env=env)
    assert built.returncode == 0, f"{block.file}:{block.line} does not compile:\n{built.stderr}"
    return subprocess.run([str(exe)], cwd=REPO, capture_output=True, text=True, env=env, timeout=600)


@pytest.mark.parametrize("block", BLOCKS, ids=[f"{b.file}:{b.line}:{b.kind}" for b in BLOCKS])
def test_documented_example_runs(block, tmp_path, user_env):
    if block.skip_reason:
        pytest.skip(f"not run: {block.skip_reason}")
    env, lib_dir = user_env
    before = untracked()
    try:
        if block.kind == "sh":
            run = subprocess.run(["bash", "-euo", "pipefail", "-c", block.code], cwd=REPO, capture_output=True, text=True, env=env, timeout=900)
        elif block.kind == "python":
            script = tmp_path / "example.py"
            script.write_text(block.code)
            run = subprocess.run([sys.executable, str(script)], cwd=REPO, capture_output=True, text=True, env=env, timeout=600)
        else:
            run = compile_and_run(block, tmp_path, env, lib_dir)
    finally:
        for created in untracked() - before:
            path = REPO / created
            shutil.rmtree(path) if path.is_dir() else path.unlink(missing_ok=True)
    assert run.returncode == 0, f"{block.file}:{block.line} ({block.kind}) failed:\n{block.code}\n--- stdout\n{run.stdout}\n--- stderr\n{run.stderr}"
