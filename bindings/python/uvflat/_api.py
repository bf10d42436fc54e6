"""The Pythonic layer: numpy arrays in and out, keyword options, exceptions.

Conventions (as in ``uvflat.h``): ``positions`` is an ``(n, 3)`` array of vertex positions,
``triangles`` an ``(m, 3)`` array of vertex indices (counter-clockwise), UVs come back as an
``(n, 2)`` float64 array with one row per vertex, NaN for vertices no triangle uses.

Inputs may be anything ``numpy.asarray`` accepts. They are handed to the library without a
copy when they already are C-contiguous, aligned float64 (positions, UVs) or uint32
(triangles); otherwise a converted copy is made. Integer triangle arrays of another type are
range-checked first, so a negative index or one that does not fit in 32 bits is reported, not
wrapped around.
"""

from __future__ import annotations

import ctypes
import dataclasses
from ctypes import POINTER, byref, c_double, c_uint32
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _library as L
from ._errors import Error, InvalidArgument, InvalidMesh, error_for_status

ArrayLike = Any
#: A progress callback: receives the fraction done in [0, 1]; returning ``False`` cancels.
ProgressCallback = Callable[[float], Optional[bool]]
#: Two pins: ``((vertex0, (u0, v0)), (vertex1, (u1, v1)))``.
Pins = Tuple[Tuple[int, Tuple[float, float]], Tuple[int, Tuple[float, float]]]

_U32_MAX = np.iinfo(np.uint32).max


# --- results --------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class MeshInfo:
    """Counts and topological invariants of a mesh (``UvfMeshInfo``)."""

    #: Vertices in the input arrays (including unreferenced ones).
    vertices: int
    #: Vertices used by at least one triangle.
    referenced_vertices: int
    #: Triangles.
    triangles: int
    #: Undirected edges.
    edges: int
    #: Connected components.
    components: int
    #: Boundary loops.
    boundary_loops: int
    #: Total number of vertices over all boundary loops.
    boundary_vertices: int
    #: Euler characteristic V − E + F.
    euler_characteristic: int
    #: Total genus.
    genus: int


@dataclasses.dataclass(frozen=True)
class Metrics:
    """Distortion summary of a UV map (``UvfMetrics``); distortion fields are NaN when no
    triangle is measurable. Angles are in radians."""

    #: Number of triangles measured.
    triangles: int
    #: Triangles whose UV orientation is opposite to the layout's majority orientation.
    flipped: int
    #: Triangles with (numerically) zero UV area, left out of every distortion figure.
    degenerate_uv: int
    #: Proper crossings between UV boundary edges.
    boundary_intersections: int
    #: Sander et al. 2001 L2 stretch after a global scale; 1 is optimal.
    stretch_l2: float
    #: Sander et al. 2001 L∞ stretch after the same scale.
    stretch_linf: float
    #: Area-weighted mean of σmax/σmin; 1 is conformal.
    conformal_mean: float
    #: Largest σmax/σmin.
    conformal_max: float
    #: Mean |UV corner angle − surface corner angle|, radians.
    angle_mean: float
    #: Largest corner angle error, radians.
    angle_max: float
    #: Area-weighted mean |ln(s·A_uv / A_3d)| with one global scale s; 0 is authalic.
    area_mean: float
    #: Largest |ln(s·A_uv / A_3d)|.
    area_max: float


def _from_struct(cls: type, struct: ctypes.Structure) -> Any:
    return cls(**{f.name: getattr(struct, f.name) for f in dataclasses.fields(cls)})


# --- calling --------------------------------------------------------------------------------


def _check(status: int) -> None:
    """Raises the exception for a failed call, with this thread's library message."""
    if status != 0:
        message = L.library().uvf_last_error_message()
        raise error_for_status(status, message.decode("utf-8", "replace") if message else "")


def version() -> str:
    """Version of the loaded library, e.g. ``"0.1.0"`` (``uvf_version()``)."""
    return L.library().uvf_version().decode("ascii")


def abi_version() -> int:
    """ABI version of the loaded library (``uvf_abi_version()``); equals :data:`ABI_VERSION`."""
    return int(L.library().uvf_abi_version())


