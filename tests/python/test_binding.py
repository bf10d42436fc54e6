"""Tests of the Python ctypes binding (bindings/python) against the built libuvflat.so.

Run with scripts/python_tests.sh, which builds the library, installs the binding in a venv and
sets UVFLAT_LIBRARY. Meshes come from tests/data/meshes; the CLI (target/release/uvflat) is
the reference the binding's results must equal.
"""

from __future__ import annotations

import ctypes
import json
import math
import os
import re
import shutil
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import uvflat
from uvflat import _common, _errors, _library
from conftest import (
    HEADER,
    REPO,
    cli_error,
    cli_unwrap,
    islands_overlap,
    library_file,
    load_mesh,
    mesh_path,
    missing,
    parse_obj,
    run_cli,
)

# A flat unit square folded along its diagonal (the README's C example).
SQUARE_P = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0.3], [0, 1, 0]], dtype=np.float64)
SQUARE_T = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.uint32)


def canonical(name: str):
    """A test mesh as the binding wants it: float64 positions, uint32 triangles."""
    p, t = load_mesh(name)
    return p, t.astype(np.uint32)


def assert_uv_equal(actual: np.ndarray, expected: np.ndarray, referenced: np.ndarray) -> None:
    """Equal to 1e-12 on referenced vertices (the CLI writes `vt 0 0` for the others)."""
    assert actual.shape == expected.shape
    np.testing.assert_allclose(actual[referenced], expected[referenced], rtol=0, atol=1e-12)


def referenced_mask(n: int, triangles: np.ndarray) -> np.ndarray:
    mask = np.zeros(n, dtype=bool)
    mask[np.asarray(triangles, dtype=np.int64).ravel()] = True
    return mask


# --- the library, its header and the ctypes declarations --------------------------------------


def test_version_and_abi_version_match_the_crate_and_the_header():
    cargo = (REPO / "Cargo.toml").read_text()
    crate_version = re.search(r'^version\s*=\s*"([^"]+)"', cargo, re.M).group(1)
    assert uvflat.version() == crate_version
    header_abi = int(re.search(r"#define UVF_ABI_VERSION (\d+)", HEADER.read_text()).group(1))
    assert uvflat.abi_version() == uvflat.ABI_VERSION == header_abi


def test_the_thread_count_is_set_before_the_workers_exist_and_fixed_after():
    # A fresh interpreter: in this one earlier tests have already started the workers.
    script = (
        "import uvflat\n"
        "uvflat.set_thread_count(1)\n"
        "assert uvflat.thread_count() == 1, uvflat.thread_count()\n"
        "try:\n"
        "    uvflat.set_thread_count(3)\n"
        "except uvflat.InvalidArgument as e:\n"
        "    assert 'already' in str(e), e\n"
        "else:\n"
        "    raise AssertionError('the thread count changed after the workers existed')\n"
        "print('ok')\n"
    )
    env = dict(os.environ, UVFLAT_LIBRARY=str(library_file()))
    out = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr


def blender_like_mesh():
    """Float positions in a 32-byte structured vertex array (co, normal, flags), quads and one
    convex 8-gon (a half disk above the grid's last top edge); and the same mesh as packed
    doubles with fan triangles."""
    gx, gy, rim = 7, 5, 6
    vertex = np.dtype([("co", np.float32, 3), ("normal", np.float32, 3), ("flags", np.uint32), ("pad", np.uint32)])
    vertices = np.zeros(gx * gy + rim, dtype=vertex)
    x, y = np.meshgrid(np.linspace(0, 1, gx), np.linspace(0, 1, gy))
    grid = np.stack([x.ravel(), y.ravel(), 0.2 * np.sin(3 * x.ravel()) * np.cos(2 * y.ravel())], axis=1)
    vertices["co"][: gx * gy] = grid
    a, b = grid[gx * gy - 2], grid[gx * gy - 1]
    angles = np.pi * np.arange(1, rim + 1) / (rim + 1)
    s = 0.5 + 0.5 * np.cos(angles)
    r = 0.5 * (b[0] - a[0])
    arc = np.stack([0.5 * (a[0] + b[0]) + r * np.cos(angles), 1 + r * np.sin(angles), a[2] + s * (b[2] - a[2])], axis=1)
    vertices["co"][gx * gy :] = arc
    faces, sizes = [], []
    for j in range(gy - 1):
        for i in range(gx - 1):
            v = j * gx + i
            faces += [v, v + 1, v + 1 + gx, v + gx]
            sizes.append(4)
    faces += [gx * gy - 2, gx * gy - 1] + list(range(gx * gy, gx * gy + rim))
    sizes.append(2 + rim)
    fan, start = [], 0
    for n in sizes:
        fan += [[faces[start], faces[start + k], faces[start + k + 1]] for k in range(1, n - 1)]
        start += n
    return vertices, np.array(faces, dtype=np.uint32), np.array(sizes), vertices["co"].astype(np.float64), np.array(fan)


def test_a_mesh_handle_of_float_strided_polygons_gives_the_flat_calls_results():
    vertices, faces, sizes, packed, fan = blender_like_mesh()
    assert vertices["co"].strides[0] == 32  # read in place, at its stride
    mesh = uvflat.Mesh(vertices["co"], faces, face_sizes=sizes)
    assert (mesh.vertex_count, mesh.triangle_count, mesh.corner_count) == (len(packed), len(fan), len(faces))
    np.testing.assert_array_equal(mesh.triangles, fan)
    np.testing.assert_array_equal(mesh.triangle_faces, np.repeat(np.arange(len(sizes)), sizes - 2))
    np.testing.assert_array_equal(uvflat.natural_conformal_map(mesh), uvflat.natural_conformal_map(packed, fan))
    np.testing.assert_array_equal(uvflat.abf(mesh)[0], uvflat.abf(packed, fan)[0])
    np.testing.assert_array_equal(
        uvflat.fixed_boundary_map(mesh, weights="floater"), uvflat.fixed_boundary_map(packed, fan, weights="floater")
    )
    np.testing.assert_array_equal(uvflat.nonlinear_map(mesh, method="slim")[0], uvflat.nonlinear_map(packed, fan, "slim")[0])
    result = uvflat.unwrap(mesh)
    assert result.report.flipped == 0 and result.report.overlaps == 0
    per_face_corner = mesh.face_corner_uv(result.corner_uv)
    assert per_face_corner.shape == (len(faces), 2) and np.isfinite(per_face_corner).all()
    mesh16 = uvflat.Mesh(vertices["co"], faces.astype(np.uint16), face_sizes=sizes)
    np.testing.assert_array_equal(uvflat.natural_conformal_map(mesh16), uvflat.natural_conformal_map(mesh))
    mesh.close()
    with pytest.raises(uvflat.InvalidArgument, match="closed"):
        uvflat.natural_conformal_map(mesh)


def test_a_mesh_handle_refuses_bad_faces_naming_them():
    vertices, faces, sizes, _, _ = blender_like_mesh()
    bad = sizes.copy()
    bad[2], bad[3] = 2, 6
    with pytest.raises(uvflat.InvalidArgument, match="face 2"):
        uvflat.Mesh(vertices["co"], faces, face_sizes=bad)
    repeated = faces.copy()
    repeated[5] = repeated[4]
    with pytest.raises(uvflat.InvalidMesh, match="face 1"):
        uvflat.Mesh(vertices["co"], repeated, face_sizes=sizes)
    with pytest.raises(uvflat.InvalidArgument, match="triangles must be None"):
        uvflat.natural_conformal_map(uvflat.Mesh(vertices["co"], faces, face_sizes=sizes), faces)


def header_functions():
    """{name: (return type, [parameter declarations])} of every function in uvflat.h."""
    text = re.sub(r"/\*.*?\*/", "", HEADER.read_text(), flags=re.S)
    found = {}
    for ret, name, params in re.findall(r"^([A-Za-z_][\w ]*?[\s*]+)(uvf_\w+)\(([^)]*)\);", text, re.M | re.S):
        parts = [p.strip() for p in params.split(",")]
        found[name] = (ret.strip(), [] if parts == ["void"] else parts)
    return found


C_TYPES = {
    "const double *": ctypes.POINTER(ctypes.c_double),
    "double *": ctypes.POINTER(ctypes.c_double),
    "const uint32_t *": ctypes.POINTER(ctypes.c_uint32),
    "uint32_t *": ctypes.POINTER(ctypes.c_uint32),
    "const uint8_t *": ctypes.POINTER(ctypes.c_uint8),
    "uint8_t *": ctypes.POINTER(ctypes.c_uint8),
    "size_t": ctypes.c_size_t,
    "double": ctypes.c_double,
    "uint32_t": ctypes.c_uint32,
    "size_t *": ctypes.POINTER(ctypes.c_size_t),
    "int32_t *": ctypes.POINTER(ctypes.c_int32),
    "char *": ctypes.c_char_p,
    "int": ctypes.c_int,
}


def c_type(text):
    """The ctypes type a header parameter type must be declared with.

    Structs map by name onto the class of the same name in ``_library``, so a
    struct the binding does not define fails here with its name."""
    if text in C_TYPES:
        return C_TYPES[text]
    match = re.fullmatch(r"(?:const )?struct (\w+) (\*+)", text)
    assert match, f"unknown C type {text!r}"
    struct = getattr(_library, match.group(1))
    pointer = ctypes.POINTER(struct)
    return pointer if len(match.group(2)) == 1 else ctypes.POINTER(pointer)


C_RETURNS = {
    "enum UvfStatus": ctypes.c_int,
    "const char *": ctypes.c_char_p,
    "uint32_t": ctypes.c_uint32,
    "size_t": ctypes.c_size_t,
    "void": None,
}


def test_every_header_function_is_declared_with_the_header_prototype():
    functions = header_functions()
    assert len(functions) == 131, sorted(functions)
    assert set(functions) == set(_library.PROTOTYPES)
    lib = uvflat.load_library(library_file())
    for name, (ret, params) in functions.items():
        restype, argtypes = _library.PROTOTYPES[name]
        assert restype is C_RETURNS[ret], name
        declared = [c_type(re.sub(r"\w+$", "", p).strip()) for p in params]
        assert list(argtypes) == declared, name
        assert list(getattr(lib, name).argtypes) == declared and getattr(lib, name).restype is restype


def test_constants_and_status_codes_match_the_header():
    text = HEADER.read_text()
    defines = {k: int(v) for k, v in re.findall(r"#define (UVF_\w+) (\d+)", text)}
    for version_macro in ("UVF_ABI_VERSION", "UVF_VERSION_MAJOR", "UVF_VERSION_MINOR", "UVF_VERSION_PATCH"):
        defines.pop(version_macro)
    assert defines, "no constants found in the header"
    for name, value in defines.items():
        assert getattr(uvflat, name) == value, name
    statuses = {k: int(v) for k, v in re.findall(r"^\s*UVF_(\w+) = (\d+),", text, re.M)}
    assert statuses == {s.name: s.value for s in uvflat.Status}


STRUCTS = {
    "UvfMeshInfo": _library.UvfMeshInfo,
    "UvfPolygonIslandsInfo": _library.UvfPolygonIslandsInfo,
    "UvfPackOptions": _library.UvfPackOptions,
    "UvfSnappedRepairInfo": _library.UvfSnappedRepairInfo,
    "UvfPackReport": _library.UvfPackReport,
    "UvfFixedBoundaryOptions": _library.UvfFixedBoundaryOptions,
    "UvfNaturalConformalOptions": _library.UvfNaturalConformalOptions,
    "UvfMetrics": _library.UvfMetrics,
    "UvfAbfOptions": _library.UvfAbfOptions,
    "UvfAbfReport": _library.UvfAbfReport,
    "UvfCirclePatternOptions": _library.UvfCirclePatternOptions,
    "UvfCirclePatternReport": _library.UvfCirclePatternReport,
    "UvfConePlacementOptions": _library.UvfConePlacementOptions,
    "UvfQuadCoverOptions": _library.UvfQuadCoverOptions,
    "UvfQuadCoverReport": _library.UvfQuadCoverReport,
    "UvfIntrinsicToolOptions": _library.UvfIntrinsicToolOptions,
    "UvfPointConstraint": _library.UvfPointConstraint,
    "UvfNonlinearOptions": _library.UvfNonlinearOptions,
    "UvfNonlinearReport": _library.UvfNonlinearReport,
    "UvfCutOptions": _library.UvfCutOptions,
    "UvfCutInfo": _library.UvfCutInfo,
    "UvfSphereOptions": _library.UvfSphereOptions,
    "UvfAtlasOptions": _library.UvfAtlasOptions,
    "UvfAtlasInfo": _library.UvfAtlasInfo,
    "UvfUnwrapOptions": _library.UvfUnwrapOptions,
    "UvfUnwrapReport": _library.UvfUnwrapReport,
    "UvfLayoutCheck": _library.UvfLayoutCheck,
    "UvfSpectralOptions": _library.UvfSpectralOptions,
    "UvfSpectralReport": _library.UvfSpectralReport,
    "UvfIntrinsicOptimalOptions": _library.UvfIntrinsicOptimalOptions,
    "UvfIntrinsicOptimalReport": _library.UvfIntrinsicOptimalReport,
    "UvfBoundaryOptimizationOptions": _library.UvfBoundaryOptimizationOptions,
    "UvfBoundaryOptimizationReport": _library.UvfBoundaryOptimizationReport,
    "UvfCurvatureOptions": _library.UvfCurvatureOptions,
    "UvfPgpOptions": _library.UvfPgpOptions,
    "UvfPgpInfo": _library.UvfPgpInfo,
    "UvfQuadMeshInfo": _library.UvfQuadMeshInfo,
    "UvfChartLayoutInfo": _library.UvfChartLayoutInfo,
    "UvfPgpChartsInfo": _library.UvfPgpChartsInfo,
    "UvfMeshDesc": _library.UvfMeshDesc,
}


