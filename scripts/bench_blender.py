#!/usr/bin/env python3
"""Times the Blender add-on's "uvflat Unwrap" against Blender's own UV > Unwrap (ANGLE_BASED and
CONFORMAL) on the same objects, in one run, and prints a table of medians.

Objects: bumpy quad grids of about 10k, 100k and 500k faces (z = 0.3·sin(3x)·cos(2y)), all
faces selected, one island each. Every timing is the whole operator call as a user runs it
(bpy.ops...), so uvflat's includes the Edit/Object Mode round trip, numpy island splitting,
ctypes, the solve, metrics and layout.

Needs bpy 4.5 (Python 3.11) and the binding: run it with the venv of scripts/python_tests.sh:

    target/python-venv/bin/python scripts/bench_blender.py [--sizes 10000,100000,500000]
        [--repeat N] [--skip-abf-above FACES]

UVFLAT_LIBRARY defaults to target/release/libuvflat.so (build it with cargo build --release).
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
os.environ.setdefault("UVFLAT_LIBRARY", str(REPO / "target" / "release" / "libuvflat.so"))
sys.path.insert(0, str(REPO))

import bpy  # noqa: E402
import numpy as np  # noqa: E402

import blender_addon  # noqa: E402
from blender_addon import unwrap as addon_unwrap  # noqa: E402


def bumpy_grid(faces: int):
    n = max(2, int(round(math.sqrt(faces))))
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=n + 1, y_subdivisions=n + 1, size=2)
    obj = bpy.context.object
    me = obj.data
    co = np.empty(len(me.vertices) * 3)
    me.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    co[:, 2] = 0.3 * np.sin(3 * co[:, 0]) * np.cos(2 * co[:, 1])
    me.vertices.foreach_set("co", co.ravel())
    me.update()
    return obj


def timed(call) -> float:
    start = time.perf_counter()
    result = call()
    seconds = time.perf_counter() - start
    assert result == {"FINISHED"}, result
    return seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", default="10000,100000,500000")
    parser.add_argument("--repeat", type=int, default=0, help="runs per cell (default: 3 up to 100k faces, 1 above)")
    parser.add_argument("--skip-abf-above", type=int, default=10**9, help="skip ANGLE_BASED above this many faces")
    args = parser.parse_args()

    bpy.ops.wm.read_factory_settings(use_empty=True)
    blender_addon.register()
    print(f"Blender {bpy.app.version_string}, uvflat library {os.environ['UVFLAT_LIBRARY']}", flush=True)
    rows = []
    for size in (int(s) for s in args.sizes.split(",")):
        for obj in list(bpy.data.objects):
            bpy.data.objects.remove(obj)
        obj = bumpy_grid(size)
        faces = len(obj.data.polygons)
        bpy.ops.object.mode_set(mode="EDIT")
        bpy.ops.mesh.select_all(action="SELECT")
        repeat = args.repeat or (3 if faces <= 100_000 else 1)
        cells = {}
        solve = []
        for name, call in [
            ("uvflat natural conformal", lambda: bpy.ops.uv.uvflat_unwrap(method="NATURAL_CONFORMAL")),
            ("Blender CONFORMAL", lambda: bpy.ops.uv.unwrap(method="CONFORMAL", margin=0.001)),
            ("Blender ANGLE_BASED", lambda: bpy.ops.uv.unwrap(method="ANGLE_BASED", margin=0.001)),
        ]:
            if name == "Blender ANGLE_BASED" and faces > args.skip_abf_above:
                cells[name] = float("nan")
                continue
            times = []
            for _ in range(repeat):
                times.append(timed(call))
                if name.startswith("uvflat"):
                    solve.append(addon_unwrap.LAST_RUN["solve_seconds"])
            cells[name] = statistics.median(times)
            print(f"  {faces} faces, {name}: {', '.join(f'{t:.3f}' for t in times)} s", flush=True)
        bpy.ops.object.mode_set(mode="OBJECT")
        rows.append((faces, repeat, cells, statistics.median(solve)))

    print()
    print("| faces | runs | uvflat natural conformal (s) | of which library solve (s) | Blender CONFORMAL (s) | Blender ANGLE_BASED (s) | CONFORMAL / uvflat |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    for faces, repeat, cells, solve in rows:
        ours = cells["uvflat natural conformal"]
        conf = cells["Blender CONFORMAL"]
        abf = cells["Blender ANGLE_BASED"]
        abf_text = "skipped" if math.isnan(abf) else f"{abf:.3f}"
        print(f"| {faces} | {repeat} | {ours:.3f} | {solve:.3f} | {conf:.3f} | {abf_text} | {conf / ours:.1f}× |")


if __name__ == "__main__":
    main()