# --- arrays ---------------------------------------------------------------------------------


def _f64p(a: np.ndarray) -> "ctypes._Pointer[c_double]":
    return a.ctypes.data_as(POINTER(c_double))


def _u32p(a: np.ndarray) -> "ctypes._Pointer[c_uint32]":
    return a.ctypes.data_as(POINTER(c_uint32))


def _as_points(a: ArrayLike, columns: int, what: str) -> np.ndarray:
    """A C-contiguous, aligned float64 ``(k, columns)`` array; copies only when needed."""
    array = np.asarray(a)
    if array.size == 0:
        array = array.reshape(0, columns)
    if array.ndim != 2 or array.shape[1] != columns:
        raise InvalidArgument(f"{what} must have shape (k, {columns}), not {array.shape}")
    if array.dtype.kind not in "fiu":
        raise InvalidArgument(f"{what} must hold real numbers, not {array.dtype}")
    return np.require(array, dtype=np.float64, requirements=["C", "A"])


def _as_indices(
    a: ArrayLike,
    what: str,
    error: type,
    columns: Optional[int] = 3,
    describe: str = "triangle {row} references vertex {value}, which {reason}",
) -> np.ndarray:
    """A C-contiguous, aligned uint32 array of shape ``(k, columns)`` (or ``(k,)`` when
    ``columns`` is None); copies only when needed. An index that is negative or does not fit in
    32 bits raises ``error`` with ``describe`` filled in for the first one."""
    array = np.asarray(a)
    if array.size == 0:
        array = array.reshape((0, columns) if columns else (0,))
    if array.ndim != (2 if columns else 1) or (columns and array.shape[1] != columns):
        shape = f"(k, {columns})" if columns else "(k,)"
        raise InvalidArgument(f"{what} must have shape {shape}, not {array.shape}")
    if array.dtype.kind not in "iu":
        raise InvalidArgument(f"{what} must hold integers, not {array.dtype}")
    if array.dtype != np.uint32 and array.size:
        bad = (array < 0) | (array > _U32_MAX)
        if bad.any():
            where = tuple(np.argwhere(bad)[0])
            value = int(array[where])
            reason = "is negative" if value < 0 else "does not fit in 32 bits"
            raise error(describe.format(row=where[0], value=value, reason=reason))
    return np.require(array, dtype=np.uint32, requirements=["C", "A"])


def _mesh_arrays(positions: ArrayLike, triangles: ArrayLike) -> Tuple[np.ndarray, np.ndarray]:
    return _as_points(positions, 3, "positions"), _as_indices(triangles, "triangles", InvalidMesh)


# --- progress -------------------------------------------------------------------------------


class _ProgressBridge:
    """Wraps a Python callable as a ``UvfProgressFn`` kept alive for one call.

    The callable receives the fraction done in [0, 1]. Returning ``False`` (or another falsy
    value other than ``None``) cancels; ``True`` or ``None`` continues. An exception raised by
    the callable also cancels, and :meth:`reraise` raises it again after the C call returned.
    """

    def __init__(self, callback: Optional[ProgressCallback]) -> None:
        if callback is not None and not callable(callback):
            raise InvalidArgument(f"progress must be callable or None, not {type(callback).__name__}")
        self.callback = callback
        self.exception: Optional[BaseException] = None
        # A NULL function pointer when there is no callback.
        self.c_function = L.UvfProgressFn(self._call) if callback is not None else L.UvfProgressFn()

    def _call(self, _user: Optional[int], fraction: float) -> int:
        if self.exception is not None:
            return 1
        try:
            keep_going = self.callback(fraction)  # type: ignore[misc]
        except BaseException as e:  # noqa: B902 - re-raised after the call, KeyboardInterrupt too
            self.exception = e
            return 1
        return 0 if keep_going is None or keep_going else 1

    def run(self, call: Callable[[], int]) -> None:
        """Runs the C call, then re-raises the callback's exception or checks the status."""
        status = call()
        if self.exception is not None:
            raise self.exception
        _check(status)


# --- topology -------------------------------------------------------------------------------