def test_every_header_struct_is_checked_for_layout():
    defined = set(re.findall(r"^typedef struct (Uvf\w+) \{|^struct (Uvf\w+) \{", HEADER.read_text(), re.M))
    names = {a or b for a, b in defined}
    assert names == set(STRUCTS), sorted(names ^ set(STRUCTS))


def c_name(field: str) -> str:
    return "lambda" if field == "lambda_" else field


def test_struct_layouts_match_the_c_compiler(tmp_path):
    """sizeof and every offsetof, as a C compiler sees uvflat.h, equal the ctypes mirror."""
    cc = shutil.which(os.environ.get("CC", "cc")) or shutil.which("gcc") or shutil.which("clang")
    if cc is None:
        missing("no C compiler (cc) to measure the header's struct layouts")
    lines = []
    for struct, cls in STRUCTS.items():
        lines.append(f'printf("{struct} sizeof %zu\\n", sizeof(struct {struct}));')
        for field, _ in cls._fields_:
            lines.append(f'printf("{struct} {field} %zu\\n", offsetof(struct {struct}, {c_name(field)}));')
    source = tmp_path / "layout.c"
    source.write_text(
        "#include <stddef.h>\n#include <stdio.h>\n#include \"uvflat.h\"\nint main(void) {\n"
        + "\n".join("    " + line for line in lines)
        + "\n    return 0;\n}\n"
    )
    exe = tmp_path / "layout"
    subprocess.run([cc, "-std=c99", "-I", str(HEADER.parent), str(source), "-o", str(exe)], check=True)
    measured = {}
    for line in subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout.splitlines():
        struct, field, value = line.split()
        measured[(struct, field)] = int(value)
    for struct, cls in STRUCTS.items():
        assert ctypes.sizeof(cls) == measured[(struct, "sizeof")], struct
        for field, _ in cls._fields_:
            assert getattr(cls, field).offset == measured[(struct, field)], (struct, field)


def test_options_struct_size_round_trips_through_the_default_functions():
    lib = uvflat.load_library(library_file())
    fixed = _library.UvfFixedBoundaryOptions()
    lib.uvf_fixed_boundary_options_default(ctypes.byref(fixed))
    assert fixed.struct_size == ctypes.sizeof(_library.UvfFixedBoundaryOptions)
    assert (fixed.weights, fixed.boundary, fixed.distribution) == (
        uvflat.UVF_WEIGHTS_MEAN_VALUE,
        uvflat.UVF_BOUNDARY_CIRCLE,
        uvflat.UVF_DISTRIBUTION_CHORD,
    )
    assert (fixed.lambda_, fixed.mu, fixed.given_count, bool(fixed.progress)) == (1.0, 0.0, 0, False)
    natural = _library.UvfNaturalConformalOptions()
    lib.uvf_natural_conformal_options_default(ctypes.byref(natural))
    assert natural.struct_size == ctypes.sizeof(_library.UvfNaturalConformalOptions)
    assert natural.pin_count == 0 and not natural.progress
    lib.uvf_fixed_boundary_options_default(None)  # NULL is allowed and ignored


# --- finding the library ----------------------------------------------------------------------


def run_python(code: str, env: dict, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, env=env, cwd=cwd
    )


def clean_env(**extra: str) -> dict:
    env = {k: v for k, v in os.environ.items() if k not in ("UVFLAT_LIBRARY", "LD_LIBRARY_PATH", "PYTHONPATH")}
    env.update(extra)
    return env


def test_explicit_path_comes_before_the_environment_variable(tmp_path):
    result = run_python(
        f"""
        import uvflat
        uvflat.load_library({str(library_file())!r})
        print(uvflat.library_path()); print(uvflat.version())
        """,
        clean_env(UVFLAT_LIBRARY=str(tmp_path / "nowhere.so")),
        tmp_path,
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout.split() == [str(library_file()), uvflat.version()]


def test_environment_variable_is_used_and_a_wrong_one_is_an_error(tmp_path):
    good = run_python(
        "import uvflat; print(uvflat.library_path())", clean_env(UVFLAT_LIBRARY=str(library_file())), tmp_path
    )
    assert good.returncode == 0, good.stderr
    assert good.stdout.strip() == str(library_file())
    bad = run_python(
        """
        import uvflat
        try:
            uvflat.mesh_info([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        except uvflat.LibraryError as e:
            print("LibraryError:", e)
        """,
        clean_env(UVFLAT_LIBRARY=str(tmp_path / "nowhere.so")),
        tmp_path,
    )
    assert bad.returncode == 0, bad.stderr
    assert bad.stdout.startswith("LibraryError: cannot load libuvflat") and "nowhere.so" in bad.stdout


def test_a_library_copied_into_the_package_directory_is_found(tmp_path):
    package = tmp_path / "site" / "uvflat"
    shutil.copytree(Path(uvflat.__file__).parent, package, ignore=shutil.ignore_patterns("*.so", "__pycache__"))
    shutil.copy(library_file(), package / "libuvflat.so")
    result = run_python(
        "import uvflat; print(uvflat.__file__); print(uvflat.library_path()); print(uvflat.version())",
        clean_env(PYTHONPATH=str(tmp_path / "site")),
        tmp_path,
    )
    assert result.returncode == 0, result.stderr
    module, path, version = result.stdout.split()
    assert Path(module).parent == package and Path(path) == package / "libuvflat.so"
    assert version == uvflat.version()


def test_the_system_search_path_is_the_last_resort(tmp_path):
    result = run_python(
        "import uvflat; print(uvflat.library_path()); print(uvflat.version())",
        clean_env(LD_LIBRARY_PATH=str(library_file().parent)),
        tmp_path,
    )
    assert result.returncode == 0, result.stderr
    path, version = result.stdout.split()
    assert "uvflat" in path and version == uvflat.version()


def test_a_library_with_another_abi_version_is_refused(monkeypatch):
    before = uvflat.library_path()
    monkeypatch.setattr(_library, "ABI_VERSION", 99)
    with pytest.raises(uvflat.LibraryError, match="ABI version 1 but this uvflat binding was written for ABI version 99"):
        uvflat.load_library(library_file())
    monkeypatch.undo()
    assert uvflat.library_path() == before  # the library in use stays
    assert uvflat.mesh_info(SQUARE_P, SQUARE_T).triangles == 2


# --- topology ---------------------------------------------------------------------------------

TOPOLOGY_MESHES = [
    "disk_cat_head.obj",
    "holes_pig.obj",
    "holes_elephant.obj",
    "closed_g1_bob.obj",
    "closed_g2_eight.obj",
    "bad_unreferenced_vertices.obj",
]


@pytest.mark.parametrize("name", TOPOLOGY_MESHES)
def test_mesh_info_equals_the_cli(name):
    p, t = load_mesh(name)
    info = uvflat.mesh_info(p, t)
    cli = json.loads(run_cli("info", str(mesh_path(name)), "--json").stdout)
    assert info == uvflat.MeshInfo(
        vertices=cli["vertices"],
        referenced_vertices=cli["referenced_vertices"],
        triangles=cli["faces"],
        edges=cli["edges"],
        components=cli["components"],
        boundary_loops=cli["boundary_loops"],
        boundary_vertices=info.boundary_vertices,
        euler_characteristic=cli["euler_characteristic"],
        genus=cli["genus"],
    )
    assert info.euler_characteristic == info.referenced_vertices - info.edges + info.triangles


@pytest.mark.parametrize("name", TOPOLOGY_MESHES)
def test_boundary_loops_follow_boundary_edges_counter_clockwise(name):
    p, t = load_mesh(name)
    info = uvflat.mesh_info(p, t)
    loops = uvflat.boundary_loops(p, t)
    assert len(loops) == info.boundary_loops
    assert sum(len(lp) for lp in loops) == info.boundary_vertices
    directed = {(int(a), int(b)) for tri in t for a, b in ((tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0]))}
    boundary = {(a, b) for a, b in directed if (b, a) not in directed}
    walked = set()
    for lp in loops:
        assert lp.dtype == np.uint32
        for a, b in zip(lp, np.roll(lp, -1)):
            walked.add((int(a), int(b)))
    assert walked == boundary  # every boundary edge once, in the triangles' direction


def _reference_polygon_islands(corners, sizes, selected, seams):
    """Islands and island vertices written out plainly (dicts and a union-find in Python), to
    check ``uvflat.polygon_islands`` against: faces join across edges used twice in the whole
    mesh, both selected, opposite directions, no seam; corners join across the same edges."""
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    face_of, next_of = {}, {}
    for f, (a, n) in enumerate(zip(starts, sizes)):
        for k in range(n):
            face_of[a + k] = f
            next_of[a + k] = a + (k + 1) % n
    parent = {}

    def find(x):
        while parent.setdefault(x, x) != x:
            x = parent[x]
        return x

    def join(x, y):
        rx, ry = find(x), find(y)
        if rx != ry:
            parent[rx] = ry

    uses = {}
    for c in range(len(corners)):
        uses.setdefault(frozenset((corners[c], corners[next_of[c]])), []).append(c)
    for cs in uses.values():
        if len(cs) != 2:
            continue
        c, d = cs
        if not (selected[face_of[c]] and selected[face_of[d]]) or seams[c] or seams[d] or face_of[c] == face_of[d]:
            continue
        if corners[c] == corners[d]:
            continue
        join(("f", face_of[c]), ("f", face_of[d]))
        join(("c", c), ("c", next_of[d]))
        join(("c", next_of[c]), ("c", d))
    face_class = [find(("f", f)) if selected[f] else None for f in range(len(sizes))]
    corner_class = [find(("c", c)) if selected[face_of[c]] else None for c in range(len(corners))]
    return face_class, corner_class


