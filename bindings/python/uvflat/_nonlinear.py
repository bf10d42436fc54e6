"""Distortion-minimizing maps: SLIM, ARAP, MIPS, stretch, Green–Lagrange, Degener, and ABF / ABF++."""

from __future__ import annotations

import ctypes
import dataclasses
import threading
from ctypes import POINTER, byref, c_double, c_uint32
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _library as L
from ._mesh import Mesh
from ._errors import Error, InternalError, InvalidArgument, InvalidMesh, Status, error_for_status
from ._common import ArrayLike, Pins, ProgressCallback, _ProgressBridge, _code, _f64p, _from_struct, _mesh_source, _non_negative_int, _on_mesh, _set_two_pins


_NONLINEAR = {
    "slim": L.UVF_NONLINEAR_SLIM,
    "arap": L.UVF_NONLINEAR_ARAP,
    "mips": L.UVF_NONLINEAR_MIPS,
    "stretch": L.UVF_NONLINEAR_STRETCH,
    "green_lagrange": L.UVF_NONLINEAR_GREEN_LAGRANGE,
    "degener": L.UVF_NONLINEAR_DEGENER,
}


@dataclasses.dataclass(frozen=True)
class NonlinearReport:
    """What ``uvf_nonlinear_map`` reports about its run."""

    iterations: int
    converged: int
    initial_energy: float
    final_energy: float


def nonlinear_map(
    positions: ArrayLike,
    triangles: Optional[ArrayLike] = None,
    method: Union[str, int] = "slim",
    *,
    iterations: Optional[int] = None,
    tolerance: Optional[float] = None,
    theta: Optional[float] = None,
    bijective: bool = False,
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, NonlinearReport]:
    """Free-boundary distortion minimisation that never flips a triangle
    (``uvf_nonlinear_map``): ``slim`` (symmetric Dirichlet, Rabinovich et al. 2017), ``arap``
    (Liu et al. 2008), ``mips`` (Hormann & Greiner 2000), ``stretch`` (Sander et al. 2001),
    ``green_lagrange`` (Maillot et al. 1993), ``degener`` (Degener et al. 2003, ``theta``).
    ``bijective``: a scaffold around the free boundary keeps it from running into itself, so
    the whole map is one-to-one (Jiang et al. 2017); ``slim`` optimizes map and scaffold
    together, the other methods stop a step where the boundary meets itself (a higher final
    energy where the boundary would have crossed). ``arap`` and
    ``green_lagrange`` keep every triangle at or above 1% of its share of the UV area (their
    energies alone would let a triangle be pressed flat).

    Returns:
        ``(uv, report)``: ``(n, 2)`` UVs and a :class:`NonlinearReport`.
    """
    p, t = _mesh_source(positions, triangles)
    options = L.UvfNonlinearOptions()
    L.library().uvf_nonlinear_options_default(byref(options))
    options.method = _code(method, _NONLINEAR, "method")
    if iterations is not None:
        options.iterations = _non_negative_int(iterations, "iterations")
    if tolerance is not None:
        options.tolerance = float(tolerance)
    if theta is not None:
        options.theta = float(theta)
    options.bijective = 1 if bijective else 0
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    report = L.UvfNonlinearReport()
    lib = L.library()
    bridge.run(lambda: _on_mesh(lib, "nonlinear_map", p, t, byref(options), _f64p(uv), byref(report)))
    return uv, _from_struct(NonlinearReport, report)


@dataclasses.dataclass(frozen=True)
class AbfReport:
    """What ``uvf_abf`` reports about its run."""

    iterations: int
    converged: int
    gradient_norm: float
    invalid_angles: int


def abf(
    positions: ArrayLike,
    triangles: Optional[ArrayLike] = None,
    *,
    variant: str = "abf++",
    max_iterations: Optional[int] = None,
    tolerance: Optional[float] = None,
    pins: Optional[Pins] = None,
    weights: str = "angle_and_supplement",
    barrier: Optional[float] = None,
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, AbfReport]:
    """Angle based flattening (``uvf_abf``): ``"abf++"`` (Sheffer et al. 2005, default) or
    ``"abf"`` (Sheffer & de Sturler 2001), then the LSCM-style reconstruction of UVs.

    Args:
        weights: the objective's weights w in Σ w (α − β)²: ``"angle_and_supplement"``
            (1/(β(π − β)), default), ``"inverse_square"`` (1/β², the papers') or ``"inverse"``.
        barrier: μ ≥ 0 of the angle barrier μ Σ (α/β − ln(α/β) − 1) (default 1); ``0`` with
            ``weights="inverse_square"`` is the papers' objective.
        pins: ``None`` (default) or ``((v0, (u0, v0_)), (v1, (u1, v1_)))``: the two vertices
            the reconstruction pins and their UVs, as for :func:`natural_conformal_map` (by
            default the two boundary vertices farthest apart).

    Returns:
        ``(uv, report)``: ``(n, 2)`` UVs and an :class:`AbfReport`.
    """
    p, t = _mesh_source(positions, triangles)
    options = L.UvfAbfOptions()
    L.library().uvf_abf_options_default(byref(options))
    options.variant = _code(variant, {"abf": L.UVF_ABF_VARIANT_ABF, "abf++": L.UVF_ABF_VARIANT_ABF_PLUS_PLUS}, "variant")
    if pins is not None:
        _set_two_pins(options, pins)
    if max_iterations is not None:
        options.max_iterations = _non_negative_int(max_iterations, "max_iterations")
    if tolerance is not None:
        options.tolerance = float(tolerance)
    options.weights = _code(
        weights,
        {
            "angle_and_supplement": L.UVF_ABF_WEIGHTS_ANGLE_AND_SUPPLEMENT,
            "inverse_square": L.UVF_ABF_WEIGHTS_INVERSE_SQUARE,
            "inverse": L.UVF_ABF_WEIGHTS_INVERSE,
        },
        "weights",
    )
    if barrier is not None:
        options.barrier = float(barrier)
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    report = L.UvfAbfReport()
    lib = L.library()
    bridge.run(lambda: _on_mesh(lib, "abf", p, t, byref(options), _f64p(uv), byref(report)))
    return uv, _from_struct(AbfReport, report)
