"""The tools of Desbrun, Meyer & Alliez 2002 (boundary editor, near-optimal map, boundary
optimization) and the spectral conformal map."""

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
from ._common import ArrayLike, Boundary, ProgressCallback, _DISTRIBUTIONS, _ENERGIES, _ProgressBridge, _U32_MAX, _check, _code, _f64p, _from_struct, _mesh_arrays, _non_negative_int, _set_boundary, _u32p


@dataclasses.dataclass(frozen=True)
class SpectralReport:
    """What ``uvf_spectral_conformal_map`` reports: the eigenpair behind the map."""

    iterations: int
    converged: int
    #: λ of ``L_C z = λ B z``.
    eigenvalue: float
    #: Normwise backward error of the eigenpair.
    residual: float


def spectral_conformal_map(
    positions: ArrayLike,
    triangles: ArrayLike,
    *,
    iterations: Optional[int] = None,
    tolerance: Optional[float] = None,
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, SpectralReport]:
    """Spectral conformal map (Mullen, Tong, Alliez, Desbrun 2008; ``uvf_spectral_conformal_map``):
    free-boundary conformal map without pins, the smallest non-trivial generalized eigenvector
    of the conformal energy against the boundary mass, by inverse iteration. Scaled to the
    surface area, farthest boundary pair from (0, 0) along +u.

    Returns:
        ``(uv, report)``: ``(n, 2)`` UVs (NaN for unreferenced vertices) and a
        :class:`SpectralReport`.
    """
    p, t = _mesh_arrays(positions, triangles)
    options = L.UvfSpectralOptions()
    L.library().uvf_spectral_options_default(byref(options))
    if iterations is not None:
        options.iterations = _non_negative_int(iterations, "iterations")
    if tolerance is not None:
        options.tolerance = float(tolerance)
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    report = L.UvfSpectralReport()
    lib = L.library()
    bridge.run(
        lambda: lib.uvf_spectral_conformal_map(_f64p(p), len(p), _u32p(t), len(t), byref(options), _f64p(uv), byref(report))
    )
    return uv, _from_struct(SpectralReport, report)


@dataclasses.dataclass(frozen=True)
class IntrinsicOptimalReport:
    """What ``uvf_intrinsic_optimal_map`` reports."""

    #: The minimizing λ of ``λ·U^A + (1 − λ)·U^χ``.
    lambda_: float
    energy: float
    #: Energy of the DCP map (λ = 1).
    energy_conformal: float
    #: Energy of the DAP map (λ = 0).
    energy_authalic: float
    boundary_scale: float
    #: Clockwise or degenerate UV triangles of the result.
    flipped: int


def intrinsic_optimal_map(
    positions: ArrayLike,
    triangles: ArrayLike,
    *,
    energy: Union[str, int] = "edge",
    boundary: Boundary = "circle",
    distribution: Union[str, int] = "chord",
    lambda_min: float = float("-inf"),
    lambda_max: float = float("inf"),
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, IntrinsicOptimalReport]:
    """Near-optimal intrinsic map (Desbrun et al. 2002 §5.1; ``uvf_intrinsic_optimal_map``):
    ``λ·DCP + (1 − λ)·DAP`` (the two maps, same boundary) of least ``energy`` — ``"edge"``
    (edge-length distortion) or ``"area"`` — over λ in [``lambda_min``, ``lambda_max``],
    by exact polynomial minimization. A circle or square boundary is scaled to the surface area.

    Returns:
        ``(uv, report)``: ``(n, 2)`` UVs and an :class:`IntrinsicOptimalReport`.
    """
    p, t = _mesh_arrays(positions, triangles)
    options = L.UvfIntrinsicOptimalOptions()
    L.library().uvf_intrinsic_optimal_options_default(byref(options))
    options.energy = _code(energy, _ENERGIES, "energy")
    keep = _set_boundary(options, boundary)
    options.distribution = _code(distribution, _DISTRIBUTIONS, "distribution")
    options.lambda_min = float(lambda_min)
    options.lambda_max = float(lambda_max)
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    report = L.UvfIntrinsicOptimalReport()
    lib = L.library()
    bridge.run(
        lambda: lib.uvf_intrinsic_optimal_map(_f64p(p), len(p), _u32p(t), len(t), byref(options), _f64p(uv), byref(report))
    )
    del keep
    return uv, _from_struct(IntrinsicOptimalReport, report)


@dataclasses.dataclass(frozen=True)
class BoundaryOptimizationReport:
    """What ``uvf_boundary_optimized_map`` reports."""

    iterations: int
    converged: int
    #: Entries of the energy history (iterations + 1).
    history_length: int
    initial_energy: float
    final_energy: float
    boundary_scale: float
    #: Triangles flipped in the start, kept as they are by every step (0 for a flip-free start).
    flipped: int