def test_polygon_islands_match_a_plain_reference_on_a_real_mesh_with_random_seams():
    _, t = load_mesh("disk_cat_head.obj")
    rng = np.random.default_rng(7)
    corners = t.reshape(-1)
    sizes = np.full(len(t), 3)
    selected = rng.random(len(t)) < 0.8
    seams = rng.random(len(corners)) < 0.08
    found = uvflat.polygon_islands(corners, sizes, selected=selected, seams=seams)
    face_class, corner_class = _reference_polygon_islands(corners, sizes, selected, seams)
    assert found.islands == len({c for c in face_class if c is not None}) > 1
    assert found.island_vertices == len({c for c in corner_class if c is not None})
    # The same partitions, and the documented numbering: islands by lowest face, island
    # vertices island by island.
    assert (found.face_island[~selected] == uvflat.NOT_IN_AN_ISLAND).all()
    by_class = {}
    for f in np.flatnonzero(selected):
        assert by_class.setdefault(face_class[f], found.face_island[f]) == found.face_island[f]
    first_faces = [np.flatnonzero(found.face_island == i)[0] for i in range(found.islands)]
    assert first_faces == sorted(first_faces)
    vertex_of = {}
    for c, cls in enumerate(corner_class):
        if cls is None:
            assert found.corner_vertex[c] == uvflat.NOT_IN_AN_ISLAND
            continue
        assert vertex_of.setdefault(cls, found.corner_vertex[c]) == found.corner_vertex[c]
    assert len(set(vertex_of.values())) == len(vertex_of)
    island_of_vertex = np.empty(found.island_vertices, dtype=np.int64)
    used = np.flatnonzero(found.corner_vertex != uvflat.NOT_IN_AN_ISLAND)
    island_of_vertex[found.corner_vertex[used]] = found.face_island[used // 3]
    assert (np.diff(island_of_vertex) >= 0).all()


def test_polygon_islands_of_a_mesh_without_faces_are_none():
    # (An edges-only object in Blender's multi-object Edit Mode.)
    found = uvflat.polygon_islands(np.zeros(0, dtype=np.uint32), np.zeros(0, dtype=np.uint32), vertex_count=4)
    assert (found.islands, found.island_vertices, len(found.face_island)) == (0, 0, 0)


def test_polygon_islands_refuse_bad_input():
    with pytest.raises(uvflat.InvalidArgument, match="vertices"):
        uvflat.polygon_islands([0, 1, 2, 3], [4], vertex_count=3)
    with pytest.raises(uvflat.InvalidArgument, match="add up"):
        uvflat.polygon_islands([0, 1, 2, 3], [3])
    with pytest.raises(uvflat.InvalidArgument, match="flags"):
        uvflat.polygon_islands([0, 1, 2], None, seams=[True])


def test_pack_islands_moves_islands_rigidly_apart_at_one_texel_density():
    p, t = load_mesh("closed_g0_decimated_knight.obj")
    layout = uvflat.unwrap(p, t, max_stretch=1.05)
    assert layout.report.islands > 10
    # Scramble the islands: each turned, scaled and put at the origin, all on top of each other.
    rng = np.random.default_rng(3)
    uv = layout.uv.copy()
    island = uvflat.pack_islands(layout.uv, layout.triangles).island
    vertex_island = np.empty(len(uv), dtype=np.int64)
    vertex_island[layout.triangles.reshape(-1)] = np.repeat(island, 3)
    for i in range(int(island.max()) + 1):
        v = vertex_island == i
        angle, scale = rng.uniform(0, 2 * np.pi), rng.uniform(0.2, 5.0)
        r = scale * np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
        uv[v] = (uv[v] - uv[v].mean(axis=0)) @ r.T
    packed = uvflat.pack_islands(uv, layout.triangles, p, t, margin=0.01)
    q = packed.uv
    assert packed.islands == int(island.max()) + 1 and 0 < packed.utilization <= 1
    assert (q >= -1e-12).all() and (q <= 1 + 1e-12).all()
    # Rigid per island (up to one uniform scale): every edge length ratio equal, no mirroring.
    density = []
    area3 = 0.5 * np.linalg.norm(np.cross(p[t[:, 1]] - p[t[:, 0]], p[t[:, 2]] - p[t[:, 0]]), axis=1)
    for i in range(packed.islands):
        tri = layout.triangles[packed.island == i]
        a, b = uv[tri], q[tri]
        la = np.linalg.norm(a[:, 1] - a[:, 0], axis=1)
        lb = np.linalg.norm(b[:, 1] - b[:, 0], axis=1)
        ratio = lb / la
        assert np.allclose(ratio, ratio[0], rtol=1e-9)
        sa = np.cross(a[:, 1] - a[:, 0], a[:, 2] - a[:, 0])
        sb = np.cross(b[:, 1] - b[:, 0], b[:, 2] - b[:, 0])
        assert (np.sign(sa) == np.sign(sb)).all()
        density.append(0.5 * np.abs(sb).sum() / area3[packed.island == i].sum())
    assert np.allclose(density, density[0], rtol=1e-9), "one texel density over all islands"
    # No two islands overlap (exact per-triangle test between islands whose boxes meet).
    assert islands_overlap([q[layout.triangles[packed.island == i]] for i in range(packed.islands)]) is None
    # The check itself: the scrambled input, every island at the origin, overlaps.
    assert islands_overlap([uv[layout.triangles[packed.island == i]] for i in range(packed.islands)]) is not None
    with pytest.raises(uvflat.InvalidArgument, match="margin"):
        uvflat.pack_islands(uv, layout.triangles, margin=0.5)
    with pytest.raises(uvflat.InvalidArgument, match="no UV area"):
        uvflat.pack_islands([[0, 0], [1, 1], [2, 2]], [[0, 1, 2]])


def test_triangle_components_label_each_connected_part():
    p, t = load_mesh("disk_cat_head.obj")
    q, s = load_mesh("closed_g1_bob.obj")
    positions = np.vstack([p, q + 10.0])
    triangles = np.vstack([t, s + len(p)])
    components = uvflat.triangle_components(positions, triangles)
    assert components.dtype == np.uint32 and components.shape == (len(triangles),)
    first, second = components[: len(t)], components[len(t):]
    assert len(set(first)) == 1 and len(set(second)) == 1 and first[0] != second[0]
    assert set(components) == {0, 1}
    assert uvflat.mesh_info(positions, triangles).components == 2


def test_snapped_repair_welds_snapped_vertices_and_the_repaired_mesh_solves():
    p, t = load_mesh("disk_cat_head.obj")
    snapped = p.copy()
    # Snap five vertices onto a neighbour each (a modeller's snap without merge), pairs far apart.
    movers, taken = [], set()
    for a, b in t[:: max(1, len(t) // 7), :2]:
        if len(movers) < 5 and not {int(a), int(b)} & taken:
            movers.append((int(a), int(b)))
            taken |= {int(a), int(b)}
    for a, b in movers:
        snapped[b] = snapped[a]
    with pytest.raises(uvflat.InvalidMesh, match="degenerate"):
        uvflat.mesh_info(snapped, t)
    r = uvflat.snapped_repair(snapped, t)
    assert r.welded == len(movers) and r.vertices == len(p) - len(movers) and r.unreferenced == 0
    for a, b in movers:
        assert r.vertex[a] == r.vertex[b]
    # Left out: exactly the triangles holding both ends of a snapped pair (written out here).
    holds_pair = np.array([any(a in tri and b in tri for a, b in movers) for tri in t])
    assert (~r.keep == holds_pair).all() and r.left_out == holds_pair.sum()
    first = np.unique(r.vertex, return_index=True)[1]
    solved = uvflat.natural_conformal_map(snapped[first], r.vertex[t[r.keep]])
    uv = solved[r.vertex]
    assert np.isfinite(uv).all()
    assert uvflat.check_layout(uv, t[r.keep]).flipped == 0
    # The default unwrap takes the snapped mesh as it is and does the same.
    result = uvflat.unwrap(snapped, t)
    assert (result.report.welded_vertices, result.report.left_out_triangles) == (len(movers), holds_pair.sum())
    kept = result.triangles[~holds_pair]
    check = uvflat.check_layout(result.uv, kept)
    assert (check.flipped, check.overlaps) == (0, 0)
    onto = np.arange(len(p))  # a welded pair maps back to its lower vertex
    for a, b in movers:
        onto[a] = onto[b] = min(a, b)
    assert (result.original_vertices[result.triangles] == onto[t]).all()
    untouched = uvflat.snapped_repair(p, t)
    assert (untouched.welded, untouched.left_out) == (0, 0) and untouched.keep.all()
    with pytest.raises(uvflat.InvalidMesh):
        uvflat.snapped_repair(p, t + len(p))


# --- results equal the CLI's ------------------------------------------------------------------

CLI_MESHES = ["disk_cat_head.obj", "disk_nefertiti_small.obj", "holes_pig.obj", "bad_unreferenced_vertices.obj"]
CLI_CASES = [
    ("tutte", (), dict(weights="uniform")),
    ("floater", (), dict(weights="floater")),
    ("authalic", (), dict(weights="authalic")),
    ("conformal", (), dict(weights="conformal")),
    ("mean-value", (), dict()),
    ("mean-value", ("--boundary", "square"), dict(boundary="square")),
    ("mean-value", ("--distribution", "uniform"), dict(distribution="uniform")),
    ("floater", ("--boundary", "square", "--distribution", "centripetal"), dict(weights="floater", boundary="square", distribution="centripetal")),
    ("intrinsic", ("--lambda", "0.5", "--mu", "2"), dict(weights="intrinsic", lambda_=0.5, mu=2.0)),
    ("natural-conformal", (), None),
]


@pytest.mark.parametrize("name", CLI_MESHES)
@pytest.mark.parametrize("method,options,kwargs", CLI_CASES, ids=["-".join((m, *o)) for m, o, _ in CLI_CASES])
def test_uv_equal_the_cli(name, method, options, kwargs, tmp_path):
    p, t = load_mesh(name)
    expected, stdout = cli_unwrap(mesh_path(name), tmp_path, "--method", method, *options)
    if kwargs is None:
        uv = uvflat.natural_conformal_map(p, t)
    else:
        uv = uvflat.fixed_boundary_map(p, t, **kwargs)
    assert uv.dtype == np.float64 and uv.shape == (len(p), 2) and uv.flags.c_contiguous
    assert_uv_equal(uv, expected, referenced_mask(len(p), t))
    # and the metrics the CLI prints are the binding's metrics of the same UVs
    cli_metrics = json.loads(stdout)
    ours = uvflat.metrics(p, t, uv)
    for field, value in vars(ours).items():
        assert value == pytest.approx(cli_metrics[field], rel=1e-12, abs=1e-12), field


@pytest.mark.parametrize(
    "function,kwargs,method",
    [
        (uvflat.tutte, {}, "tutte"),
        (uvflat.floater, {}, "floater"),
        (uvflat.authalic, {}, "authalic"),
        (uvflat.conformal, {}, "conformal"),
        (uvflat.mean_value, {}, "mean-value"),
        (uvflat.intrinsic, dict(lambda_=1.0, mu=1.0), "intrinsic"),
        (uvflat.lscm, {}, "natural-conformal"),
    ],
)
def test_convenience_functions_equal_the_cli(function, kwargs, method, tmp_path):
    name = "disk_nefertiti_small.obj"
    p, t = load_mesh(name)
    extra = ("--lambda", "1", "--mu", "1") if method == "intrinsic" else ()
    expected, _ = cli_unwrap(mesh_path(name), tmp_path, "--method", method, *extra)
    assert_uv_equal(function(p, t, **kwargs), expected, referenced_mask(len(p), t))


def test_given_boundary_equals_the_cli_boundary_file(tmp_path):
    name = "disk_cat_head.obj"
    p, t = load_mesh(name)
    (loop,) = uvflat.boundary_loops(p, t)
    angles = np.linspace(0, 2 * np.pi, len(loop), endpoint=False)
    given = {int(v): (0.5 + 0.4 * float(np.cos(a)), 0.5 + 0.3 * float(np.sin(a))) for v, a in zip(loop, angles)}
    boundary_file = tmp_path / "boundary.txt"
    boundary_file.write_text("".join(f"{v} {u!r} {w!r}\n" for v, (u, w) in given.items()))
    expected, _ = cli_unwrap(mesh_path(name), tmp_path, "--method", "floater", "--boundary", str(boundary_file))
    mask = referenced_mask(len(p), t)
    uv = uvflat.floater(p, t, boundary=given)
    assert_uv_equal(uv, expected, mask)
    pair = (np.array(list(given)), np.array(list(given.values())))
    assert_uv_equal(uvflat.floater(p, t, boundary=pair), expected, mask)
    for v, (u, w) in given.items():
        assert tuple(uv[v]) == (u, w)


def test_pins_equal_the_cli_pins(tmp_path):
    name = "disk_nefertiti_small.obj"
    p, t = load_mesh(name)
    a, b = 3, 200
    expected, _ = cli_unwrap(mesh_path(name), tmp_path, "--method", "natural-conformal", "--pin", str(a), "--pin", str(b))
    d = float(np.linalg.norm(p[a] - p[b]))
    uv = uvflat.natural_conformal_map(p, t, pins=((a, (0.0, 0.0)), (b, (d, 0.0))))
    assert_uv_equal(uv, expected, referenced_mask(len(p), t))
    assert tuple(uv[a]) == (0.0, 0.0) and tuple(uv[b]) == (d, 0.0)


def test_per_corner_uvs_measure_like_per_vertex_uvs():
    p, t = canonical("disk_three_peaks.obj")
    uv = uvflat.natural_conformal_map(p, t)
    per_vertex = uvflat.metrics(p, t, uv)
    corners = uv[t].reshape(-1, 2)
    per_corner = uvflat.metrics(p, t, corners, np.arange(3 * len(t)).reshape(-1, 3))
    for field in ("triangles", "flipped", "degenerate_uv", "stretch_l2", "stretch_linf", "conformal_mean",
                  "conformal_max", "angle_mean", "angle_max", "area_mean", "area_max"):
        assert getattr(per_corner, field) == pytest.approx(getattr(per_vertex, field), rel=1e-12, abs=1e-15), field


def test_a_flat_mesh_is_its_own_parameterization():
    xs, ys = np.meshgrid(np.linspace(0, 1, 6), np.linspace(0, 1, 5))
    p = np.column_stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)])
    idx = np.arange(30).reshape(5, 6)
    t = np.vstack([np.column_stack([idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel()]),
                   np.column_stack([idx[:-1, :-1].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()])])
    m = uvflat.metrics(p, t, p[:, :2])
    assert (m.flipped, m.degenerate_uv, m.boundary_intersections) == (0, 0, 0)
    assert m.angle_max < 1e-12 and m.conformal_max == pytest.approx(1.0, abs=1e-12)
    uv = uvflat.natural_conformal_map(p, t, pins=((0, (0.0, 0.0)), (5, (1.0, 0.0))))
    np.testing.assert_allclose(uv, p[:, :2], atol=1e-12)


# --- errors -----------------------------------------------------------------------------------

BAD_MESHES = [
    ("bad_degenerate_faces.obj", r"triangle 127 uses vertex 20 more than once"),
    ("bad_duplicate_faces.obj", r"triangle 128 uses the same three vertices as triangle 10"),
    ("bad_empty_no_faces.obj", r"the mesh has no triangles"),
    ("bad_inconsistent_orientation.obj", r"triangles 15 and 30 are inconsistently oriented: both traverse edge \(17, 16\)"),
    ("bad_nan_coordinate.obj", r"vertex 12 has a non-finite coordinate \(inf\)"),
    ("bad_nonmanifold_edge.obj", r"edge \(40, 50\) is non-manifold: it is shared by 3 triangles \[72, 73, 128\]"),
    ("bad_nonmanifold_vertex.obj", r"vertex 80 is non-manifold: its triangles form 2 separate fans"),
    ("realbad_moebius.obj", r"triangles 27 and 226 are inconsistently oriented"),
    ("realbad_triple_vierbein.obj", r"edge \(0, 1\) is non-manifold"),
]
ALL_METHODS = [
    uvflat.mesh_info,
    uvflat.boundary_loops,
    uvflat.triangle_components,
    uvflat.fixed_boundary_map,
    uvflat.natural_conformal_map,
]