def mesh_info(positions: ArrayLike, triangles: ArrayLike) -> MeshInfo:
    """Validates a mesh and reports its counts and topology (``uvf_mesh_info``).

    Raises :class:`InvalidMesh` (naming the bad triangle, vertex or edge) or
    :class:`InvalidArgument`.
    """
    p, t = _mesh_arrays(positions, triangles)
    info = L.UvfMeshInfo()
    _check(L.library().uvf_mesh_info(_f64p(p), len(p), _u32p(t), len(t), byref(info)))
    return _from_struct(MeshInfo, info)


def boundary_loops(positions: ArrayLike, triangles: ArrayLike) -> List[np.ndarray]:
    """Ordered boundary loops, counter-clockwise with the surface on the left
    (``uvf_boundary_loops``): one uint32 array of vertex indices per loop."""
    p, t = _mesh_arrays(positions, triangles)
    info = mesh_info(p, t)
    vertices = np.empty(info.boundary_vertices, dtype=np.uint32)
    offsets = np.empty(info.boundary_loops + 1, dtype=np.uint32)
    _check(
        L.library().uvf_boundary_loops(
            _f64p(p), len(p), _u32p(t), len(t), _u32p(vertices), len(vertices), _u32p(offsets), len(offsets)
        )
    )
    return [vertices[offsets[k] : offsets[k + 1]] for k in range(info.boundary_loops)]


def triangle_components(positions: ArrayLike, triangles: ArrayLike) -> np.ndarray:
    """Connected component id (0-based) of every triangle, a uint32 array of length m
    (``uvf_triangle_components``)."""
    p, t = _mesh_arrays(positions, triangles)
    out = np.empty(len(t), dtype=np.uint32)
    _check(L.library().uvf_triangle_components(_f64p(p), len(p), _u32p(t), len(t), _u32p(out)))
    return out


# --- fixed-boundary maps --------------------------------------------------------------------

_WEIGHTS: Dict[str, int] = {
    "uniform": L.UVF_WEIGHTS_UNIFORM,
    "tutte": L.UVF_WEIGHTS_UNIFORM,
    "floater": L.UVF_WEIGHTS_FLOATER,
    "authalic": L.UVF_WEIGHTS_AUTHALIC,
    "wachspress": L.UVF_WEIGHTS_AUTHALIC,
    "conformal": L.UVF_WEIGHTS_CONFORMAL,
    "harmonic": L.UVF_WEIGHTS_CONFORMAL,
    "mean_value": L.UVF_WEIGHTS_MEAN_VALUE,
    "intrinsic": L.UVF_WEIGHTS_INTRINSIC,
}
_SHAPES: Dict[str, int] = {"circle": L.UVF_BOUNDARY_CIRCLE, "square": L.UVF_BOUNDARY_SQUARE}
_DISTRIBUTIONS: Dict[str, int] = {
    "uniform": L.UVF_DISTRIBUTION_UNIFORM,
    "chord": L.UVF_DISTRIBUTION_CHORD,
    "centripetal": L.UVF_DISTRIBUTION_CENTRIPETAL,
}

Weights = Union[str, int]
Boundary = Union[str, int, Mapping[int, Sequence[float]], Tuple[ArrayLike, ArrayLike]]


def _code(value: Union[str, int], table: Dict[str, int], what: str) -> int:
    """A ``UVF_*`` code from a name (``"mean_value"``, ``"mean-value"``) or the code itself.
    Unknown integers are passed on for the library to reject."""
    if isinstance(value, str):
        key = value.strip().lower().replace("-", "_").replace(" ", "_")
        if key not in table:
            names = ", ".join(sorted(set(table)))
            raise InvalidArgument(f"unknown {what} {value!r}; use one of {names}")
        return table[key]
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool) and 0 <= int(value) <= _U32_MAX:
        return int(value)
    raise InvalidArgument(f"{what} must be a name or a UVF_* code, not {value!r}")


