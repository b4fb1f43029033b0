"""The error hierarchy of skisnow.

Every error skisnow raises on purpose derives from :class:`SkisnowError`; the specific ones also
derive from the builtin they refine, so ``except ValueError`` keeps working for callers who do not
know skisnow (the pattern of pint's errors). Messages say what was wrong, where (file, row,
column, argument) and what would be valid.
"""

from __future__ import annotations

import enum


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


class SolverStatus(enum.Enum):
    """How an iterative solver ended: the status every solver result carries.

    Modelled on optimistix's ``RESULTS`` (Kidger, ``optimistix/_solution.py``): one enumeration
    shared by all solvers, each member with a message; a result is usable when its status is
    :attr:`SUCCESSFUL` (``status.successful``), and callers who want an exception ask for one
    (``raise_on_failure=True`` raises :class:`ConvergenceError` carrying the result).
    """

    #: converged to the tolerance (or found the exact answer)
    SUCCESSFUL = "successful"
    #: the iteration limit was reached before the tolerance
    MAX_STEPS_REACHED = "max_steps_reached"
    #: a NaN or an infinity appeared in the iteration
    NONFINITE = "nonfinite"
    #: the iteration broke down (a search direction lost positivity: an ill-conditioned operator)
    BREAKDOWN = "breakdown"
    #: the contact set vanished under load or moment control
    CONTACT_LOST = "contact_lost"
    #: the constraints cannot be met on the contact set (it cannot carry the load and the moment)
    INFEASIBLE = "infeasible"

    @property
    def successful(self) -> bool:
        """True for :attr:`SUCCESSFUL`."""
        return self is SolverStatus.SUCCESSFUL

    @property
    def message(self) -> str:
        """A one-line explanation of the status."""
        return _STATUS_MESSAGES[self]


_STATUS_MESSAGES = {
    SolverStatus.SUCCESSFUL: "converged",
    SolverStatus.MAX_STEPS_REACHED: "maximum number of iterations reached",
    SolverStatus.NONFINITE: "non-finite values (NaN or inf) in the iteration",
    SolverStatus.BREAKDOWN: "search direction lost positivity (ill-conditioned operator)",
    SolverStatus.CONTACT_LOST: "the contact set vanished",
    SolverStatus.INFEASIBLE: "the contact set cannot carry the load and the moment",
}


class ConvergenceError(RuntimeError, SkisnowError):
    """An iterative solver did not reach its tolerance.

    Raised only on request (solvers return a result with a :class:`SolverStatus` otherwise).
    The error always carries ``.result``, the partial result (``None`` only where a solver has
    nothing partial to return, e.g. a failed library fit), and ``.status``, the result's
    :class:`SolverStatus` when it has one.
    """

    def __init__(self, message: str, *, result: object | None) -> None:
        super().__init__(message)
        self.result = result
        status = getattr(result, "status", None)
        self.status: SolverStatus | None = status if isinstance(status, SolverStatus) else None


class DomainWarning(UserWarning):
    """A model is used outside the range in which it was fitted or is valid."""