@pytest.mark.parametrize("name,message", BAD_MESHES)
@pytest.mark.parametrize("function", ALL_METHODS, ids=lambda f: f.__name__)
def test_invalid_meshes_raise_invalid_mesh_naming_the_element(name, message, function):
    p, t = load_mesh(name)
    with pytest.raises(uvflat.InvalidMesh) as caught:
        function(p, t)
    error = caught.value
    assert isinstance(error, uvflat.Error) and isinstance(error, ValueError)
    assert error.status == uvflat.Status.INVALID_MESH == 2
    assert re.fullmatch(message + ".*", error.message), error.message
    assert str(error) == error.message
    if function is uvflat.mesh_info:
        assert error.message == cli_error(mesh_path(name))


def test_out_of_range_indices_name_the_triangle():
    p, t = load_mesh("bad_out_of_range_index.obj")
    # the file's last face has OBJ index 0 (-1 here): the binding refuses it before the library
    with pytest.raises(uvflat.InvalidMesh, match=r"^triangle 129 references vertex -1, which is negative$"):
        uvflat.natural_conformal_map(p, t)
    # the face before it references vertex 86 (1-based) of 81: the library's message
    # (the CLI's OBJ reader rejects both faces itself, so its message is not the library's)
    with pytest.raises(uvflat.InvalidMesh, match=r"^triangle 128 references vertex 85 but the mesh has 81 vertices$"):
        uvflat.mesh_info(p, t[:-1])
    too_big = t[:-1].copy()
    too_big[5, 2] = 2**32 + 3  # would wrap to vertex 3 if cast blindly
    with pytest.raises(uvflat.InvalidMesh, match=r"^triangle 5 references vertex 4294967299, which does not fit in 32 bits$"):
        uvflat.mean_value(p, too_big)


@pytest.mark.parametrize("name", ["closed_g1_bob.obj", "holes_punctured_torus.obj", "closed_g0_decimated_knight.obj"])
@pytest.mark.parametrize("function", [uvflat.fixed_boundary_map, uvflat.natural_conformal_map], ids=lambda f: f.__name__)
def test_meshes_that_are_not_disks_raise_unsupported_topology(name, function):
    p, t = load_mesh(name)
    info = uvflat.mesh_info(p, t)
    with pytest.raises(uvflat.UnsupportedTopology) as caught:
        function(p, t)
    assert caught.value.status == uvflat.Status.UNSUPPORTED_TOPOLOGY
    assert caught.value.message == (
        f"the mesh is not a topological disk: {info.components} component(s), "
        f"{info.boundary_loops} boundary loop(s), genus {info.genus}"
    )


def with_entry(triangles: np.ndarray, row: int, value: int) -> np.ndarray:
    triangles[row, 1] = value
    return triangles


@pytest.mark.parametrize(
    "call,message",
    [
        # rejected by the library
        (lambda p, t: uvflat.fixed_boundary_map(p, t, weights=99), r"invalid argument: unknown weights 99; use one of UVF_WEIGHTS_\*"),
        (lambda p, t: uvflat.fixed_boundary_map(p, t, distribution=7), r"invalid argument: unknown distribution 7; use one of UVF_DISTRIBUTION_\*"),
        (lambda p, t: uvflat.intrinsic(p, t, lambda_=0.0, mu=0.0), r"invalid argument: intrinsic weights need finite λ, μ not both zero \(got λ = 0, μ = 0\)"),
        (lambda p, t: uvflat.mean_value(p, t, boundary={60: (0, 0)}), r"invalid argument: vertex 60 was given a boundary position but is not on a boundary loop"),
        (lambda p, t: uvflat.mean_value(p, t, boundary={1000: (0, 0)}), r"invalid argument: boundary vertex 1000 does not exist \(the mesh has 131 vertices\)"),
        (lambda p, t: uvflat.natural_conformal_map(p, t, pins=((3, (0, 0)), (3, (1, 0)))), r"invalid argument: the two pins must be different vertices \(both are 3\)"),
        (lambda p, t: uvflat.natural_conformal_map(p, t, pins=((3, (0, 0)), (500, (1, 0)))), r"invalid argument: pinned vertex 500 is out of range: the mesh has 131 vertices"),
        (lambda p, t: uvflat.metrics(p, t, np.zeros((3, 2))), r"invalid argument: uv_triangles is NULL \(per-vertex UVs\) but uv_count 3 differs from vertex_count 131"),
        (lambda p, t: uvflat.metrics(p, t, np.zeros((3, 2)), with_entry(np.zeros_like(t), 7, 5)), r"invalid argument: triangle 7 references uv 5 but there are 3 uv coordinates"),
        # rejected by the binding before the call
        (lambda p, t: uvflat.fixed_boundary_map(p, t, weights="bogus"), r"unknown weights 'bogus'; use one of .*mean_value.*"),
        (lambda p, t: uvflat.fixed_boundary_map(p, t, lambda_=2.0), r"lambda_ and mu apply to weights='intrinsic' only.*"),
        (lambda p, t: uvflat.mesh_info(p[:, :2], t), r"positions must have shape \(k, 3\), not \(131, 2\)"),
        (lambda p, t: uvflat.mesh_info(p, t.astype(float)), r"triangles must hold integers, not float64"),
        (lambda p, t: uvflat.natural_conformal_map(p, t, pins=(3, 4)), r"pins must be .*"),
        (lambda p, t: uvflat.natural_conformal_map(p, t, progress=42), r"progress must be callable or None, not int"),
        (lambda p, t: uvflat.metrics(p, t, np.zeros((131, 2)), t[:5]), r"uv_triangles has 5 rows but triangles has 248"),
    ],
)
def test_invalid_arguments_raise_invalid_argument(call, message):
    p, t = load_mesh("disk_cat_head.obj")
    with pytest.raises(uvflat.InvalidArgument) as caught:
        call(p, t)
    assert caught.value.status == uvflat.Status.INVALID_ARGUMENT
    assert re.fullmatch(message, caught.value.message), caught.value.message


def test_an_overflowing_solve_raises_numerical_failure():
    p, t = load_mesh("disk_cat_head.obj")
    with pytest.raises(uvflat.NumericalFailure) as caught:
        uvflat.intrinsic(p, t, lambda_=1e308, mu=1e308)
    assert caught.value.status == uvflat.Status.NUMERICAL_FAILURE
    assert caught.value.message.startswith("numerical failure: ")
    assert isinstance(caught.value, ArithmeticError)


def test_every_status_maps_to_its_exception_class():
    expected = {
        1: uvflat.InvalidArgument,
        2: uvflat.InvalidMesh,
        3: uvflat.UnsupportedTopology,
        4: uvflat.NumericalFailure,
        5: uvflat.Cancelled,
        6: uvflat.NotImplemented,
        7: uvflat.InternalError,
        8: uvflat.IoError,
    }
    assert set(expected) == {s.value for s in uvflat.Status} - {0}
    for status, cls in expected.items():
        error = _errors.error_for_status(status, f"message {status}")
        assert type(error) is cls and isinstance(error, uvflat.Error)
        assert error.status == status == cls.default_status and error.message == f"message {status}"
    unknown = _errors.error_for_status(42, "?")
    assert type(unknown) is uvflat.InternalError and "unknown uvflat status 42" in unknown.message
    assert issubclass(uvflat.NotImplemented, NotImplementedError)
    assert issubclass(uvflat.InternalError, RuntimeError)
    # NOT_IMPLEMENTED and INTERNAL_ERROR have no trigger in this C API yet: check that a status
    # the library returns goes through the same path, with the thread's message
    status = _library.library().uvf_mesh_info(None, 0, None, 0, ctypes.byref(_library.UvfMeshInfo()))
    assert status == uvflat.Status.INVALID_MESH
    with pytest.raises(uvflat.InvalidMesh, match="^the mesh has no triangles$"):
        _common._check(status)


# --- unreferenced vertices --------------------------------------------------------------------

UNREFERENCED = [0, 1, 50, 84, 85]  # bad_unreferenced_vertices.obj: 1-based 1, 2, 51 and the last two


@pytest.mark.parametrize(
    "function",
    [uvflat.tutte, uvflat.floater, uvflat.authalic, uvflat.conformal, uvflat.mean_value, uvflat.intrinsic, uvflat.natural_conformal_map],
    ids=lambda f: f.__name__,
)
def test_unreferenced_vertices_get_nan(function):
    p, t = load_mesh("bad_unreferenced_vertices.obj")
    uv = function(p, t)
    mask = referenced_mask(len(p), t)
    assert sorted(np.flatnonzero(~mask)) == UNREFERENCED
    assert np.isnan(uv[~mask]).all()
    assert np.isfinite(uv[mask]).all()
    assert uvflat.metrics(p, t, uv).flipped == 0  # NaN rows that no triangle uses are fine


# --- progress and cancellation ----------------------------------------------------------------


@pytest.mark.parametrize("function", [uvflat.mean_value, uvflat.natural_conformal_map], ids=lambda f: f.__name__)
def test_progress_is_reported_from_zero_to_one(function):
    p, t = canonical("disk_three_peaks.obj")
    fractions = []
    uv = function(p, t, progress=fractions.append)  # returns None: go on
    assert len(fractions) >= 2 and fractions[-1] == 1.0
    assert all(0.0 <= f <= 1.0 for f in fractions) and fractions == sorted(fractions)
    np.testing.assert_array_equal(uv, function(p, t))
    assert function(p, t, progress=lambda f: True).tolist() == uv.tolist()


@pytest.mark.parametrize("function", [uvflat.floater, uvflat.natural_conformal_map], ids=lambda f: f.__name__)
@pytest.mark.parametrize("stop_at", [0.0, 0.25, 0.9])
def test_returning_false_cancels(function, stop_at):
    p, t = canonical("disk_three_peaks.obj")
    seen = []

    def progress(fraction):
        seen.append(fraction)
        return fraction < stop_at

    with pytest.raises(uvflat.Cancelled) as caught:
        function(p, t, progress=progress)
    assert caught.value.status == uvflat.Status.CANCELLED
    assert caught.value.message == "cancelled by the progress callback"
    assert seen and seen[-1] >= stop_at and all(f < stop_at for f in seen[:-1])
    assert np.isfinite(function(p, t)).all()  # the next call is unaffected


@pytest.mark.parametrize("function", [uvflat.conformal, uvflat.natural_conformal_map], ids=lambda f: f.__name__)
def test_an_exception_in_the_callback_cancels_and_is_reraised(function):
    p, t = canonical("disk_three_peaks.obj")
    calls = []

    class Boom(Exception):
        pass

    def progress(fraction):
        calls.append(fraction)
        if fraction > 0.1:
            raise Boom(f"stop at {fraction}")

    with pytest.raises(Boom, match="stop at"):
        function(p, t, progress=progress)
    assert len([f for f in calls if f > 0.1]) == 1  # not called again after raising
    def interrupt(fraction):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        function(p, t, progress=interrupt)
    assert np.isfinite(function(p, t, progress=lambda f: None)).all()


# --- input conversion -------------------------------------------------------------------------


def test_canonical_inputs_are_passed_without_a_copy():
    p, t = canonical("disk_cat_head.obj")
    assert _common._as_points(p, 3, "positions") is p
    assert _common._as_indices(t, "triangles", uvflat.InvalidMesh) is t
    uv = uvflat.natural_conformal_map(p, t)
    assert _common._as_points(uv, 2, "uv") is uv


def test_converted_inputs_give_the_same_results():
    p, t = canonical("disk_nefertiti_small.obj")
    expected = uvflat.natural_conformal_map(p, t)
    wide = np.zeros((len(p), 7))
    wide[:, 1:4] = p
    strided = wide[:, 1:4]  # not contiguous
    fortran = np.asfortranarray(p)
    assert not strided.flags.c_contiguous and not fortran.flags.c_contiguous
    variants = [
        (strided, t),
        (fortran, t),
        (p, t.astype(np.int64)),
        (p, t.astype(np.int32)),
        (p, t.astype(np.uint64)),
        (p, np.asfortranarray(t.astype(np.int16))),
        (p.tolist(), t.tolist()),
        (p, t[::-1][::-1]),
    ]
    for positions, triangles in variants:
        np.testing.assert_array_equal(uvflat.natural_conformal_map(positions, triangles), expected)
    # float32 positions are widened exactly: same result as float64 positions of the same values
    p32 = p.astype(np.float32)
    np.testing.assert_array_equal(
        uvflat.natural_conformal_map(p32, t.astype(np.int64)), uvflat.natural_conformal_map(p32.astype(np.float64), t)
    )
    # a strided uv array in metrics
    uv_wide = np.zeros((len(p), 4))
    uv_wide[:, ::2] = expected
    assert uvflat.metrics(p, t, uv_wide[:, ::2]) == uvflat.metrics(p, t, expected)


def test_inputs_are_not_modified_and_may_be_read_only():
    p, t = canonical("disk_cat_head.obj")
    p.setflags(write=False)
    t.setflags(write=False)
    p_before, t_before = p.copy(), t.copy()
    uv = uvflat.mean_value(p, t, boundary="square")
    uvflat.metrics(p, t, uv)
    np.testing.assert_array_equal(p, p_before)
    np.testing.assert_array_equal(t, t_before)


# --- threads and the GIL ----------------------------------------------------------------------