def _given_boundary(boundary: Any) -> Tuple[np.ndarray, np.ndarray]:
    """(vertices uint32 (k,), uv float64 (k, 2)) from a mapping or a (vertices, uv) pair."""
    if isinstance(boundary, Mapping):
        vertices: Any = list(boundary.keys())
        uv: Any = [boundary[v] for v in vertices]
    elif isinstance(boundary, tuple) and len(boundary) == 2:
        vertices, uv = boundary
    else:
        raise InvalidArgument(
            "boundary must be 'circle', 'square', a mapping {vertex: (u, v)} or a pair "
            f"(vertices, uv), not {type(boundary).__name__}"
        )
    v = _as_indices(
        vertices, "boundary vertices", InvalidArgument, None, "boundary vertex {value} (entry {row}) {reason}"
    )
    q = _as_points(uv, 2, "boundary uv")
    if len(v) != len(q):
        raise InvalidArgument(f"boundary has {len(v)} vertices but {len(q)} uv pairs")
    return v, q


def fixed_boundary_map(
    positions: ArrayLike,
    triangles: ArrayLike,
    *,
    weights: Weights = "mean_value",
    boundary: Boundary = "circle",
    distribution: Union[str, int] = "chord",
    lambda_: Optional[float] = None,
    mu: Optional[float] = None,
    progress: Optional[ProgressCallback] = None,
) -> np.ndarray:
    """Fixed-boundary barycentric map (``uvf_fixed_boundary_map``; course notes ch. 2,
    Desbrun et al. 2002 §3–4.1).

    The longest boundary loop is placed on ``boundary`` and every interior vertex is the
    weighted average of its neighbours; other loops are holes.

    Args:
        positions: ``(n, 3)`` vertex positions.
        triangles: ``(m, 3)`` vertex indices, counter-clockwise.
        weights: ``"uniform"`` (Tutte; alias ``"tutte"``), ``"floater"``, ``"authalic"``
            (DAP = Wachspress), ``"conformal"`` (DCP = discrete harmonic), ``"mean_value"``
            (default) or ``"intrinsic"`` (λ·DCP + μ·DAP), or a ``UVF_WEIGHTS_*`` code.
        boundary: ``"circle"`` (centre (0.5, 0.5), radius 0.5; default), ``"square"`` (the unit
            square), or given positions: a mapping ``{vertex: (u, v)}`` or a pair
            ``(vertices, uv)`` with ``uv`` of shape ``(k, 2)``; they must cover whole loops.
        distribution: spacing along a circle or square: ``"uniform"``, ``"chord"`` (default)
            or ``"centripetal"``.
        lambda_, mu: λ and μ of ``weights="intrinsic"`` (defaults 1 and 0); an error with
            other weights.
        progress: optional ``callable(fraction) -> bool | None``; see :func:`natural_conformal_map`.

    Returns:
        ``(n, 2)`` float64 UVs, NaN for unreferenced vertices.

    Raises:
        InvalidArgument, InvalidMesh, UnsupportedTopology (not a single genus-0 component
        with a boundary), NumericalFailure, Cancelled, InternalError; or whatever ``progress``
        raised.
    """
    p, t = _mesh_arrays(positions, triangles)
    options = L.UvfFixedBoundaryOptions()
    L.library().uvf_fixed_boundary_options_default(byref(options))
    options.weights = _code(weights, _WEIGHTS, "weights")
    if options.weights == L.UVF_WEIGHTS_INTRINSIC:
        options.lambda_ = 1.0 if lambda_ is None else float(lambda_)
        options.mu = 0.0 if mu is None else float(mu)
    elif lambda_ is not None or mu is not None:
        raise InvalidArgument(f"lambda_ and mu apply to weights='intrinsic' only, not {weights!r}")
    if isinstance(boundary, (str, int, np.integer)) and not isinstance(boundary, bool):
        options.boundary = _code(boundary, _SHAPES, "boundary")
        if options.boundary == L.UVF_BOUNDARY_GIVEN:
            raise InvalidArgument("give the boundary positions themselves (a mapping or (vertices, uv))")
        given_vertices, given_uv = None, None
    else:
        given_vertices, given_uv = _given_boundary(boundary)
        options.boundary = L.UVF_BOUNDARY_GIVEN
        options.given_count = len(given_vertices)
        options.given_vertices = _u32p(given_vertices)
        options.given_uv = _f64p(given_uv)
    options.distribution = _code(distribution, _DISTRIBUTIONS, "distribution")
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    lib = L.library()
    bridge.run(lambda: lib.uvf_fixed_boundary_map(_f64p(p), len(p), _u32p(t), len(t), byref(options), _f64p(uv)))
    del given_vertices, given_uv  # kept alive until here: `options` points into them
    return uv


