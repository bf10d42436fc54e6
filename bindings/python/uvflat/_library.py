"""Finding and loading ``libuvflat``, and the ctypes mirror of ``include/uvflat.h``.

Everything here follows the header line by line: the structs are ``ctypes.Structure``
subclasses with the header's fields in the header's order, and every ``uvf_*`` function gets
its ``argtypes`` and ``restype`` when the library is loaded. Nothing here converts arrays or
raises per-call errors; that is :mod:`uvflat._api`'s job.

Where the library comes from, in this order:

1. the path given to :func:`load_library`;
2. the ``UVFLAT_LIBRARY`` environment variable (a path to the shared library);
3. a ``libuvflat.so`` (``.dylib``, ``uvflat.dll``) copied into this package's directory;
4. the system search path (``ctypes.util.find_library("uvflat")``, then plain
   ``libuvflat.so``, which the dynamic loader looks up in ``LD_LIBRARY_PATH`` and the
   ``ldconfig`` cache).

GIL: calls through a ``ctypes.CDLL`` release the GIL for the duration of the C call, so
several Python threads can run uvflat functions at the same time (the library is reentrant and
its error message is thread-local). A progress callback re-acquires the GIL while it runs.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import os
import sys
import threading
from ctypes import (
    CFUNCTYPE,
    POINTER,
    Structure,
    c_char_p,
    c_double,
    c_int,
    c_int64,
    c_size_t,
    c_uint32,
    c_uint64,
    c_void_p,
)
from typing import Optional, Union

from ._errors import LibraryError

#: The ABI version this binding was written for (``UVF_ABI_VERSION`` in ``uvflat.h``).
ABI_VERSION = 1

#: Name of the environment variable that points at the shared library.
LIBRARY_ENV = "UVFLAT_LIBRARY"

# --- constants (uvflat.h) -------------------------------------------------------------------

UVF_WEIGHTS_UNIFORM = 0
UVF_WEIGHTS_FLOATER = 1
UVF_WEIGHTS_AUTHALIC = 2
UVF_WEIGHTS_CONFORMAL = 3
UVF_WEIGHTS_MEAN_VALUE = 4
UVF_WEIGHTS_INTRINSIC = 5

UVF_BOUNDARY_CIRCLE = 0
UVF_BOUNDARY_SQUARE = 1
UVF_BOUNDARY_GIVEN = 2

UVF_DISTRIBUTION_UNIFORM = 0
UVF_DISTRIBUTION_CHORD = 1
UVF_DISTRIBUTION_CENTRIPETAL = 2

UVF_ABF_VARIANT_ABF = 0
UVF_ABF_VARIANT_ABF_PLUS_PLUS = 1

UVF_NONLINEAR_SLIM = 0
UVF_NONLINEAR_ARAP = 1
UVF_NONLINEAR_MIPS = 2
UVF_NONLINEAR_STRETCH = 3
UVF_NONLINEAR_GREEN_LAGRANGE = 4
UVF_NONLINEAR_DEGENER = 5

UVF_CUT_COST_CURVATURE = 0
UVF_CUT_COST_LENGTH = 1
UVF_CUT_COST_GIVEN = 2

UVF_SPHERE_TUTTE_GNOMONIC = 0
UVF_SPHERE_GAUSS_SEIDEL = 1
UVF_SPHERE_STEREOGRAPHIC = 2

# --- types (uvflat.h) -----------------------------------------------------------------------

#: ``enum UvfStatus`` is passed as a C ``int``.
UvfStatus = c_int

#: ``typedef int (*UvfProgressFn)(void *user, double fraction);``
UvfProgressFn = CFUNCTYPE(c_int, c_void_p, c_double)


class UvfMeshInfo(Structure):
    """``struct UvfMeshInfo``: counts and topological invariants of a mesh."""

    _fields_ = [
        ("vertices", c_size_t),
        ("referenced_vertices", c_size_t),
        ("triangles", c_size_t),
        ("edges", c_size_t),
        ("components", c_size_t),
        ("boundary_loops", c_size_t),
        ("boundary_vertices", c_size_t),
        ("euler_characteristic", c_int64),
        ("genus", c_int64),
    ]


class UvfFixedBoundaryOptions(Structure):
    """``struct UvfFixedBoundaryOptions``; fill with ``uvf_fixed_boundary_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("weights", c_uint32),
        ("boundary", c_uint32),
        ("distribution", c_uint32),
        ("lambda_", c_double),  # `lambda` in C; a Python keyword
        ("mu", c_double),
        ("given_count", c_size_t),
        ("given_vertices", POINTER(c_uint32)),
        ("given_uv", POINTER(c_double)),
        ("progress", UvfProgressFn),
        ("progress_user", c_void_p),
    ]


