"""Fixed-boundary (barycentric) maps: Tutte, Floater, authalic, discrete conformal, mean value and
intrinsic weights, with a circle, square or given boundary."""

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
from ._common import ArrayLike, Boundary, ProgressCallback, Weights, _DISTRIBUTIONS, _ProgressBridge, _SHAPES, _WEIGHTS, _code, _f64p, _given_boundary, _mesh_source, _on_mesh, _u32p


def fixed_boundary_map(
    positions: ArrayLike,
    triangles: Optional[ArrayLike] = None,
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
        positions: ``(n, 3)`` vertex positions, or a :class:`Mesh` (then no ``triangles``).
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
    p, t = _mesh_source(positions, triangles)
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
    bridge.run(lambda: _on_mesh(lib, "fixed_boundary_map", p, t, byref(options), _f64p(uv)))
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
