"""Exceptions: one :class:`Error` subclass per ``UvfStatus`` failure code."""

from __future__ import annotations

import enum
from typing import Dict, Optional, Type


class Status(enum.IntEnum):
    """``enum UvfStatus`` of ``uvflat.h``."""

    OK = 0
    INVALID_ARGUMENT = 1
    INVALID_MESH = 2
    UNSUPPORTED_TOPOLOGY = 3
    NUMERICAL_FAILURE = 4
    CANCELLED = 5
    NOT_IMPLEMENTED = 6
    INTERNAL_ERROR = 7
    IO_ERROR = 8


class Error(Exception):
    """Base class of every uvflat failure.

    ``status`` is the :class:`Status` the C library returned (``None`` for
    :class:`LibraryError`, which is not a library call's failure), ``message`` the library's
    text (``uvf_last_error_message()``), which names the offending element, e.g.
    ``"triangle 128 references vertex 85 but the mesh has 81 vertices"``.
    """

    #: The status code this class stands for.
    default_status: Optional[Status] = None

    def __init__(self, message: str, status: Optional[int] = None) -> None:
        super().__init__(message)
        self.message = message
        self.status: Optional[Status] = Status(status) if status is not None else self.default_status


class InvalidArgument(Error, ValueError):
    """A pointer, count, option or index given by the caller is invalid (``UVF_INVALID_ARGUMENT``)."""

    default_status = Status.INVALID_ARGUMENT


class InvalidMesh(Error, ValueError):
    """Bad index, non-finite coordinate, degenerate/duplicate/non-manifold triangle, inconsistent
    orientation or no triangles (``UVF_INVALID_MESH``)."""

    default_status = Status.INVALID_MESH


class UnsupportedTopology(Error):
    """A valid mesh whose topology does not suit the method, e.g. not a disk
    (``UVF_UNSUPPORTED_TOPOLOGY``)."""

    default_status = Status.UNSUPPORTED_TOPOLOGY


class NumericalFailure(Error, ArithmeticError):
    """The linear system or optimisation failed numerically (``UVF_NUMERICAL_FAILURE``)."""

    default_status = Status.NUMERICAL_FAILURE


class Cancelled(Error):
    """The progress callback asked to stop (``UVF_CANCELLED``)."""

    default_status = Status.CANCELLED


class NotImplemented(Error, NotImplementedError):  # noqa: A001 - mirrors UVF_NOT_IMPLEMENTED
    """The method exists in the API but is not implemented yet (``UVF_NOT_IMPLEMENTED``)."""

    default_status = Status.NOT_IMPLEMENTED


class InternalError(Error, RuntimeError):
    """A bug in uvflat (a caught panic) or an allocation failure (``UVF_INTERNAL_ERROR``)."""

    default_status = Status.INTERNAL_ERROR


class IoError(Error, OSError):
    """Reading or writing a file failed (``UVF_IO_ERROR``)."""

    default_status = Status.IO_ERROR


class LibraryError(Error, OSError):
    """``libuvflat`` cannot be found or loaded, lacks a function, or has another ABI version."""


#: Status code -> exception class.
ERROR_CLASSES: Dict[Status, Type[Error]] = {
    Status.INVALID_ARGUMENT: InvalidArgument,
    Status.INVALID_MESH: InvalidMesh,
    Status.UNSUPPORTED_TOPOLOGY: UnsupportedTopology,
    Status.NUMERICAL_FAILURE: NumericalFailure,
    Status.CANCELLED: Cancelled,
    Status.NOT_IMPLEMENTED: NotImplemented,
    Status.INTERNAL_ERROR: InternalError,
    Status.IO_ERROR: IoError,
}


def error_for_status(status: int, message: str) -> Error:
    """The exception for a non-zero ``UvfStatus``; unknown codes become :class:`InternalError`."""
    try:
        known = Status(status)
    except ValueError:
        return InternalError(f"unknown uvflat status {status}: {message}", Status.INTERNAL_ERROR)
    cls = ERROR_CLASSES.get(known)
    if cls is None:  # Status.OK is not an error
        raise ValueError("UVF_OK is not an error status")
    return cls(message, known)