class UvfNaturalConformalOptions(Structure):
    """``struct UvfNaturalConformalOptions``; fill with ``uvf_natural_conformal_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("pin_count", c_uint32),
        ("pin_vertices", c_uint32 * 2),
        ("pin_uv", c_double * 4),
        ("progress", UvfProgressFn),
        ("progress_user", c_void_p),
    ]


class UvfMetrics(Structure):
    """``struct UvfMetrics``: distortion summary of a UV map."""

    _fields_ = [
        ("triangles", c_size_t),
        ("flipped", c_size_t),
        ("degenerate_uv", c_size_t),
        ("boundary_intersections", c_size_t),
        ("stretch_l2", c_double),
        ("stretch_linf", c_double),
        ("conformal_mean", c_double),
        ("conformal_max", c_double),
        ("angle_mean", c_double),
        ("angle_max", c_double),
        ("area_mean", c_double),
        ("area_max", c_double),
    ]


class UvfAbfOptions(Structure):
    """``struct UvfAbfOptions``; fill with ``uvf_abf_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("variant", c_uint32),
        ("max_iterations", c_uint32),
        ("tolerance", c_double),
        ("pin_count", c_uint32),
        ("pin_vertices", c_uint32 * 2),
        ("pin_uv", c_double * 4),
        ("progress", UvfProgressFn),
        ("progress_user", c_void_p),
    ]


class UvfAbfReport(Structure):
    """``struct UvfAbfReport``: iterations and convergence of an ABF / ABF++ run."""

    _fields_ = [
        ("iterations", c_uint32),
        ("converged", c_uint32),
        ("gradient_norm", c_double),
        ("invalid_angles", c_uint64),
    ]


class UvfIntrinsicToolOptions(Structure):
    """``struct UvfIntrinsicToolOptions``; fill with ``uvf_intrinsic_tool_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("progress", UvfProgressFn),
        ("progress_user", c_void_p),
    ]


class UvfPointConstraint(Structure):
    """``struct UvfPointConstraint``: a point (triangle, barycentric coordinates) and its UV."""

    _fields_ = [
        ("triangle", c_uint32),
        ("barycentric", c_double * 3),
        ("uv", c_double * 2),
    ]


class UvfNonlinearOptions(Structure):
    """``struct UvfNonlinearOptions``; fill with ``uvf_nonlinear_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("method", c_uint32),
        ("iterations", c_uint32),
        ("tolerance", c_double),
        ("theta", c_double),
        ("progress", UvfProgressFn),
        ("progress_user", c_void_p),
    ]


class UvfNonlinearReport(Structure):
    """``struct UvfNonlinearReport``: iterations and energies of a non-linear run."""

    _fields_ = [
        ("iterations", c_uint32),
        ("converged", c_uint32),
        ("initial_energy", c_double),
        ("final_energy", c_double),
    ]


class UvfCutOptions(Structure):
    """``struct UvfCutOptions``; fill with ``uvf_cut_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("cost", c_uint32),
        ("edge_cost", POINTER(c_double)),
    ]


class UvfCutInfo(Structure):
    """``struct UvfCutInfo``: sizes of a cut's outputs and its seam length."""

    _fields_ = [
        ("vertex_count", c_size_t),
        ("triangle_count", c_size_t),
        ("edge_count", c_size_t),
        ("seam_length", c_double),
        ("total_edge_length", c_double),
    ]