def _named_weights(name: str, doc: str) -> Callable[..., np.ndarray]:
    def method(
        positions: ArrayLike,
        triangles: ArrayLike,
        *,
        boundary: Boundary = "circle",
        distribution: Union[str, int] = "chord",
        progress: Optional[ProgressCallback] = None,
    ) -> np.ndarray:
        return fixed_boundary_map(
            positions, triangles, weights=name, boundary=boundary, distribution=distribution, progress=progress
        )

    method.__name__ = method.__qualname__ = name if name != "uniform" else "tutte"
    method.__doc__ = (
        f"{doc}\n\n``fixed_boundary_map(positions, triangles, weights={name!r}, ...)``; "
        "returns ``(n, 2)`` float64 UVs (NaN for unreferenced vertices)."
    )
    return method


tutte = _named_weights("uniform", "Tutte's embedding: uniform weights (Tutte 1963); never flips with a convex boundary.")
floater = _named_weights("floater", "Floater's shape-preserving weights (1997); never flips with a convex boundary.")
authalic = _named_weights("authalic", "Discrete authalic map = Wachspress weights (Desbrun et al. 2002 eq. 6).")
conformal = _named_weights(
    "conformal", "Fixed-boundary discrete conformal map = discrete harmonic (Desbrun et al. 2002 eq. 4)."
)
mean_value = _named_weights("mean_value", "Floater's mean value weights (2003); never flips with a convex boundary.")


def intrinsic(
    positions: ArrayLike,
    triangles: ArrayLike,
    *,
    lambda_: float = 1.0,
    mu: float = 0.0,
    boundary: Boundary = "circle",
    distribution: Union[str, int] = "chord",
    progress: Optional[ProgressCallback] = None,
) -> np.ndarray:
    """Desbrun et al. 2002 §3.4 intrinsic map: weights λ·DCP + μ·DAP with a fixed boundary.

    ``fixed_boundary_map(positions, triangles, weights="intrinsic", lambda_=..., mu=..., ...)``;
    returns ``(n, 2)`` float64 UVs (NaN for unreferenced vertices).
    """
    return fixed_boundary_map(
        positions,
        triangles,
        weights="intrinsic",
        lambda_=lambda_,
        mu=mu,
        boundary=boundary,
        distribution=distribution,
        progress=progress,
    )


# --- natural conformal map ------------------------------------------------------------------


def natural_conformal_map(
    positions: ArrayLike,
    triangles: ArrayLike,
    *,
    pins: Optional[Pins] = None,
    progress: Optional[ProgressCallback] = None,
) -> np.ndarray:
    """Natural conformal map = LSCM (``uvf_natural_conformal_map``; Desbrun et al. 2002 §4.2
    eq. 7): free boundary, two pinned vertices.

    Args:
        positions: ``(n, 3)`` vertex positions.
        triangles: ``(m, 3)`` vertex indices, counter-clockwise.
        pins: ``None`` (default) pins the two boundary vertices farthest apart at (0, 0) and
            (d, 0), d their 3D distance; or ``((v0, (u0, v0_)), (v1, (u1, v1_)))``.
        progress: optional callable receiving the fraction done in [0, 1] (called from the
            calling thread, with the GIL held). Return ``True`` or ``None`` to go on,
            ``False`` to cancel (the call then raises :class:`Cancelled`). An exception
            raised by the callback cancels too and is re-raised once the library returns.

    Returns:
        ``(n, 2)`` float64 UVs, NaN for unreferenced vertices.

    Raises:
        InvalidArgument (bad pins), InvalidMesh, UnsupportedTopology, NumericalFailure,
        Cancelled, InternalError; or whatever ``progress`` raised.
    """
    p, t = _mesh_arrays(positions, triangles)
    options = L.UvfNaturalConformalOptions()
    L.library().uvf_natural_conformal_options_default(byref(options))
    if pins is not None:
        try:
            (v0, uv0), (v1, uv1) = pins
            vertices = [int(v0), int(v1)]
            uvs = [float(uv0[0]), float(uv0[1]), float(uv1[0]), float(uv1[1])]
            if len(uv0) != 2 or len(uv1) != 2:
                raise ValueError
        except (TypeError, ValueError, IndexError):
            raise InvalidArgument(f"pins must be ((vertex, (u, v)), (vertex, (u, v))), not {pins!r}") from None
        for v in vertices:
            if not 0 <= v <= _U32_MAX:
                raise InvalidArgument(f"pinned vertex {v} is not a vertex index")
        options.pin_count = 2
        options.pin_vertices[:] = vertices
        options.pin_uv[:] = uvs
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    lib = L.library()
    bridge.run(lambda: lib.uvf_natural_conformal_map(_f64p(p), len(p), _u32p(t), len(t), byref(options), _f64p(uv)))
    return uv


