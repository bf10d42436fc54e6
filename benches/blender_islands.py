#!/usr/bin/env python3
"""The Blender add-on against Blender 4.5's own unwrap (PyPI `bpy`) on many small islands.

An N × N quad grid with every edge a seam (N² one-face islands) is unwrapped in Edit Mode with
everything selected, alternately by Blender's `bpy.ops.uv.unwrap(method='ANGLE_BASED')` and by
the add-on's `bpy.ops.uv.uvflat_unwrap()` (natural conformal, the add-on's defaults; reading
the mesh, splitting the islands, solving, laying out, writing back, measuring), REPEATS times
each; it prints one Markdown row per grid size with the median wall seconds and their ratio.
What it measures is the per-island cost outside the solver (Python, numpy and library calls).

Usage (a venv with `bpy==4.5.*` and numpy; Blender's wheels need CPython 3.11):
  cargo build --release
  python benches/blender_islands.py [--repeats N] [--sizes 33,73]
  (UVFLAT_LIBRARY may point at the library, default target/release/libuvflat.so)
"""
import argparse
import os
import statistics
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def seamed_grid(bpy, n: int):
    """An n × n grid, every edge a seam, in Edit Mode with every face selected."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=n, y_subdivisions=n, size=2)
    me = bpy.context.object.data
    me.edges.foreach_set("use_seam", [True] * len(me.edges))
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    return len(me.polygons)


def timed(call) -> float:
    start = time.perf_counter()
    result = call()
    assert result == {"FINISHED"}, result
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--sizes", default="33,73")
    args = parser.parse_args()
    os.environ.setdefault("UVFLAT_LIBRARY", os.path.join(ROOT, "target", "release", "libuvflat.so"))
    sys.path.insert(0, ROOT)
    sys.path.insert(0, os.path.join(ROOT, "bindings", "python"))
    import bpy  # type: ignore[import-not-found]

    import blender_addon

    print("| grid | islands | Blender ANGLE_BASED s | uvflat add-on s | uvflat / Blender |")
    print("|---|--:|--:|--:|--:|")
    for n in (int(s) for s in args.sizes.split(",")):
        faces = seamed_grid(bpy, n)
        blender_addon.register()
        ours, theirs = [], []
        for _ in range(args.repeats):
            theirs.append(timed(lambda: bpy.ops.uv.unwrap(method="ANGLE_BASED", margin=0.001)))
            ours.append(timed(lambda: bpy.ops.uv.uvflat_unwrap()))
        blender_addon.unregister()
        b, u = statistics.median(theirs), statistics.median(ours)
        print(f"| {n} × {n} | {faces} | {b:.3f} | {u:.3f} | {u / b:.1f}× |", flush=True)


if __name__ == "__main__":
    main()