def test_four_threads_get_the_single_threaded_results_and_their_own_errors():
    jobs = [
        ("disk_three_peaks.obj", uvflat.natural_conformal_map),
        ("disk_mushroom.obj", uvflat.mean_value),
        ("disk_cow_cut.obj", uvflat.natural_conformal_map),
        ("holes_head.obj", uvflat.floater),
    ]
    bad = [name for name, _ in BAD_MESHES[:4]]
    meshes = {name: canonical(name) for name, _ in jobs}
    expected = {name: function(*meshes[name]) for name, function in jobs}
    expected_errors = {}
    for name in bad:
        with pytest.raises(uvflat.InvalidMesh) as caught:
            uvflat.mesh_info(*load_mesh(name))
        expected_errors[name] = caught.value.message
    results, failures = {}, []
    barrier = threading.Barrier(4)

    def work(k: int) -> None:
        try:
            name, function = jobs[k]
            barrier.wait()
            for round_ in range(3):
                uv = function(*meshes[name])
                np.testing.assert_array_equal(uv, expected[name])
                with pytest.raises(uvflat.InvalidMesh) as caught:
                    uvflat.natural_conformal_map(*load_mesh(bad[k]))
                assert caught.value.message == expected_errors[bad[k]]
            results[k] = uv
        except BaseException as e:  # noqa: B902 - reported in the main thread
            failures.append((k, e))

    threads = [threading.Thread(target=work, args=(k,)) for k in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert not failures, failures
    assert sorted(results) == [0, 1, 2, 3]


def test_the_gil_is_released_during_a_call():
    """ctypes releases the GIL around a CDLL call: another Python thread keeps running while
    uvflat computes. If the GIL were held, no tick could land inside the call."""
    p, t = canonical("disk_camelhead.obj")
    window = {}

    def unwrap() -> None:
        window["start"] = time.perf_counter()
        uvflat.natural_conformal_map(p, t)
        window["end"] = time.perf_counter()

    ticks = []
    worker = threading.Thread(target=unwrap)
    worker.start()
    while worker.is_alive():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    worker.join()
    start, end = window["start"], window["end"]
    inside = [x for x in ticks if start < x < end]
    assert len(inside) >= 5, (end - start, len(inside))
    gaps = np.diff([start, *inside, end])
    assert gaps.max() < 0.5 * (end - start), (end - start, gaps.max())


# --- more pins, non-linear methods, ABF, closed surfaces ---------------------------------------


def signed_uv_areas(uv: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    a, b, c = uv[triangles[:, 0]], uv[triangles[:, 1]], uv[triangles[:, 2]]
    return (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])


def test_pinned_natural_conformal_map_places_every_pin_and_matches_the_two_pin_map():
    p, t = load_mesh("disk_nefertiti_small.obj")
    loops = uvflat.boundary_loops(p, t)
    a, b, c = (int(loops[0][k]) for k in (0, len(loops[0]) // 3, 2 * len(loops[0]) // 3))
    two = uvflat.natural_conformal_map(p, t, pins=((a, (0.0, 0.0)), (b, (1.0, 0.0))))
    same = uvflat.pinned_natural_conformal_map(p, t, {a: (0.0, 0.0), b: (1.0, 0.0)})
    assert np.nanmax(np.abs(same - two)) < 1e-9
    three = uvflat.pinned_natural_conformal_map(p, t, {a: (0.0, 0.0), b: (1.0, 0.0), c: (0.3, 0.9)})
    for v, uv in ((a, (0.0, 0.0)), (b, (1.0, 0.0)), (c, (0.3, 0.9))):
        assert np.allclose(three[v], uv, atol=1e-9)
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.pinned_natural_conformal_map(p, t, {a: (0.0, 0.0)})


@pytest.mark.parametrize("method", ["slim", "arap", "mips"])
def test_nonlinear_map_never_flips_and_lowers_its_energy(method):
    p, t = load_mesh("disk_cat_head.obj")
    uv, report = uvflat.nonlinear_map(p, t, method, iterations=10)
    assert (signed_uv_areas(uv, t.astype(np.int64)) > 0).all()
    assert report.iterations > 0 and report.final_energy < report.initial_energy
    with pytest.raises(uvflat.InvalidArgument, match="unknown method 'bogus'"):
        uvflat.nonlinear_map(p, t, "bogus")


def test_abf_plus_plus_converges_without_flips_and_cancels():
    p, t = load_mesh("disk_nefertiti_small.obj")
    uv, report = uvflat.abf(p, t)
    assert report.converged and report.gradient_norm <= 1e-6
    assert uvflat.metrics(p, t, uv).flipped == 0
    with pytest.raises(uvflat.Cancelled):
        uvflat.abf(p, t, progress=lambda fraction: False)


def test_abf_objective_options_reach_the_library():
    p, t = load_mesh("disk_nefertiti_small.obj")
    default_uv, _ = uvflat.abf(p, t)
    papers_uv, report = uvflat.abf(p, t, weights="inverse_square", barrier=0.0)
    assert report.converged and uvflat.metrics(p, t, papers_uv).flipped == 0
    # Another objective gives other angles.
    assert np.abs(papers_uv - default_uv).max() > 1e-6
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.abf(p, t, weights="squared")
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.abf(p, t, barrier=-1.0)


def test_abf_with_given_pins_places_them_and_keeps_the_angles():
    p, t = load_mesh("disk_nefertiti_small.obj")
    loops = uvflat.boundary_loops(p, t)
    a, b = int(loops[0][0]), int(loops[0][len(loops[0]) // 2])
    free, _ = uvflat.abf(p, t)
    pinned, report = uvflat.abf(p, t, pins=((a, (0.25, -1.0)), (b, (2.0, 3.0))))
    assert report.converged
    assert np.allclose(pinned[a], (0.25, -1.0), atol=1e-9) and np.allclose(pinned[b], (2.0, 3.0), atol=1e-9)
    # Other pins only move, turn and scale the reconstruction: the angles stay the same.
    m_free, m_pinned = uvflat.metrics(p, t, free), uvflat.metrics(p, t, pinned)
    assert m_pinned.flipped == 0
    assert abs(m_pinned.angle_mean - m_free.angle_mean) < 1e-6
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.abf(p, t, pins=((a, (0.0, 0.0)),))


def test_cut_to_disk_makes_a_torus_a_disk_that_maps_back_to_its_vertices():
    p, t = load_mesh("closed_g1_bob.obj")
    cut = uvflat.cut_to_disk(p, t)
    info = uvflat.mesh_info(cut.positions, cut.triangles)
    assert (info.boundary_loops, info.euler_characteristic) == (1, 1)
    assert (cut.original_vertices[cut.triangles] == t).all()
    assert 0 < cut.seam_length < cut.total_edge_length
    uv = uvflat.mean_value(cut.positions, cut.triangles)
    assert uvflat.metrics(cut.positions, cut.triangles, uv).flipped == 0


def test_spherical_map_of_a_closed_genus_zero_mesh_is_on_the_unit_sphere_without_flips():
    p, t = load_mesh("closed_g0_decimated_knight.obj")
    sphere, flipped = uvflat.spherical_map(p, t)
    assert flipped == 0
    assert np.allclose(np.linalg.norm(sphere, axis=1), 1.0, atol=1e-12)
    # The circle-pattern map is conformal: the angles of the chordal triangles stay closer to
    # the mesh's own than the Tutte embedding's do.
    conformal, _ = uvflat.spherical_map(p, t, method="circle_patterns")
    assert np.allclose(np.linalg.norm(conformal, axis=1), 1.0, atol=1e-12)

    def angles(x):
        a, b, c = x[t[:, 0]], x[t[:, 1]], x[t[:, 2]]
        u, w = b - a, c - a
        return np.arccos(np.clip((u * w).sum(1) / np.linalg.norm(u, axis=1) / np.linalg.norm(w, axis=1), -1, 1))

    assert np.abs(angles(conformal) - angles(p)).mean() < np.abs(angles(sphere) - angles(p)).mean()
    with pytest.raises(uvflat.InvalidArgument, match="method"):
        uvflat.spherical_map(p, t, method="mercator")
    fractions = []
    uvflat.spherical_map(p, t, method="circle_patterns", progress=lambda f: fractions.append(f) or True)
    assert fractions[0] == 0.0 and fractions[-1] == 1.0 and fractions == sorted(fractions)
    with pytest.raises(uvflat.Cancelled):
        uvflat.spherical_map(p, t, method="circle_patterns", progress=lambda f: f < 0.5)
    with pytest.raises(uvflat.UnsupportedTopology):
        uvflat.spherical_map(*load_mesh("closed_g1_bob.obj"))


def test_cut_to_disk_with_given_costs_avoids_expensive_edges():
    p, t = load_mesh("closed_g1_bob.obj")
    t64 = t.astype(np.int64)
    # Half-edges whose two ends both lie above the median height cost a thousand times more:
    # the cut must then run (where topology allows) through the cheap lower part.
    z = p[:, 2]
    high = (z[t64] > np.median(z)) & (z[np.roll(t64, -1, axis=1)] > np.median(z))
    length = np.linalg.norm(p[np.roll(t64, -1, axis=1)] - p[t64], axis=2)
    cost = length * np.where(high, 1e3, 1.0)
    cut = uvflat.cut_to_disk(p, t, cost=cost)
    info = uvflat.mesh_info(cut.positions, cut.triangles)
    assert (info.boundary_loops, info.euler_characteristic) == (1, 1)
    plain = uvflat.cut_to_disk(p, t, cost="length")
    high_edges = lambda c: int((z[c.edges] > np.median(z)).all(axis=1).sum())  # noqa: E731
    assert high_edges(cut) < high_edges(plain)
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.cut_to_disk(p, t, cost=cost[:-1])
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.cut_to_disk(p, t, cost=np.full(t.shape, -1.0))


# --- periodic global parameterization ----------------------------------------------------------


def test_curvature_of_a_torus_is_one_over_r_around_the_tube():
    # closed_g1_torus: tube radius from the mesh itself (distance to the centre circle; the
    # axis of revolution is the coordinate axis of smallest extent, 2r against 2(R + r)).
    p, t = load_mesh("closed_g1_torus.obj")
    c = uvflat.curvature(p, t)
    assert c.kmin_direction.shape == c.kmax_direction.shape == (len(p), 3)
    assert (c.kmin <= c.kmax).all()
    assert np.allclose(np.einsum("ij,ij->i", c.kmin_direction, c.kmax_direction), 0.0, atol=1e-12)
    q = p - p.mean(axis=0)
    axis = int(np.argmin(q.max(axis=0) - q.min(axis=0)))
    a, b = [i for i in range(3) if i != axis]
    ring = np.hypot(q[:, a], q[:, b])
    big_r = 0.5 * (ring.max() + ring.min())
    r = np.hypot(ring - big_r, q[:, axis]).mean()
    assert abs(np.median(c.kmax) - 1.0 / r) < 0.05 / r
    wider = uvflat.curvature(p, t, radius=0.2 * r)
    assert wider.kmax.shape == (len(p),)
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.curvature(p, t, rings=0)


def test_pgp_equals_the_cli_and_its_indices_sum_to_the_euler_characteristic(tmp_path):
    name = "closed_g3_triple_torus.obj"
    p, t = load_mesh(name)
    result = uvflat.pgp(p, t)
    assert result.corner_coords.shape == (len(t), 3, 2)
    assert abs(result.indices.sum() - (2 - 2 * 3)) < 1e-9
    # Newton at ε = 0.1 runs to ‖∇F**‖ < 10⁻⁶ by default (its limit of 100 iterations is a
    # safeguard) and stops at a smaller limit, reporting that it did not get there.
    assert result.converged and result.final_gradient < 1e-6 and 3 < result.newton_iterations < 100
    shorter = uvflat.pgp(p, t, max_newton_iterations=3)
    assert shorter.newton_iterations == 3 and not shorter.converged and shorter.final_gradient >= 1e-6
    for bad in (2.5, -1, True):
        with pytest.raises(uvflat.InvalidArgument):
            uvflat.pgp(p, t, max_newton_iterations=bad)
    assert (result.singular_triangles < len(t)).all() and result.singular_edges.shape[1] == 2
    out = tmp_path / "pgp.obj"
    cli = json.loads(run_cli("pgp", str(mesh_path(name)), "-o", str(out), "--json").stdout)
    _, _, vt = parse_obj(out.read_text())
    np.testing.assert_allclose(vt, result.uv.reshape(-1, 2), rtol=0, atol=1e-12)
    assert cli["singular_triangles"] == len(result.singular_triangles)
    assert cli["index_sum"] == pytest.approx(result.indices.sum(), abs=1e-9)
    assert cli["converged"] and cli["newton_iterations"] == result.newton_iterations
    shorter_cli = run_cli("pgp", str(mesh_path(name)), "-o", str(out), "--json", "--newton-iterations", "3")
    shorter_json = json.loads(shorter_cli.stdout)
    assert not shorter_json["converged"] and shorter_json["newton_iterations"] == shorter.newton_iterations


def test_pgp_untangling_repairs_negative_triangles_and_can_be_turned_off(tmp_path):
    # The untangling (on by default, not in Ray et al. 2006) moves vertex phases only: the
    # singular edges (transitions) stay, fewer (θ, φ) triangles are negative or singular. Without
    # the phase relaxation, to measure the untangling alone.
    name = "closed_g0_cow.obj"
    p, t = load_mesh(name)
    raw = uvflat.pgp(p, t, untangle=False, relax=False)
    fixed = uvflat.pgp(p, t, relax=False)

    def negative(r):
        c = r.corner_coords
        e1, e2 = c[:, 1] - c[:, 0], c[:, 2] - c[:, 0]
        return int(((e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]) <= 0).sum())

    assert negative(fixed) < 0.75 * negative(raw)
    assert len(fixed.singular_triangles) < len(raw.singular_triangles)
    np.testing.assert_array_equal(raw.singular_edges, fixed.singular_edges)
    out = tmp_path / "pgp.obj"
    args = ("pgp", str(mesh_path(name)), "-o", str(out), "--json", "--no-relax")
    plain = json.loads(run_cli(*args, "--no-untangle").stdout)
    assert plain["singular_triangles"] == len(raw.singular_triangles)
    assert plain["untangled"]["moved_vertices"] == 0
    default = json.loads(run_cli(*args).stdout)
    assert default["singular_triangles"] == len(fixed.singular_triangles)
    u = default["untangled"]
    assert u["negative_after"] < u["negative_before"] and u["moved_vertices"] > 0


def test_pgp_phase_relaxation_keeps_every_transition_and_can_be_turned_off(tmp_path):
    # The phase relaxation (on by default, not in Ray et al. 2006) turns vertex phases by a
    # least-squares fit with Algorithm 1's integers kept: the singular edges stay; on eight
    # (genus 2) the singular triangles went 13 -> 8. The CLI reports both counts.
    name = "closed_g2_eight.obj"
    p, t = load_mesh(name)
    plain = uvflat.pgp(p, t, relax=False)
    relaxed = uvflat.pgp(p, t)
    np.testing.assert_array_equal(plain.singular_edges, relaxed.singular_edges)
    assert len(relaxed.singular_triangles) < len(plain.singular_triangles)
    assert relaxed.indices.sum() == pytest.approx(-2)
    out = tmp_path / "pgp.obj"
    off = json.loads(run_cli("pgp", str(mesh_path(name)), "-o", str(out), "--json", "--no-relax").stdout)
    assert off["relaxed"]["kept"] is False and off["singular_triangles"] == len(plain.singular_triangles)
    on = json.loads(run_cli("pgp", str(mesh_path(name)), "-o", str(out), "--json").stdout)
    assert on["relaxed"] == {
        "kept": True,
        "singular_without": len(plain.singular_triangles),
        "singular_with": len(relaxed.singular_triangles),
    }
    assert on["singular_triangles"] == len(relaxed.singular_triangles)


def test_pgp_feature_adaptive_density_and_the_papers_single_omega_agree_with_the_cli(tmp_path):
    # feature_periods (default 3, not in Ray et al. 2006) raises the frequency on features whose
    # curvature radius holds fewer than 3 periods: on cow (legs, horns) the singular triangles
    # fell from 10.4% to 2.5% (README; now 5.5% and 1.2% with the singularity-pair cancellation);
    # feature_periods=0 is the paper's single omega. Both without the dislocation annihilation,
    # which also lowers the single omega's rate (cow 5.5 -> 1.6%), to measure the density alone.
    name = "closed_g0_cow.obj"
    p, t = load_mesh(name)
    single = uvflat.pgp(p, t, feature_periods=0, dislocation_periods=0)
    adaptive = uvflat.pgp(p, t, dislocation_periods=0)
    assert len(adaptive.singular_triangles) <= 0.03 * len(t) < len(single.singular_triangles)
    out = tmp_path / "pgp.obj"
    off = ["--dislocation-periods", "0"]
    for args, result in [(["--feature-periods", "0", *off], single), (off, adaptive)]:
        cli = json.loads(run_cli("pgp", str(mesh_path(name)), "-o", str(out), "--json", *args).stdout)
        assert cli["singular_triangles"] == len(result.singular_triangles)
        assert cli["feature_periods"] == (0 if "--feature-periods" in args else 3)
    with pytest.raises(uvflat.InvalidArgument, match="feature_periods"):
        uvflat.pgp(p, t, feature_periods=-1)
    bad = run_cli("pgp", str(mesh_path(name)), "-o", str(out), "--feature-periods", "nan", check=False)
    assert bad.returncode != 0 and "--feature-periods" in bad.stderr


def test_pgp_pair_cancellation_and_the_kept_field_singularities_agree_with_the_cli(tmp_path):
    # pair_periods (default 0.5, not in Ray et al. 2006) cancels the +1/4 and -1/4 singularities
    # of the smoothed field closer than half a period: on bob (500 triangles) the singular
    # triangles fall from 4.0% to 1.8% (README); pair_periods=0 keeps the smoothed field's.
    name = "closed_g1_bob.obj"
    p, t = load_mesh(name)
    kept = uvflat.pgp(p, t, pair_periods=0)
    cancelled = uvflat.pgp(p, t)
    assert len(cancelled.singular_triangles) <= 0.03 * len(t) < len(kept.singular_triangles)
    out = tmp_path / "pgp.obj"
    for args, result in [(["--pair-periods", "0"], kept), ([], cancelled)]:
        cli = json.loads(run_cli("pgp", str(mesh_path(name)), "-o", str(out), "--json", *args).stdout)
        assert cli["singular_triangles"] == len(result.singular_triangles)
        assert cli["pair_periods"] == (0 if args else 0.5)
        pairs = cli["pairs"]
        if args:
            assert pairs["cancelled"] == 0 and pairs["trials"] == 0
        else:
            assert pairs["cancelled"] > 0 and pairs["field_singular_after"] < pairs["field_singular_before"]
    with pytest.raises(uvflat.InvalidArgument, match="pair_periods"):
        uvflat.pgp(p, t, pair_periods=float("nan"))
    bad = run_cli("pgp", str(mesh_path(name)), "-o", str(out), "--pair-periods=-1", check=False)
    assert bad.returncode != 0 and "--pair-periods" in bad.stderr


def test_pgp_dislocation_annihilation_and_the_kept_phases_agree_with_the_cli(tmp_path):
    # dislocation_periods (default 1.5, not in Ray et al. 2006) annihilates pairs of open triangles
    # of opposite winding where the field is regular; each kept pair removes at least two
    # singular triangles, so the coarse knight has fewer with it than without (README).
    name = "closed_g0_decimated_knight.obj"
    p, t = load_mesh(name)
    kept = uvflat.pgp(p, t, dislocation_periods=0)
    annihilated = uvflat.pgp(p, t)
    assert len(annihilated.singular_triangles) + 2 <= len(kept.singular_triangles)
    out = tmp_path / "pgp.obj"
    for args, result in [(["--dislocation-periods", "0"], kept), ([], annihilated)]:
        cli = json.loads(run_cli("pgp", str(mesh_path(name)), "-o", str(out), "--json", *args).stdout)
        assert cli["singular_triangles"] == len(result.singular_triangles)
        assert cli["dislocation_periods"] == (0 if args else 1.5)
        report = cli["dislocations"]
        if args:
            assert report["annihilated_pairs"] == report["absorbed"] == report["trials"] == 0
        else:
            removed = 2 * report["annihilated_pairs"] + report["absorbed"]
            assert removed > 0 and report["before"] >= removed
    with pytest.raises(uvflat.InvalidArgument, match="dislocation_periods"):
        uvflat.pgp(p, t, dislocation_periods=float("inf"))
    bad = run_cli("pgp", str(mesh_path(name)), "-o", str(out), "--dislocation-periods=-1", check=False)
    assert bad.returncode != 0 and "--dislocation-periods" in bad.stderr


def test_pgp_rejects_a_bad_field_naming_the_vertex_and_cancels():
    p, t = load_mesh("closed_g1_bob.obj")
    field = uvflat.curvature(p, t).kmax_direction.copy()
    field[11] = np.nan
    with pytest.raises(uvflat.InvalidArgument, match="vertex 11"):
        uvflat.pgp(p, t, field=field)
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.pgp(p, t, smooth="quarter")
    with pytest.raises(uvflat.Cancelled):
        uvflat.pgp(p, t, progress=lambda fraction: fraction < 0.3)


def test_pgp_quad_mesh_is_a_manifold_quad_dominant_mesh_and_the_chart_layout_has_polylines(tmp_path):
    p, t = load_mesh("closed_g1_torus.obj")
    r = uvflat.pgp(p, t, quad_mesh=4, chart_layout=True)
    positions, faces = r.quad_mesh
    assert len(faces) > 100 and sum(len(f) == 4 for f in faces) >= 0.9 * len(faces)
    assert all(f.max() < len(positions) for f in faces)
    directed = {(int(f[i]), int(f[(i + 1) % len(f)])) for f in faces for i in range(len(f))}
    assert len(directed) == sum(len(f) for f in faces)  # no edge twice in one direction
    assert all((b, a) in directed for a, b in directed)  # closed
    polylines, corners = r.chart_layout
    assert len(polylines) > 0 and all(len(line) >= 2 and line.shape[1] == 3 for line in polylines)
    assert len(corners) > 0 and (corners == 4).all()
    with pytest.raises(uvflat.InvalidArgument, match="density"):
        uvflat.pgp(p, t, quad_mesh=2.5)
    out = tmp_path / "quad.obj"
    cli = run_cli("pgp", str(mesh_path("closed_g1_torus.obj")), "-o", "/dev/null", "--quad-mesh", str(out))
    assert "quad-dominant remesh" in cli.stdout
    face_lines = [line for line in out.read_text().splitlines() if line.startswith("f ")]
    assert len(face_lines) > 10 and all(len(line.split()) in (4, 5) for line in face_lines)


def test_pgp_charts_cut_the_surface_into_charts_that_do_not_fold(tmp_path):
    p, t = load_mesh("closed_g0_bunny.obj")
    r = uvflat.pgp(p, t, charts=1)
    c = r.charts
    assert (c.positions[: len(p)] == p).all() and c.triangles.max() < len(c.positions)
    assert c.uv.shape == (len(c.triangles), 3, 2) and c.chart.max() == len(c.kinds) - 1
    assert (c.origin < len(t)).all()
    kinds = set(c.kinds.tolist())
    assert uvflat.UVF_PGP_CHART_SPLIT_QUAD in kinds and uvflat.UVF_PGP_CHART_UNRESOLVED not in kinds
    # The cut triangulation covers the surface exactly, and no chart folds.
    def area3(pos, tri):
        a, b, d = pos[tri[:, 0]], pos[tri[:, 1]], pos[tri[:, 2]]
        return 0.5 * np.linalg.norm(np.cross(b - a, d - a), axis=1)

    cut_area = area3(c.positions, c.triangles)
    assert abs(cut_area.sum() / area3(p, t).sum() - 1) < 1e-9
    e1, e2 = c.uv[:, 1] - c.uv[:, 0], c.uv[:, 2] - c.uv[:, 0]
    signed = 0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    assert (signed[cut_area > 1e-12 * cut_area.sum()] > 0).all()
    assert (c.uv >= -1e-6).all() and (c.uv <= c.sizes[c.chart][:, None, :] + 1e-6).all()
    with pytest.raises(uvflat.InvalidArgument, match="density"):
        uvflat.pgp(p, t, charts=0.5)
    out = tmp_path / "charts.obj"
    cli = run_cli("pgp", str(mesh_path("closed_g0_bunny.obj")), "-o", "/dev/null", "--charts", str(out))
    assert "charts (assembled" in cli.stdout
    lines = out.read_text().splitlines()
    assert sum(line.startswith("g chart") for line in lines) == len(c.kinds)
    assert sum(line.startswith("f ") for line in lines) == len(c.triangles)


def test_atlas_of_a_genus_one_mesh_is_flip_free_inside_the_unit_square():
    p, t = load_mesh("closed_g1_bob.obj")
    a = uvflat.atlas(p, t, max_stretch=1.05, margin=0.01)
    assert a.chart_count >= 1 and a.charts.max() == a.chart_count - 1
    assert (a.original_vertices[a.triangles] == t).all()
    assert ((a.uv >= 0) & (a.uv <= 1)).all()
    assert a.max_chart_stretch <= 1.05 and 0 < a.utilization < 1
    m = uvflat.metrics(p[a.original_vertices], a.triangles, a.uv)
    assert m.flipped == 0 and m.boundary_intersections == 0
    assert abs(m.stretch_l2 - a.stretch_l2) < 1e-9
    assert a.corner_uv.shape == (len(t), 3, 2)
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.atlas(p, t, max_stretch=0.5)
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.atlas(p, t, method="tutte")
    with pytest.raises(uvflat.Cancelled):
        uvflat.atlas(p, t, progress=lambda fraction: False)
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.atlas(p, t, polish_iterations=-1)
    plain = uvflat.atlas(p, t, max_stretch=1.05, margin=0.01, polish_iterations=0)
    assert plain.max_chart_stretch <= 1.05 and plain.stretch_l2 >= a.stretch_l2


def boundary_crossings(uv, uv_triangles):
    """Pairs of UV boundary edges (used by one triangle) that cross or touch, sharing no
    endpoint: an all-pairs segment test written out here, independent of the library."""
    e = np.concatenate([uv_triangles[:, [0, 1]], uv_triangles[:, [1, 2]], uv_triangles[:, [2, 0]]])
    key, count = np.unique(np.sort(e, axis=1), axis=0, return_counts=True)
    b = key[count == 1]
    a0, a1 = uv[b[:, 0]], uv[b[:, 1]]

    def orient(p, q, r):
        return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])

    P, Q = a0[:, None], a1[:, None]
    R, S = a0[None, :], a1[None, :]
    crossing = (orient(P, Q, R) * orient(P, Q, S) <= 0) & (orient(R, S, P) * orient(R, S, Q) <= 0)
    shares = (b[:, None, 0] == b[None, :, 0]) | (b[:, None, 0] == b[None, :, 1])
    shares |= (b[:, None, 1] == b[None, :, 0]) | (b[:, None, 1] == b[None, :, 1])
    return int(np.triu(crossing & ~shares, 1).sum())


def test_unwrap_is_flip_and_overlap_free_where_the_conformal_map_folds():
    p, t = load_mesh("disk_three_peaks.obj")
    folded = uvflat.metrics(p, t, uvflat.natural_conformal_map(p, t))
    assert folded.flipped > 0  # the reason for the default's repair
    r = uvflat.unwrap(p, t)
    assert r.report.flipped == 0 and r.report.overlaps == 0 and r.report.repaired_islands >= 1
    assert (r.original_vertices[r.triangles] == t).all()
    assert ((r.uv >= 0) & (r.uv <= 1)).all()
    q = r.corner_uv
    signed = (q[:, 1, 0] - q[:, 0, 0]) * (q[:, 2, 1] - q[:, 0, 1]) - (q[:, 1, 1] - q[:, 0, 1]) * (q[:, 2, 0] - q[:, 0, 0])
    assert (signed > 0).all()
    assert boundary_crossings(r.uv, r.triangles) == 0
    m = uvflat.metrics(p[r.original_vertices], r.triangles, r.uv)
    assert m.stretch_l2 <= 1.5 + 1e-9 and abs(m.stretch_l2 - r.report.stretch_l2) < 1e-9
    check = uvflat.check_layout(r.uv, r.triangles)
    assert (check.flipped, check.overlaps, check.islands) == (0, 0, r.report.islands)
    # The checker is not the method's bookkeeping: it finds the conformal map's folds.
    conformal = uvflat.natural_conformal_map(p, t)
    assert uvflat.check_layout(conformal, t).flipped > 0
    assert abs(np.degrees(m.angle_mean) - r.report.angle_error_mean_deg) < 1e-9


def test_unwrap_cuts_a_torus_and_keeps_it_whole_without_a_bound():
    p, t = load_mesh("closed_g1_bob.obj")
    r = uvflat.unwrap(p, t, max_stretch=math.inf)
    assert r.report.islands == 1 and (r.islands == 0).all()
    assert r.report.seam_edges == len(r.seams) > 0 and (r.seams[:, 0] < r.seams[:, 1]).all()
    bounded = uvflat.unwrap(p, t)
    assert bounded.report.max_island_stretch <= 1.5
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.unwrap(p, t, max_stretch=0.5)
    with pytest.raises(uvflat.Cancelled):
        uvflat.unwrap(p, t, progress=lambda fraction: False)


def test_bijective_slim_keeps_the_boundary_apart():
    p, t = load_mesh("disk_cow_cut.obj")
    free, _ = uvflat.nonlinear_map(p, t, "slim")
    bijective, report = uvflat.nonlinear_map(p, t, "slim", bijective=True)
    assert boundary_crossings(free, t) > 0  # plain SLIM runs its boundary into itself here
    assert boundary_crossings(bijective, t) == 0
    assert uvflat.metrics(p, t, bijective).flipped == 0
    assert report.final_energy <= report.initial_energy


@pytest.mark.parametrize("method", ["mips", "stretch", "degener"])
def test_the_other_methods_keep_the_boundary_apart_when_bijective(method):
    # Plain, these three run the cut cow's boundary into itself (8, 28 and 13 crossing pairs
    # measured); bijective, the scaffold stops each step first.
    p, t = load_mesh("disk_cow_cut.obj")
    free, _ = uvflat.nonlinear_map(p, t, method)
    bijective, report = uvflat.nonlinear_map(p, t, method, bijective=True)
    assert boundary_crossings(free, t) > 0
    assert boundary_crossings(bijective, t) == 0
    assert uvflat.check_layout(bijective, t).overlaps == 0 and uvflat.metrics(p, t, bijective).flipped == 0
    assert report.final_energy <= report.initial_energy


# --- near-optimal λ, boundary optimization, spectral conformal ------------------------------


def edge_energy(p, t, uv):
    """Σ_edges (|u_i − u_j|² / |x_i − x_j|² − 1)² (Desbrun et al. 2002 §5.1), written out here."""
    e = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    e = np.unique(np.sort(e, axis=1), axis=0)
    l3 = ((p[e[:, 0]] - p[e[:, 1]]) ** 2).sum(axis=1)
    l2 = ((uv[e[:, 0]] - uv[e[:, 1]]) ** 2).sum(axis=1)
    return float(((l2 / l3 - 1.0) ** 2).sum())


def test_intrinsic_optimal_map_minimizes_the_edge_energy_on_its_line():
    p, t = load_mesh("disk_nefertiti_small.obj")
    uv, report = uvflat.intrinsic_optimal_map(p, t, energy="edge")
    assert abs(edge_energy(p, t, uv) - report.energy) <= 1e-9 * max(report.energy, 1.0)
    assert report.energy <= min(report.energy_conformal, report.energy_authalic) * (1 + 1e-12)
    # The line λ·DCP + (1 − λ)·DAP at the reported boundary scale, scanned densely.
    dcp = uvflat.conformal(p, t) * report.boundary_scale
    dap = uvflat.authalic(p, t) * report.boundary_scale
    scan = min(edge_energy(p, t, l * dcp + (1 - l) * dap) for l in np.linspace(-1, 2, 601))
    assert report.energy <= scan * (1 + 1e-12)
    assert np.allclose(uv, report.lambda_ * dcp + (1 - report.lambda_) * dap, atol=1e-9)
    _, bounded = uvflat.intrinsic_optimal_map(p, t, energy="area", lambda_min=0.0, lambda_max=1.0)
    assert 0.0 <= bounded.lambda_ <= 1.0
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.intrinsic_optimal_map(p, t, lambda_min=1.0, lambda_max=0.0)
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.intrinsic_optimal_map(p, t, energy="volume")


def test_boundary_optimized_map_lowers_the_energy_without_flips_and_cancels():
    p, t = load_mesh("disk_nefertiti_small.obj")
    uv, history, report = uvflat.boundary_optimized_map(p, t, energy="edge", iterations=20)
    assert len(history) == report.history_length == report.iterations + 1
    assert (np.diff(history) <= 0).all() and history[-1] < history[0]
    assert abs(edge_energy(p, t, uv) - history[-1]) <= 1e-9 * max(history[-1], 1.0)
    m = uvflat.metrics(p, t, uv)
    assert report.flipped == 0 and m.flipped == 0 and m.degenerate_uv == 0
    with pytest.raises(uvflat.Cancelled):
        uvflat.boundary_optimized_map(p, t, progress=lambda fraction: False)


def test_spectral_conformal_map_needs_no_pins_and_ignores_rigid_motion():
    p, t = load_mesh("disk_nefertiti_small.obj")
    uv, report = uvflat.spectral_conformal_map(p, t)
    assert report.converged and report.residual <= 1e-10 and report.eigenvalue > 0
    assert uvflat.metrics(p, t, uv).flipped == 0
    c, s = np.cos(0.7), np.sin(0.7)
    rotation = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    moved, _ = uvflat.spectral_conformal_map(p @ rotation.T * 3.0 + [1.0, -2.0, 5.0], t)
    # Same placement convention (area scale, farthest boundary pair on +u): the same map up to
    # the scale of the input.
    assert np.allclose(moved, 3.0 * uv, atol=1e-6 * np.abs(uv).max() * 3.0)
    with pytest.raises(uvflat.UnsupportedTopology):
        uvflat.spectral_conformal_map(*load_mesh("closed_g0_decimated_knight.obj"))
    with pytest.raises(uvflat.Cancelled):
        uvflat.spectral_conformal_map(p, t, progress=lambda fraction: False)


def test_circle_pattern_map_flips_to_intrinsic_delaunay_ignores_rigid_motion_and_cancels():
    p, t = load_mesh("disk_nefertiti_small.obj")
    uv, report = uvflat.circle_pattern_map(p, t)
    assert report.closure_error < 1e-9 and report.radius_iterations >= 1
    assert report.intrinsic_flips > 0
    m = uvflat.metrics(p, t, uv)
    assert m.flipped == report.flipped_triangles == 0 and m.degenerate_uv == 0
    # Without the flips: no flip can occur, but the Delaunay condition on the mesh's own edges
    # distorts the angles (2.80° mean against 1.49° with the flips and 1.53° for LSCM).
    plain, plain_report = uvflat.circle_pattern_map(p, t, intrinsic_delaunay=False)
    assert plain_report.intrinsic_flips == 0 and plain_report.flipped_triangles == 0
    natural = uvflat.metrics(p, t, uvflat.natural_conformal_map(p, t)).angle_mean
    assert m.angle_mean <= natural < uvflat.metrics(p, t, plain).angle_mean
    c, s = np.cos(0.7), np.sin(0.7)
    rotation = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    # Intrinsic, pinned at (0, 0) and (d, 0) (d the pins' 3D distance): the same map up to
    # the input's scale, whatever the rigid motion.
    moved, _ = uvflat.circle_pattern_map(p @ rotation.T * 3.0 + [1.0, -2.0, 5.0], t)
    assert np.allclose(moved, 3.0 * uv, atol=1e-6 * np.abs(uv).max() * 3.0)
    with pytest.raises(uvflat.UnsupportedTopology):
        uvflat.circle_pattern_map(*load_mesh("closed_g0_decimated_knight.obj"))
    with pytest.raises(uvflat.Cancelled):
        uvflat.circle_pattern_map(p, t, progress=lambda fraction: False)
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.circle_pattern_map(p, t, max_iterations=0)


def test_circle_pattern_map_onto_a_rectangle_by_prescribed_boundary_curvature():
    p, t = load_mesh("disk_nefertiti_small.obj")
    loop = max(uvflat.boundary_loops(p, t), key=len)
    corners = loop[[0, len(loop) // 4, len(loop) // 2, 3 * len(loop) // 4]]
    uv, report = uvflat.circle_pattern_map(p, t, corners=corners)
    assert report.closure_error < 1e-9
    # The uv boundary turns by π/2 at the four corners and not at all elsewhere.
    a, v, b = uv[np.roll(loop, 1)], uv[loop], uv[np.roll(loop, -1)]
    d1, d2 = v - a, b - v
    turning = np.arctan2(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0], (d1 * d2).sum(axis=1))
    expected = np.where(np.isin(loop, corners), np.pi / 2, 0.0)
    assert np.abs(turning - expected).max() < 1e-8
    curvature = uvflat.polygon_boundary_curvature(p, t, corners)
    assert np.isnan(curvature).sum() == len(p) - len(loop)
    same, _ = uvflat.circle_pattern_map(p, t, boundary_curvature=curvature)
    assert np.array_equal(same, uv)
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.circle_pattern_map(p, t, corners=corners, boundary_curvature=curvature)
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.circle_pattern_map(p, t, boundary_curvature=curvature[:-1])
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.polygon_boundary_curvature(p, t, corners[:2])
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.circle_pattern_map(p, t, boundary_curvature=np.where(np.isnan(curvature), np.nan, 0.1))


def test_circle_pattern_map_with_a_convex_boundary():
    p, t = load_mesh("disk_nefertiti_small.obj")
    loop = max(uvflat.boundary_loops(p, t), key=len)

    def turning(uv):
        a, v, b = uv[np.roll(loop, 1)], uv[loop], uv[np.roll(loop, -1)]
        d1, d2 = v - a, b - v
        return np.arctan2(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0], (d1 * d2).sum(axis=1))

    free, free_report = uvflat.circle_pattern_map(p, t)
    assert turning(free).min() < -0.05  # the free map's boundary is concave somewhere
    uv, report = uvflat.circle_pattern_map(p, t, convex_boundary=True)
    assert report.closure_error < 1e-9 and 0.0 < report.radius_span < 12.0
    assert turning(uv).min() > -1e-9 and abs(turning(uv).sum() - 2.0 * np.pi) < 1e-8
    m, f = uvflat.metrics(p, t, uv), uvflat.metrics(p, t, free)
    assert m.flipped == report.flipped_triangles == 0 and m.boundary_intersections == 0
    assert f.angle_mean < m.angle_mean < uvflat.metrics(p, t, uvflat.fixed_boundary_map(p, t)).angle_mean
    # Three corners already turning by more than 2π leave the other vertices nothing convex.
    curvature = np.full(len(p), np.nan)
    curvature[loop[[0, len(loop) // 3, 2 * len(loop) // 3]]] = 2.2
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.circle_pattern_map(p, t, boundary_curvature=curvature, convex_boundary=True)


def test_automatic_cones_for_the_circle_pattern_cone_map():
    p, t = load_mesh("closed_g0_bunny.obj")
    placement = uvflat.place_cones(p, t)
    vertices, curvatures = placement.cones()
    assert len(set(vertices.tolist())) == len(vertices) <= 64 and placement.max_log_scale <= 0.7
    assert abs(curvatures.sum() - 4.0 * np.pi) < 1e-8  # Gauss–Bonnet on a sphere
    corner_uv, report = uvflat.circle_pattern_cone_map(p, t, placement.cones())
    assert report.closure_error < 1e-9 and report.flipped_triangles == 0
    same, _ = uvflat.circle_pattern_cone_map(p, t, placement)
    assert np.array_equal(same, corner_uv)
    # Fewer cones leave more scale distortion; none would leave the sphere's 4π nowhere to go.
    three = uvflat.place_cones(p, t, max_cones=3)
    assert len(three.vertices) == 3 and three.max_log_scale > placement.max_log_scale
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.place_cones(p, t, max_cones=-1)
    # No limit worth the name allocates no more than one place per vertex.
    assert len(uvflat.place_cones(p, t, max_cones=2**32 - 1).vertices) == len(vertices)
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.place_cones(p, t, max_log_scale=float("nan"))
    with pytest.raises(uvflat.Cancelled):
        uvflat.place_cones(p, t, progress=lambda fraction: False)
    # Genus 133 needs at least 2g − 2 = 264 cones: 64 are refused with the reason.
    with pytest.raises(uvflat.InvalidArgument, match="too few"):
        uvflat.place_cones(*load_mesh("closed_g133_cheese.obj"))


def test_circle_pattern_cone_map_of_a_sphere_and_a_torus():
    # Sphere: four cones of curvature π (a tetrahedron's corners, Σ = 4π = 2π χ).
    p, t = load_mesh("closed_g0_bunny.obj")
    chosen = [0]
    distance = np.linalg.norm(p - p[0], axis=1)
    while len(chosen) < 4:
        chosen.append(int(np.argmax(distance)))
        distance = np.minimum(distance, np.linalg.norm(p - p[chosen[-1]], axis=1))
    corner_uv, report = uvflat.circle_pattern_cone_map(p, t, {v: np.pi for v in chosen})
    assert corner_uv.shape == (len(t), 3, 2) and np.isfinite(corner_uv).all()
    assert report.closure_error < 1e-9 and report.flipped_triangles == 0
    # The uv angles around each cone sum to its cone angle, 2π − π.
    e1 = np.roll(corner_uv, -1, axis=1) - corner_uv
    e2 = np.roll(corner_uv, -2, axis=1) - corner_uv
    angle = np.arctan2(e1[..., 0] * e2[..., 1] - e1[..., 1] * e2[..., 0], (e1 * e2).sum(axis=2))
    for v in chosen:
        assert abs(angle[t == v].sum() - np.pi) < 1e-8
    # Torus: no cone needed (χ = 0); a closed torus without them is flat but cut open.
    p, t = load_mesh("closed_g1_torus.obj")
    corner_uv, report = uvflat.circle_pattern_cone_map(p, t, {})
    assert report.flipped_triangles == 0 and report.closure_error < 1e-9
    # Gauss–Bonnet, a boundary cone, malformed cones.
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.circle_pattern_cone_map(*load_mesh("closed_g0_bunny.obj"), {0: np.pi})
    disk = load_mesh("disk_nefertiti_small.obj")
    loop = uvflat.boundary_loops(*disk)[0]
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.circle_pattern_cone_map(*disk, {int(loop[0]): 1.0})
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.circle_pattern_cone_map(*disk, ([1, 2], [0.5]))
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.circle_pattern_cone_map(*disk, [1, 2])
    with pytest.raises(uvflat.Cancelled):
        uvflat.circle_pattern_cone_map(*disk, {}, progress=lambda fraction: False)


def test_quadcover_gives_integer_seams_and_cones_and_checks_its_input():
    p, t = load_mesh("closed_g3_triple_torus.obj")
    corner_uv, cones, report = uvflat.quadcover(p, t, cones_on_grid=True)
    assert corner_uv.shape == (len(t), 3, 2) and cones.shape == (len(p),)
    # Hopf–Poincaré for genus 3: the cone indices (in quarters) sum to 4 (2 − 2g) = −16.
    assert int(cones.sum()) == -16 and report.cone_count == int((cones != 0).sum())
    assert report.lattice_error < 1e-9 and report.energy >= report.energy_continuous - 1e-12
    # Every cone on an integer point, in every triangle around it.
    at_cones = corner_uv[np.isin(t, np.flatnonzero(cones))]
    assert np.abs(at_cones - np.round(at_cones)).max() < 1e-6
    # Across every interior edge: a quarter turn and an integer translation.
    corner_of = {}
    for f, tri in enumerate(t):
        for k in range(3):
            corner_of[(int(tri[k]), int(tri[(k + 1) % 3]))] = (f, k)
    turns = [np.array([[1, 0], [0, 1]]), np.array([[0, 1], [-1, 0]]), np.array([[-1, 0], [0, -1]]), np.array([[0, -1], [1, 0]])]
    for (a, b), (f, k) in corner_of.items():
        g, j = corner_of[(b, a)]
        fa, fb = corner_uv[f, k], corner_uv[f, (k + 1) % 3]
        gb, ga = corner_uv[g, j], corner_uv[g, (j + 1) % 3]
        r = min(turns, key=lambda m: np.linalg.norm(m @ (fb - fa) - (gb - ga)))
        assert np.linalg.norm(r @ (fb - fa) - (gb - ga)) < 1e-6
        shift = ga - r @ fa
        assert np.abs(shift - np.round(shift)).max() < 1e-6
    # The course notes' variant (the default): integer gaps, cones anywhere, fewer folds.
    _, _, gaps_only = uvflat.quadcover(p, t)
    assert gaps_only.lattice_error < 1e-9 and gaps_only.cone_count == report.cone_count
    # The cone-pair cancellation (default 2 cells) removes cones the field alone has, and
    # keeps the index sum.
    _, kept_cones, kept = uvflat.quadcover(p, t, pair_cells=0)
    assert kept.cones_before_cancellation == kept.cone_count == int((kept_cones != 0).sum())
    assert kept.cancelled_pairs == 0 and kept.cones_moved_to_boundary == 0
    assert report.cones_before_cancellation == kept.cone_count
    assert report.cone_count < kept.cone_count and report.cancelled_pairs > 0
    assert int(kept_cones.sum()) == -16
    with pytest.raises(uvflat.InvalidArgument, match="pair_cells"):
        uvflat.quadcover(p, t, pair_cells=-1.0)
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.quadcover(p, t, grid_spacing=-1.0)
    with pytest.raises(uvflat.InvalidArgument):
        uvflat.quadcover(p, t, field=np.ones((3, 3)))
    with pytest.raises(uvflat.Cancelled):
        uvflat.quadcover(p, t, progress=lambda fraction: False)


def test_quadcover_untangling_opens_the_folds_and_keeps_the_cones():
    p, t = load_mesh("closed_g1_bob.obj")

    def folded(uv):
        a, b, c = uv[:, 0], uv[:, 1], uv[:, 2]
        return int(np.sum((b - a)[:, 0] * (c - a)[:, 1] - (c - a)[:, 0] * (b - a)[:, 1] <= 0))

    raw_uv, raw_cones, raw = uvflat.quadcover(p, t, untangle=False)
    uv, cones, report = uvflat.quadcover(p, t)
    assert raw.flipped_count == folded(raw_uv) > 0 and raw.flipped_before_untangling == raw.flipped_count
    assert report.flipped_before_untangling == raw.flipped_count
    assert report.flipped_count == folded(uv) < raw.flipped_count
    assert report.forced_flat_count <= report.flipped_count
    # Only regular vertices move: the cones and their corners stay where the rounding put them.
    assert np.array_equal(cones, raw_cones)
    at_cones = np.isin(t, np.flatnonzero(cones))
    assert np.array_equal(uv[at_cones], raw_uv[at_cones])
    assert report.lattice_error < 1e-9


def test_quadcover_quad_mesh_is_a_closed_quad_mesh_with_a_quad_per_grid_cell():
    p, t = load_mesh("closed_g3_triple_torus.obj")
    corner_uv, _, report = uvflat.quadcover(p, t, cones_on_grid=True)
    positions, faces, quad_report = uvflat.quadcover_quad_mesh(p, t, cones_on_grid=True)
    assert quad_report == report
    # Closed and manifold: every directed edge once, with its opposite.
    directed = [(int(f[i]), int(f[(i + 1) % len(f)])) for f in faces for i in range(len(f))]
    assert len(set(directed)) == len(directed) and all((b, a) in set(directed) for a, b in directed)
    assert all(len(set(f.tolist())) == len(f) for f in faces) and positions.shape[1] == 3
    quads = sum(len(f) == 4 for f in faces)
    assert quads >= 0.95 * len(faces), (quads, len(faces))
    # About one face per grid cell: the (u, v) area of the map (cells it covers).
    a, b, c = corner_uv[:, 0], corner_uv[:, 1], corner_uv[:, 2]
    cells = 0.5 * np.sum((b - a)[:, 0] * (c - a)[:, 1] - (c - a)[:, 0] * (b - a)[:, 1])
    assert abs(len(faces) - cells) <= 0.05 * cells, (len(faces), cells)
    # Twice the lines per unit: about four times the faces.
    _, finer, _ = uvflat.quadcover_quad_mesh(p, t, cones_on_grid=True, density=2)
    assert 3.6 * len(faces) <= len(finer) <= 4.4 * len(faces)
    with pytest.raises(uvflat.InvalidArgument, match="density"):
        uvflat.quadcover_quad_mesh(p, t, density=2.5)
    with pytest.raises(uvflat.Cancelled):
        uvflat.quadcover_quad_mesh(p, t, progress=lambda fraction: False)


def test_boundary_editor_matches_a_fresh_solve_and_its_basis():
    p, t = load_mesh("disk_nefertiti_small.obj")
    with uvflat.BoundaryEditor(p, t, lambda_=1.0, mu=0.0) as editor:
        ring = editor.boundary
        assert len(ring) > 3 and set(ring.tolist()) <= set(uvflat.boundary_loops(p, t)[0].tolist())
        angle = np.linspace(0.0, 2.0 * np.pi, len(ring), endpoint=False)
        boundary_uv = np.c_[np.cos(angle), 0.5 * np.sin(angle)]
        uv = editor.solve(boundary_uv)
        fresh = uvflat.fixed_boundary_map(p, t, weights="conformal", boundary=(ring, boundary_uv))
        assert np.abs(uv - fresh).max() <= 1e-9
        basis = editor.basis()
        assert basis.shape == (len(ring), len(p))
        assert np.abs(basis.T @ boundary_uv - uv).max() <= 1e-9
        with pytest.raises(uvflat.InvalidArgument):
            editor.basis(max_bytes=8)
        with pytest.raises(uvflat.InvalidArgument):
            editor.solve(boundary_uv[:-1])
    with pytest.raises(uvflat.UnsupportedTopology):
        uvflat.BoundaryEditor(*load_mesh("closed_g0_decimated_knight.obj"))


def test_closing_a_boundary_editor_waits_for_a_solve_in_another_thread():
    # close() used to free the factorization under a solve() running without the GIL (a
    # segmentation fault); now it waits, and the solves after it are refused.
    p, t = load_mesh("disk_nefertiti_small.obj")
    editor = uvflat.BoundaryEditor(p, t)
    angle = np.linspace(0.0, 2.0 * np.pi, len(editor.boundary), endpoint=False)
    boundary_uv = np.c_[np.cos(angle), np.sin(angle)]
    outcome: list = []
    solved = threading.Event()

    def solve_until_closed() -> None:
        try:
            while True:
                editor.solve(boundary_uv)
                solved.set()
        except BaseException as e:  # noqa: B902 - the test inspects it
            outcome.append(e)

    worker = threading.Thread(target=solve_until_closed)
    worker.start()
    assert solved.wait(60)
    editor.close()
    worker.join(60)
    assert not worker.is_alive()
    assert len(outcome) == 1 and isinstance(outcome[0], uvflat.InvalidArgument), outcome


def test_iteration_limits_beyond_32_bits_are_refused_not_wrapped():
    p, t = load_mesh("disk_nefertiti_small.obj")
    with pytest.raises(uvflat.InvalidArgument, match="iterations"):
        uvflat.nonlinear_map(p, t, "slim", iterations=2**32 + 3)
    with pytest.raises(uvflat.InvalidArgument, match="max_iterations"):
        uvflat.abf(p, t, max_iterations=2**32)
    with pytest.raises(uvflat.InvalidArgument, match="iterations"):
        uvflat.spectral_conformal_map(p, t, iterations=-1)


def test_a_cancellation_the_callback_did_not_ask_for_is_an_interrupt():
    # Ctrl-C raised as the callback is entered, before its `try`, is swallowed by ctypes and
    # ends the call as cancelled; the bridge tells that apart from a real cancellation.
    bridge = _common._ProgressBridge(lambda fraction: True)
    with pytest.raises(KeyboardInterrupt):
        bridge.run(lambda: int(_errors.Status.CANCELLED))
    declining = _common._ProgressBridge(lambda fraction: False)
    assert declining._call(None, 0.5) == 1
    with pytest.raises(uvflat.Cancelled):
        declining.run(lambda: int(_errors.Status.CANCELLED))


def test_empty_index_lists_are_empty_and_float_pin_vertices_are_refused():
    p, t = load_mesh("disk_nefertiti_small.obj")
    # An empty list is an empty index array, not "floats".
    assert _common._as_indices([], "corners", uvflat.InvalidArgument, None).shape == (0,)
    with pytest.raises(uvflat.InvalidArgument, match="pins"):
        uvflat.natural_conformal_map(p, t, pins=((0.9, (0.0, 0.0)), (5.7, (1.0, 0.0))))
    with pytest.raises(uvflat.InvalidArgument, match="pins"):
        uvflat.pinned_natural_conformal_map(p, t, {0.5: (0.0, 0.0), 3: (1.0, 0.0)})