#: Alias: the natural conformal map is LSCM.
lscm = natural_conformal_map


# --- metrics --------------------------------------------------------------------------------


def metrics(
    positions: ArrayLike,
    triangles: ArrayLike,
    uv: ArrayLike,
    uv_triangles: Optional[ArrayLike] = None,
) -> Metrics:
    """Distortion of a UV map (``uvf_metrics``; course notes ch. 4, Sander et al. 2001).

    Args:
        positions: ``(n, 3)`` vertex positions.
        triangles: ``(m, 3)`` vertex indices.
        uv: ``(k, 2)`` UV coordinates; NaN rows that no triangle uses are fine.
        uv_triangles: ``(m, 3)`` indices into ``uv`` per triangle (per-corner UVs), or
            ``None`` when ``uv`` has one row per vertex (then ``k`` must equal ``n``).

    The mesh need not be manifold. Raises :class:`InvalidArgument` for mis-sized arrays,
    out-of-range indices, non-finite coordinates or no triangles.
    """
    p = _as_points(positions, 3, "positions")
    t = _as_indices(triangles, "triangles", InvalidArgument)
    q = _as_points(uv, 2, "uv")
    if uv_triangles is None:
        ut = None
    else:
        ut = _as_indices(
            uv_triangles, "uv_triangles", InvalidArgument, 3, "uv triangle {row} references uv {value}, which {reason}"
        )
        if len(ut) != len(t):
            raise InvalidArgument(f"uv_triangles has {len(ut)} rows but triangles has {len(t)}")
    out = L.UvfMetrics()
    _check(
        L.library().uvf_metrics(
            _f64p(p), len(p), _u32p(t), len(t), _f64p(q), len(q), None if ut is None else _u32p(ut), byref(out)
        )
    )
    return _from_struct(Metrics, out)


# --- more pins, non-linear methods, ABF, closed surfaces -----------------------------------