class UvfSphereOptions(Structure):
    """``struct UvfSphereOptions``; fill with ``uvf_sphere_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("method", c_uint32),
        ("sweeps", c_uint32),
    ]


class UvfBoundaryEditor(Structure):
    """Opaque ``struct UvfBoundaryEditor`` (only used through pointers)."""


class UvfCut(Structure):
    """Opaque ``struct UvfCut`` (only used through pointers)."""


_f64p = POINTER(c_double)
_u32p = POINTER(c_uint32)

#: Every function of ``uvflat.h``: name -> (restype, argtypes).
PROTOTYPES = {
    "uvf_last_error_message": (c_char_p, []),
    "uvf_version": (c_char_p, []),
    "uvf_abi_version": (c_uint32, []),
    "uvf_mesh_info": (UvfStatus, [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfMeshInfo)]),
    "uvf_boundary_loops": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, _u32p, c_size_t, _u32p, c_size_t],
    ),
    "uvf_triangle_components": (UvfStatus, [_f64p, c_size_t, _u32p, c_size_t, _u32p]),
    "uvf_fixed_boundary_options_default": (None, [POINTER(UvfFixedBoundaryOptions)]),
    "uvf_natural_conformal_options_default": (None, [POINTER(UvfNaturalConformalOptions)]),
    "uvf_fixed_boundary_map": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfFixedBoundaryOptions), _f64p],
    ),
    "uvf_natural_conformal_map": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfNaturalConformalOptions), _f64p],
    ),
    "uvf_metrics": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, _f64p, c_size_t, _u32p, POINTER(UvfMetrics)],
    ),
    "uvf_abf_options_default": (None, [POINTER(UvfAbfOptions)]),
    "uvf_abf": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfAbfOptions), _f64p, POINTER(UvfAbfReport)],
    ),
    "uvf_intrinsic_tool_options_default": (None, [POINTER(UvfIntrinsicToolOptions)]),
    "uvf_constrained_fixed_boundary_map": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfFixedBoundaryOptions), POINTER(UvfPointConstraint), c_size_t, _f64p],
    ),
    "uvf_constrained_natural_conformal_map": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfPointConstraint), c_size_t, POINTER(UvfIntrinsicToolOptions), _f64p],
    ),
    "uvf_pinned_natural_conformal_map": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, _u32p, _f64p, c_size_t, POINTER(UvfIntrinsicToolOptions), _f64p],
    ),
    "uvf_boundary_editor_new": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, c_double, c_double, POINTER(UvfIntrinsicToolOptions), POINTER(POINTER(UvfBoundaryEditor))],
    ),
    "uvf_boundary_editor_free": (None, [POINTER(UvfBoundaryEditor)]),
    "uvf_boundary_editor_boundary": (UvfStatus, [POINTER(UvfBoundaryEditor), POINTER(c_size_t), _u32p]),
    "uvf_boundary_editor_solve": (UvfStatus, [POINTER(UvfBoundaryEditor), _f64p, c_size_t, _f64p]),
    "uvf_boundary_editor_basis": (UvfStatus, [POINTER(UvfBoundaryEditor), c_size_t, _f64p]),
    "uvf_spectral_conformal_map": (UvfStatus, [_f64p, c_size_t, _u32p, c_size_t, _f64p]),
    "uvf_intrinsic_optimal_map": (UvfStatus, [_f64p, c_size_t, _u32p, c_size_t, c_uint32, _f64p, _f64p]),
    "uvf_boundary_optimized_map": (UvfStatus, [_f64p, c_size_t, _u32p, c_size_t, c_uint32, _f64p]),
    "uvf_nonlinear_options_default": (None, [POINTER(UvfNonlinearOptions)]),
    "uvf_nonlinear_map": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfNonlinearOptions), _f64p, POINTER(UvfNonlinearReport)],
    ),
    "uvf_cut_options_default": (None, [POINTER(UvfCutOptions)]),
    "uvf_cut_to_disk": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfCutOptions), POINTER(POINTER(UvfCut))],
    ),
    "uvf_cut_info": (UvfStatus, [POINTER(UvfCut), POINTER(UvfCutInfo)]),
    "uvf_cut_copy_edges": (UvfStatus, [POINTER(UvfCut), _u32p, c_size_t]),
    "uvf_cut_copy_triangles": (UvfStatus, [POINTER(UvfCut), _u32p, c_size_t]),
    "uvf_cut_copy_original_vertices": (UvfStatus, [POINTER(UvfCut), _u32p, c_size_t]),
    "uvf_cut_copy_positions": (UvfStatus, [POINTER(UvfCut), _f64p, c_size_t]),
    "uvf_cut_free": (None, [POINTER(UvfCut)]),
    "uvf_sphere_options_default": (None, [POINTER(UvfSphereOptions)]),
    "uvf_spherical_map": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfSphereOptions), _f64p, POINTER(c_size_t)],
    ),
}

# --- loading --------------------------------------------------------------------------------

_lock = threading.Lock()
_loaded: Optional[ctypes.CDLL] = None
_loaded_path: Optional[str] = None

PathLike = Union[str, "os.PathLike[str]"]


def _library_file_names() -> list:
    if sys.platform == "darwin":
        return ["libuvflat.dylib"]
    if sys.platform == "win32":
        return ["uvflat.dll"]
    return ["libuvflat.so"]


def _candidates(path: Optional[PathLike]) -> list:
    """Where to look, in order, as (description, path or name) pairs."""
    if path is not None:
        return [("explicit path", os.fspath(path))]
    env = os.environ.get(LIBRARY_ENV)
    if env:
        # An explicit setting that is wrong is an error, not a reason to look elsewhere.
        return [(f"${LIBRARY_ENV}", env)]
    found = []
    here = os.path.dirname(os.path.abspath(__file__))
    for name in _library_file_names():
        local = os.path.join(here, name)
        if os.path.exists(local):
            found.append(("package directory", local))
    system = ctypes.util.find_library("uvflat")
    if system:
        found.append(("system search path", system))
    found.extend(("system search path", name) for name in _library_file_names())
    return found


def _declare(lib: ctypes.CDLL) -> None:
    for name, (restype, argtypes) in PROTOTYPES.items():
        try:
            function = getattr(lib, name)
        except AttributeError as e:
            raise LibraryError(f"{lib._name} has no function {name}; is it an older libuvflat?") from e
        function.restype = restype
        function.argtypes = argtypes


def _check(lib: ctypes.CDLL, where: str) -> ctypes.CDLL:
    _declare(lib)
    abi = lib.uvf_abi_version()
    if abi != ABI_VERSION:
        raise LibraryError(
            f"{where} has ABI version {abi} but this uvflat binding was written for ABI version "
            f"{ABI_VERSION}; install matching versions of the library and the binding"
        )
    return lib


def load_library(path: Optional[PathLike] = None) -> ctypes.CDLL:
    """Loads ``libuvflat`` and makes it the library every uvflat function calls.

    With ``path``, loads exactly that file. Without, looks in ``$UVFLAT_LIBRARY``, then for a
    copy in the package directory, then on the system search path (see the module docs).
    Declares every function's prototype and checks that the library's
    ``uvf_abi_version()`` equals :data:`ABI_VERSION`.

    Returns the ``ctypes.CDLL``. Raises :class:`uvflat.LibraryError` when no library can be
    loaded, a function is missing, or the ABI version differs; the previously loaded library,
    if any, stays in use.
    """
    global _loaded, _loaded_path
    failures = []
    for description, where in _candidates(path):
        try:
            lib = ctypes.CDLL(where)
        except OSError as e:
            failures.append(f"{where} ({description}): {e}")
            continue
        lib = _check(lib, where)  # a library that loads but does not fit is an error at once
        with _lock:
            _loaded, _loaded_path = lib, where
        return lib
    raise LibraryError(
        "cannot load libuvflat: pass its path to uvflat.load_library(), set "
        f"{LIBRARY_ENV}, copy it into {os.path.dirname(os.path.abspath(__file__))}, or put it "
        "on the system library path; tried:" + "".join("\n  " + f for f in failures)
    )


def library() -> ctypes.CDLL:
    """The loaded library, loading it on first use with :func:`load_library`'s search order."""
    lib = _loaded
    return lib if lib is not None else load_library()


def library_path() -> str:
    """The path (or name given to the dynamic loader) of the library in use; loads it if needed."""
    library()
    assert _loaded_path is not None
    return _loaded_path
