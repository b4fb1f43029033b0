"""The error hierarchy of skisnow.

Every error skisnow raises on purpose derives from :class:`SkisnowError`; the specific ones also
derive from the builtin they refine, so ``except ValueError`` keeps working for callers who do not
know skisnow (the pattern of pint's errors). Messages say what was wrong, where (file, row,
column, argument) and what would be valid.
"""

from __future__ import annotations


class SkisnowError(Exception):
    """Base class of all errors raised on purpose by skisnow."""


class InputError(ValueError, SkisnowError):
    """An argument or a value read from a file is invalid (NaN, out of range, wrong shape...)."""


class ImplausibleValueError(InputError):
    """A value is physically possible but implausible for a ski (often a unit slip: heights in
    metres in a millimetre column). The message says which unit was probably meant; the CLI's
    ``--allow-implausible`` (library: ``skisnow.allow_implausible()``) accepts it."""


class FileFormatError(InputError):
    """A file cannot be read: unknown format, corrupt, truncated, or failing validation.

    The message names the file and, where it applies, the row and column.
    """


class UnsupportedLoadError(InputError):
    """The load cannot be carried by the profile (e.g. the ski would tip over one of its ends)."""


class ConvergenceError(RuntimeError, SkisnowError):
    """An iterative solver did not reach its tolerance.

    Raised only on request (solvers return a result with ``converged=False`` otherwise). The
    partial result is attached as ``.result`` where one exists.
    """

    def __init__(self, message: str, result: object | None = None) -> None:
        super().__init__(message)
        self.result = result


class DomainWarning(UserWarning):
    """A model is used outside the range in which it was fitted or is valid."""
