"""Shared helpers of the Python binding tests: where the repository, the meshes, the library and
the CLI are, and a tiny OBJ reader (``v``, ``vt`` and ``f`` lines only)."""

from __future__ import annotations

import functools
import os
import subprocess
import sys
from pathlib import Path
from typing import List, Optional, Tuple

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "tests" / "data"))
import meshes  # noqa: E402  (tests/data/meshes.py: the repository's test meshes, unpacked)
HEADER = REPO / "include" / "uvflat.h"
IN_CI = os.environ.get("CI", "").lower() in ("1", "true", "yes")


def missing(reason: str) -> None:
    """Skips the test, or fails it under CI=true (where every reference must be present)."""
    if IN_CI:
        pytest.fail(reason)
    pytest.skip(reason)


def library_file() -> Path:
    """The libuvflat.so under test: $UVFLAT_LIBRARY, else the release build of this repo."""
    env = os.environ.get("UVFLAT_LIBRARY")
    return Path(env) if env else REPO / "target" / "release" / "libuvflat.so"


def cli_file() -> Path:
    """The uvflat CLI built with the library: $UVFLAT_CLI, else next to the library."""
    env = os.environ.get("UVFLAT_CLI")
    return Path(env) if env else library_file().parent / "uvflat"


def mesh_path(name: str) -> Path:
    """The plain OBJ of test mesh ``name`` (``NAME.obj``, from ``tests/data/meshes``)."""
    return meshes.mesh_path(name)


def _index(word: str, count: int) -> int:
    """0-based index of an OBJ index (1-based, or negative = relative). Index 0, which OBJ does
    not allow, becomes -1 so the binding's own check sees it."""
    i = int(word)
    return i - 1 if i > 0 else (count + i if i < 0 else -1)


def parse_obj(text: str) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(positions float64 (n, 3), triangles int64 (m, 3), vt float64 (k, 2)) of an OBJ text;
    polygons are fan-triangulated, texture indices of faces ignored, NaN/inf coordinates kept."""
    positions: List[List[float]] = []
    uvs: List[List[float]] = []
    triangles: List[List[int]] = []
    for line in text.splitlines():
        words = line.split()
        if not words:
            continue
        if words[0] == "v":
            positions.append([float(w) for w in words[1:4]])
        elif words[0] == "vt":
            uvs.append([float(w) for w in words[1:3]])
        elif words[0] == "f":
            corners = [_index(w.split("/")[0], len(positions)) for w in words[1:]]
            triangles.extend([corners[0], corners[k], corners[k + 1]] for k in range(1, len(corners) - 1))
    return (
        np.array(positions, dtype=np.float64).reshape(-1, 3),
        np.array(triangles, dtype=np.int64).reshape(-1, 3),
        np.array(uvs, dtype=np.float64).reshape(-1, 2),
    )


@functools.lru_cache(maxsize=None)
def _load(name: str) -> Tuple[np.ndarray, np.ndarray]:
    positions, triangles, _ = parse_obj(mesh_path(name).read_text())
    positions.setflags(write=False)
    triangles.setflags(write=False)
    return positions, triangles


def load_mesh(name: str) -> Tuple[np.ndarray, np.ndarray]:
    """(positions float64 (n, 3), triangles int64 (m, 3)) of a test mesh, cached
    and read-only (copy before changing them)."""
    return _load(name)


def triangles_overlap(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Whether the interiors of 2D triangles ``a[i]`` and ``b[i]`` (arrays ``(k, 3, 2)``)
    intersect, for every pair at once: the separating axis test over the six edge normals
    (touching counts as apart). Written here, independent of the library's checker."""

    def separated(p: np.ndarray, q: np.ndarray) -> np.ndarray:
        out = np.zeros(len(p), dtype=bool)
        for k in range(3):
            e = p[:, (k + 1) % 3] - p[:, k]
            n = np.stack([-e[:, 1], e[:, 0]], axis=1)
            sp = np.einsum("ij,ikj->ik", n, p)
            sq = np.einsum("ij,ikj->ik", n, q)
            tolerance = 1e-12 * np.maximum(np.abs(sp).max(axis=1), np.abs(sq).max(axis=1))
            out |= (sp.max(axis=1) <= sq.min(axis=1) + tolerance) | (sq.max(axis=1) <= sp.min(axis=1) + tolerance)
        return out

    return ~(separated(a, b) | separated(b, a))


def islands_overlap(uv_triangles: List[np.ndarray]) -> Optional[Tuple[int, int]]:
    """The first pair of islands (each a ``(k, 3, 2)`` array of UV triangles) whose triangles
    overlap, or None: exact triangle pairs between islands whose bounding boxes meet."""
    boxes = [(t.reshape(-1, 2).min(axis=0), t.reshape(-1, 2).max(axis=0)) for t in uv_triangles]
    for i in range(len(uv_triangles)):
        for j in range(i + 1, len(uv_triangles)):
            if (boxes[i][1] <= boxes[j][0]).any() or (boxes[j][1] <= boxes[i][0]).any():
                continue
            ti, tj = uv_triangles[i], uv_triangles[j]
            a = np.repeat(ti, len(tj), axis=0)
            b = np.tile(tj, (len(ti), 1, 1))
            if triangles_overlap(a, b).any():
                return i, j
    return None


def run_cli(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    """Runs the uvflat CLI; skips (fails under CI) when it was not built."""
    cli = cli_file()
    if not cli.exists():
        missing(f"{cli} not found: run `cargo build --release` (scripts/python_tests.sh does)")
    result = subprocess.run([str(cli), *args], capture_output=True, text=True)
    if check and result.returncode != 0:
        raise AssertionError(f"uvflat {' '.join(args)} failed ({result.returncode}): {result.stderr}")
    return result


def cli_unwrap(mesh: Path, tmp_path: Path, *options: str) -> Tuple[np.ndarray, str]:
    """UVs (one per vertex, from the `vt` lines) and stdout of `uvflat unwrap MESH ... --json`."""
    out = tmp_path / f"{mesh.stem}-{abs(hash(options))}.obj"
    result = run_cli("unwrap", str(mesh), "-o", str(out), "--json", *options)
    _, _, uv = parse_obj(out.read_text())
    return uv, result.stdout


def cli_error(mesh: Path) -> Optional[str]:
    """The library message the CLI prints for a mesh it rejects (without `uvflat: PATH: `)."""
    result = run_cli("info", str(mesh), check=False)
    if result.returncode == 0:
        return None
    line = result.stderr.strip().splitlines()[-1]
    prefix = f"uvflat: {mesh}: "
    return line[len(prefix):] if line.startswith(prefix) else line


@pytest.fixture(scope="session", autouse=True)
def _library_under_test() -> None:
    """Loads the library under test once, failing clearly when it is missing."""
    import uvflat

    path = library_file()
    if not path.exists():
        missing(f"{path} not found: run `cargo build --release` or set UVFLAT_LIBRARY")
    uvflat.load_library(path)
