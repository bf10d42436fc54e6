"""The shipped artifacts of ``scripts/dist.sh`` (folder ``$UVFLAT_DIST``, which the test command
sets), used as a user would use them, with no ``UVFLAT_LIBRARY`` and nothing of this checkout on
the path:

- the wheel, installed with pip into a fresh venv, unwraps a real mesh with the library it
  carries, and its tag names this platform;
- the Blender extension zip, installed into ``bpy`` (4.5, as a module) with the command
  ``docs/blender.md`` gives, unwraps a real mesh imported from OBJ with the add-on's operator.

Skipped without ``$UVFLAT_DIST`` (failed under CI).
"""

from __future__ import annotations

import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from conftest import IN_CI, mesh_path, missing

DIST = os.environ.get("UVFLAT_DIST")


def artifact(pattern: str) -> Path:
    if not DIST:
        missing("UVFLAT_DIST is not set: run scripts/dist.sh, then point UVFLAT_DIST at its folder")
    found = sorted(Path(DIST).glob(pattern))
    assert len(found) == 1, f"expected one {pattern} in {DIST}, found {found}"
    return found[0]


def user_env(tmp_path: Path) -> dict:
    """The environment of a user who never set anything uvflat-specific."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("UVFLAT") and k not in ("PYTHONPATH", "LD_LIBRARY_PATH")}
    env["HOME"] = str(tmp_path)
    return env


UNWRAP_SCRIPT = """
import sys
import numpy as np
import uvflat
positions, triangles = [], []
for line in open(sys.argv[1]):
    if line.startswith("v "):
        positions.append([float(x) for x in line.split()[1:4]])
    elif line.startswith("f "):
        triangles.append([int(w.split("/")[0]) - 1 for w in line.split()[1:4]])
result = uvflat.unwrap(np.array(positions), np.array(triangles))
check = uvflat.check_layout(result.uv, result.triangles)
print("LIBRARY", uvflat.library_path())
print("CHECK", check.flipped, check.overlaps, result.report.islands, np.isfinite(result.uv).all())
"""


def test_wheel_installs_in_a_fresh_venv_and_unwraps_with_the_library_it_carries(tmp_path):
    wheel = artifact("uvflat-*.whl")
    tag = wheel.name.split("-")[-1]
    assert wheel.name.split("-")[2:4] == ["py3", "none"] and tag.startswith("manylinux_") and tag.endswith("_x86_64.whl"), wheel.name
    with zipfile.ZipFile(wheel) as z:
        names = z.namelist()
        assert "uvflat/libuvflat.so" in names, names
        assert "Root-Is-Purelib: false" in z.read(next(n for n in names if n.endswith(".dist-info/WHEEL"))).decode()
    venv = tmp_path / "venv"
    env = user_env(tmp_path)
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True, env=env)
    python = venv / "bin" / "python"
    install = subprocess.run([str(python), "-m", "pip", "install", "--quiet", str(wheel)], capture_output=True, text=True, env=env)
    assert install.returncode == 0, install.stdout + install.stderr
    script = tmp_path / "unwrap.py"
    script.write_text(UNWRAP_SCRIPT)
    run = subprocess.run([str(python), str(script), str(mesh_path("disk_three_peaks.obj"))], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert run.returncode == 0, run.stdout + run.stderr
    assert f"LIBRARY {venv}" in run.stdout, run.stdout
    assert "CHECK 0 0 " in run.stdout and run.stdout.rstrip().endswith("True"), run.stdout


def test_blender_extension_zip_installs_into_bpy_and_unwraps_a_real_mesh(tmp_path):
    zip_path = artifact("uvflat-blender-*.zip")
    try:
        import bpy  # noqa: F401  (the venv's bpy 4.5, which the test command installs)
    except ImportError:
        missing("bpy (PyPI, Blender 4.5 as a module) is not installed")
    with zipfile.ZipFile(zip_path) as z:
        assert "vendor/uvflat/libuvflat.so" in z.namelist()
    mesh = mesh_path("disk_nefertiti_small.obj")
    script = tmp_path / "install.py"
    script.write_text(
        "import os, sys, bpy\n"
        "bpy.ops.wm.read_factory_settings(use_empty=True)\n"
        f"assert bpy.ops.extensions.package_install_files(filepath={str(zip_path)!r}, repo='user_default', enable_on_install=True) == {{'FINISHED'}}\n"
        f"bpy.ops.wm.obj_import(filepath={str(mesh)!r})\n"
        "obj = bpy.context.selected_objects[0]\n"
        "bpy.context.view_layer.objects.active = obj\n"
        "bpy.ops.object.mode_set(mode='EDIT'); bpy.ops.mesh.select_all(action='SELECT')\n"
        "assert bpy.ops.uv.uvflat_unwrap() == {'FINISHED'}\n"
        "run = sys.modules['bl_ext.user_default.uvflat.unwrap'].LAST_RUN\n"
        "print('RUN', run['islands'], run['flipped'], run['overlaps'], len(obj.data.polygons))\n"
        "print('LIBRARY', sys.modules['bl_ext.user_default.uvflat.vendor.uvflat'].library_path())\n"
        "sys.stdout.flush(); os._exit(0)\n"
    )
    env = user_env(tmp_path)
    env["BLENDER_USER_RESOURCES"] = str(tmp_path / "blender")
    run = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=env, timeout=300, cwd=tmp_path)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "RUN 1 0 0 562" in run.stdout, run.stdout + run.stderr
    assert f"LIBRARY {tmp_path / 'blender'}" in run.stdout, run.stdout
