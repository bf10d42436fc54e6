"""The repository's test meshes (``tests/data/meshes/NAME.obj.gz``) as plain OBJ files, for the
Python tests, the benchmark scripts and the programs of others (xatlas, libigl, Blender) that
read only plain OBJ.

``unpacked_dir()`` decompresses every mesh once into ``target/test-meshes/`` (each file through a
temporary name and a rename, so runs side by side never see half a file; rewritten when the
compressed file is newer) and returns that folder. ``mesh_path(name)`` does it for one mesh.

From the shell: ``python3 tests/data/meshes.py`` unpacks them all and prints the folder.
"""

from __future__ import annotations

import gzip
import os
import shutil
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
COMPRESSED = REPO / "tests" / "data" / "meshes"
UNPACKED = REPO / "target" / "test-meshes"


def names() -> list[str]:
    """Every test mesh, as ``NAME.obj``, sorted."""
    return sorted(p.name[: -len(".gz")] for p in COMPRESSED.glob("*.obj.gz"))


def mesh_path(name: str) -> Path:
    """The plain OBJ of test mesh ``name`` (``NAME.obj``), unpacked if needed; ``FileNotFoundError``
    when the repository has no such mesh."""
    source = COMPRESSED / f"{name}.gz"
    out = UNPACKED / name
    if out.exists() and out.stat().st_mtime >= source.stat().st_mtime:
        return out
    UNPACKED.mkdir(parents=True, exist_ok=True)
    partial = UNPACKED / f".{name}.{os.getpid()}"
    with gzip.open(source, "rb") as src, open(partial, "wb") as dst:
        shutil.copyfileobj(src, dst)
    os.replace(partial, out)
    return out


def unpacked_dir() -> Path:
    """The folder holding every test mesh as plain OBJ."""
    for name in names():
        mesh_path(name)
    return UNPACKED


if __name__ == "__main__":
    print(unpacked_dir())