def boundary_optimized_map(
    positions: ArrayLike,
    triangles: ArrayLike,
    *,
    energy: Union[str, int] = "edge",
    lambda_: float = 1.0,
    mu: float = 0.0,
    iterations: Optional[int] = None,
    tolerance: Optional[float] = None,
    boundary: Boundary = "circle",
    distribution: Union[str, int] = "chord",
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, np.ndarray, BoundaryOptimizationReport]:
    """Boundary-optimized intrinsic map (Desbrun et al. 2002 §5.2; ``uvf_boundary_optimized_map``):
    the λ·DCP + μ·DAP map whose outer boundary descends ``energy`` (``"edge"`` or ``"area"``),
    with steps that never flip or degenerate a triangle. ``progress`` is called once per
    iteration; returning ``False`` cancels before the next one.

    Returns:
        ``(uv, history, report)``: ``(n, 2)`` UVs, the energy history (start first,
        non-increasing; its first 2^20 entries) and a :class:`BoundaryOptimizationReport`.
    """
    p, t = _mesh_arrays(positions, triangles)
    options = L.UvfBoundaryOptimizationOptions()
    L.library().uvf_boundary_optimization_options_default(byref(options))
    options.energy = _code(energy, _ENERGIES, "energy")
    options.lambda_ = float(lambda_)
    options.mu = float(mu)
    if iterations is not None:
        if not 0 <= int(iterations) <= _U32_MAX:
            raise InvalidArgument(f"iterations must be in [0, {_U32_MAX}], not {iterations}")
        options.iterations = int(iterations)
    if tolerance is not None:
        options.tolerance = float(tolerance)
    keep = _set_boundary(options, boundary)
    options.distribution = _code(distribution, _DISTRIBUTIONS, "distribution")
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    # The library writes what fits; 2^20 energies (8 MiB) rather than a buffer sized by a huge
    # iteration limit that the tolerance ends long before.
    history = np.empty(min(options.iterations + 1, 1 << 20), dtype=np.float64)
    report = L.UvfBoundaryOptimizationReport()
    lib = L.library()
    bridge.run(
        lambda: lib.uvf_boundary_optimized_map(
            _f64p(p), len(p), _u32p(t), len(t), byref(options), _f64p(uv), _f64p(history), len(history), byref(report)
        )
    )
    del keep
    result = _from_struct(BoundaryOptimizationReport, report)
    return uv, history[: min(result.history_length, len(history))].copy(), result


class BoundaryEditor:
    """Real-time boundary editing (Desbrun et al. 2002 §4.2, ``uvf_boundary_editor_*``): the
    intrinsic map ``lambda_·conformal + mu·authalic`` is factored once; :meth:`solve` then
    returns the whole map for new boundary positions in milliseconds. Solves on one editor may
    run concurrently from several threads.

    Example::

        editor = uvflat.BoundaryEditor(positions, triangles, lambda_=1.0, mu=0.0)
        ring = editor.boundary                      # boundary vertices, solve() order
        angle = np.linspace(0, 2 * np.pi, len(ring), endpoint=False)
        uv = editor.solve(np.c_[np.cos(angle), np.sin(angle)])

    Raises (constructor): InvalidArgument, InvalidMesh, UnsupportedTopology (not a disk),
    NumericalFailure, Cancelled.
    """

    def __init__(
        self,
        positions: ArrayLike,
        triangles: ArrayLike,
        lambda_: float = 1.0,
        mu: float = 0.0,
        progress: Optional[ProgressCallback] = None,
    ) -> None:
        p, t = _mesh_arrays(positions, triangles)
        self._vertex_count = len(p)
        # solve() and basis() run without the GIL; close() must not free the handle under them.
        self._lock = threading.Lock()
        self._lib = L.library()
        options = L.UvfIntrinsicToolOptions()
        self._lib.uvf_intrinsic_tool_options_default(byref(options))
        bridge = _ProgressBridge(progress)
        options.progress = bridge.c_function
        self._handle = POINTER(L.UvfBoundaryEditor)()
        bridge.run(
            lambda: self._lib.uvf_boundary_editor_new(
                _f64p(p), len(p), _u32p(t), len(t), float(lambda_), float(mu), byref(options), byref(self._handle)
            )
        )
        count = ctypes.c_size_t()
        _check(self._lib.uvf_boundary_editor_boundary(self._handle, byref(count), None))
        #: Boundary vertices in the order :meth:`solve` expects their UVs.
        self.boundary = np.empty(count.value, dtype=np.uint32)
        _check(self._lib.uvf_boundary_editor_boundary(self._handle, byref(count), _u32p(self.boundary)))

    def solve(self, boundary_uv: ArrayLike) -> np.ndarray:
        """``(n, 2)`` UVs of every vertex for the ``(b, 2)`` boundary positions (in
        :attr:`boundary` order); NaN for unreferenced vertices."""
        b = np.ascontiguousarray(boundary_uv, dtype=np.float64)
        if b.shape != (len(self.boundary), 2):
            raise InvalidArgument(f"boundary_uv must have shape ({len(self.boundary)}, 2), not {b.shape}")
        uv = np.empty((self._vertex_count, 2), dtype=np.float64)
        with self._lock:
            _check(self._lib.uvf_boundary_editor_solve(self._handle, _f64p(b), len(b), _f64p(uv)))
        return uv

    def basis(self, max_bytes: int = 1 << 30) -> np.ndarray:
        """The Green-function basis as a ``(b, n)`` array: ``uv = basis.T @ boundary_uv``.
        Costs 8·n·b bytes; refused with InvalidArgument above ``max_bytes`` (default 1 GiB)."""
        needed = 8 * len(self.boundary) * self._vertex_count
        if needed > max_bytes:
            raise InvalidArgument(f"the basis needs {needed} bytes, more than max_bytes = {max_bytes}")
        out = np.empty((len(self.boundary), self._vertex_count), dtype=np.float64)
        with self._lock:
            _check(self._lib.uvf_boundary_editor_basis(self._handle, int(max_bytes), _f64p(out)))
        return out

    def close(self) -> None:
        """Frees the factorization now (also done when the editor is garbage-collected); waits
        for a :meth:`solve` running in another thread. Later solves raise InvalidArgument."""
        lock = getattr(self, "_lock", None)
        if lock is None:
            return
        with lock:
            if getattr(self, "_handle", None):
                self._lib.uvf_boundary_editor_free(self._handle)
                self._handle = None

    def __enter__(self) -> "BoundaryEditor":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def __del__(self) -> None:
        self.close()