def pinned_natural_conformal_map(
    positions: ArrayLike,
    triangles: ArrayLike,
    pins: Mapping[int, Sequence[float]],
    *,
    progress: Optional[ProgressCallback] = None,
) -> np.ndarray:
    """Natural conformal map with two or more pinned vertices
    (``uvf_pinned_natural_conformal_map``; Desbrun et al. 2002 §4.1–4.2, pins as Lagrange
    point constraints): every pin lands exactly where given, the rest minimises the conformal
    energy.

    Args:
        positions: ``(n, 3)`` vertex positions.
        triangles: ``(m, 3)`` vertex indices, counter-clockwise.
        pins: ``{vertex: (u, v)}`` with at least two entries.
        progress: as for :func:`natural_conformal_map`.

    Returns:
        ``(n, 2)`` float64 UVs, NaN for unreferenced vertices.

    Raises:
        InvalidArgument (fewer than two pins, bad vertices, conflicting pins), InvalidMesh,
        UnsupportedTopology, NumericalFailure, Cancelled.
    """
    p, t = _mesh_arrays(positions, triangles)
    try:
        items = sorted((int(v), (float(uv[0]), float(uv[1]))) for v, uv in dict(pins).items())
    except (TypeError, ValueError, IndexError):
        raise InvalidArgument(f"pins must map vertex -> (u, v), not {pins!r}") from None
    vertices = _as_indices(np.array([v for v, _ in items], dtype=np.int64), "pin vertices", InvalidArgument, None,
                           "pin {row} is vertex {value}, which {reason}")
    uvs = np.ascontiguousarray([uv for _, uv in items], dtype=np.float64).reshape(-1, 2)
    options = L.UvfIntrinsicToolOptions()
    L.library().uvf_intrinsic_tool_options_default(byref(options))
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    lib = L.library()
    bridge.run(
        lambda: lib.uvf_pinned_natural_conformal_map(
            _f64p(p), len(p), _u32p(t), len(t), _u32p(vertices), _f64p(uvs), len(vertices), byref(options), _f64p(uv)
        )
    )
    return uv


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
    triangles: ArrayLike,
    method: Union[str, int] = "slim",
    *,
    iterations: Optional[int] = None,
    tolerance: Optional[float] = None,
    theta: Optional[float] = None,
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, NonlinearReport]:
    """Free-boundary distortion minimisation that never flips a triangle
    (``uvf_nonlinear_map``): ``slim`` (symmetric Dirichlet, Rabinovich et al. 2017), ``arap``
    (Liu et al. 2008), ``mips`` (Hormann & Greiner 2000), ``stretch`` (Sander et al. 2001),
    ``green_lagrange`` (Maillot et al. 1993), ``degener`` (Degener et al. 2003, ``theta``).

    Returns:
        ``(uv, report)``: ``(n, 2)`` UVs and a :class:`NonlinearReport`.
    """
    p, t = _mesh_arrays(positions, triangles)
    options = L.UvfNonlinearOptions()
    L.library().uvf_nonlinear_options_default(byref(options))
    options.method = _code(method, _NONLINEAR, "method")
    if iterations is not None:
        options.iterations = int(iterations)
    if tolerance is not None:
        options.tolerance = float(tolerance)
    if theta is not None:
        options.theta = float(theta)
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    report = L.UvfNonlinearReport()
    lib = L.library()
    bridge.run(lambda: lib.uvf_nonlinear_map(_f64p(p), len(p), _u32p(t), len(t), byref(options), _f64p(uv), byref(report)))
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
    triangles: ArrayLike,
    *,
    variant: str = "abf++",
    max_iterations: Optional[int] = None,
    tolerance: Optional[float] = None,
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, AbfReport]:
    """Angle based flattening (``uvf_abf``): ``"abf++"`` (Sheffer et al. 2005, default) or
    ``"abf"`` (Sheffer & de Sturler 2001), then the LSCM-style reconstruction of UVs.

    Returns:
        ``(uv, report)``: ``(n, 2)`` UVs and an :class:`AbfReport`.
    """
    p, t = _mesh_arrays(positions, triangles)
    options = L.UvfAbfOptions()
    L.library().uvf_abf_options_default(byref(options))
    options.variant = _code(variant, {"abf": L.UVF_ABF_VARIANT_ABF, "abf++": L.UVF_ABF_VARIANT_ABF_PLUS_PLUS}, "variant")
    if max_iterations is not None:
        options.max_iterations = int(max_iterations)
    if tolerance is not None:
        options.tolerance = float(tolerance)
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    report = L.UvfAbfReport()
    lib = L.library()
    bridge.run(lambda: lib.uvf_abf(_f64p(p), len(p), _u32p(t), len(t), byref(options), _f64p(uv), byref(report)))
    return uv, _from_struct(AbfReport, report)


def spherical_map(positions: ArrayLike, triangles: ArrayLike, method: str = "tutte_gnomonic") -> Tuple[np.ndarray, int]:
    """Spherical parameterization of a closed genus-0 mesh (``uvf_spherical_map``; course notes
    §6.1): ``tutte_gnomonic`` (flip-free construction, default), ``gauss_seidel`` or
    ``stereographic`` (Haker et al. 2000).

    Returns:
        ``(sphere, flipped)``: ``(n, 3)`` unit vectors and the count of flipped spherical
        triangles.
    """
    p, t = _mesh_arrays(positions, triangles)
    options = L.UvfSphereOptions()
    L.library().uvf_sphere_options_default(byref(options))
    options.method = _code(
        method,
        {
            "tutte_gnomonic": L.UVF_SPHERE_TUTTE_GNOMONIC,
            "gauss_seidel": L.UVF_SPHERE_GAUSS_SEIDEL,
            "stereographic": L.UVF_SPHERE_STEREOGRAPHIC,
        },
        "method",
    )
    out = np.empty((len(p), 3), dtype=np.float64)
    flipped = ctypes.c_size_t(0)
    _check(L.library().uvf_spherical_map(_f64p(p), len(p), _u32p(t), len(t), byref(options), _f64p(out), byref(flipped)))
    return out, int(flipped.value)


@dataclasses.dataclass(frozen=True)
class Cut:
    """A mesh cut into a topological disk (``uvf_cut_to_disk``)."""

    positions: np.ndarray  #: ``(k, 3)`` positions of the cut mesh's vertices
    triangles: np.ndarray  #: ``(m, 3)`` triangles of the cut mesh (same order as the input)
    original_vertices: np.ndarray  #: ``(k,)`` input vertex of each cut-mesh vertex
    edges: np.ndarray  #: ``(e, 2)`` input vertex pairs along the cut
    seam_length: float
    total_edge_length: float


def cut_to_disk(positions: ArrayLike, triangles: ArrayLike, cost: Union[str, ArrayLike] = "curvature") -> Cut:
    """Cuts a manifold mesh of any genus into a topological disk (``uvf_cut_to_disk``:
    tree-cotree cut graph, Erickson & Har-Peled 2002, steered by a ``curvature`` or ``length``
    edge cost, or by a caller-given ``(m, 3)`` array: the cost of half-edge ``k`` of triangle
    ``t`` (corner ``k`` to corner ``k + 1``), finite and ≥ 0, low cost attracting the cut); any
    disk method then runs on ``Cut.positions`` / ``Cut.triangles``."""
    p, t = _mesh_arrays(positions, triangles)
    options = L.UvfCutOptions()
    lib = L.library()
    lib.uvf_cut_options_default(byref(options))
    given = None
    if isinstance(cost, str):
        options.cost = _code(cost, {"curvature": L.UVF_CUT_COST_CURVATURE, "length": L.UVF_CUT_COST_LENGTH}, "cost")
    else:
        try:
            given = np.ascontiguousarray(cost, dtype=np.float64)
        except (TypeError, ValueError) as e:
            raise InvalidArgument(f"cost must be 'curvature', 'length' or an (m, 3) array of numbers: {e}") from None
        if given.shape != (len(t), 3):
            raise InvalidArgument(f"cost array has shape {given.shape}; expected ({len(t)}, 3), one per half-edge")
        options.cost = L.UVF_CUT_COST_GIVEN
        options.edge_cost = _f64p(given)
    handle = POINTER(L.UvfCut)()
    _check(lib.uvf_cut_to_disk(_f64p(p), len(p), _u32p(t), len(t), byref(options), byref(handle)))
    try:
        info = L.UvfCutInfo()
        _check(lib.uvf_cut_info(handle, byref(info)))
        cut_positions = np.empty((info.vertex_count, 3), dtype=np.float64)
        cut_triangles = np.empty((info.triangle_count, 3), dtype=np.uint32)
        original = np.empty(info.vertex_count, dtype=np.uint32)
        edges = np.empty((info.edge_count, 2), dtype=np.uint32)
        _check(lib.uvf_cut_copy_positions(handle, _f64p(cut_positions), cut_positions.size))
        _check(lib.uvf_cut_copy_triangles(handle, _u32p(cut_triangles), cut_triangles.size))
        _check(lib.uvf_cut_copy_original_vertices(handle, _u32p(original), original.size))
        _check(lib.uvf_cut_copy_edges(handle, _u32p(edges), edges.size))
    finally:
        lib.uvf_cut_free(handle)
    return Cut(cut_positions, cut_triangles, original, edges, info.seam_length, info.total_edge_length)
