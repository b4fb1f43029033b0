"""The contact problem of :func:`~skisnow.contact.solve_contact`, validated and set up once.

:func:`build_problem` checks the arguments (messages name the argument and what would be valid),
lays out the grid — stations along the ski, for the surface model also cells across it and the
footprint of the ski's outline w(x) — and builds the half-space operator (cached: a sweep reuses
the same few grids). The result is a frozen :class:`ContactProblem`: everything the starts and
the Polonsky–Keer iteration need, on the flat vector of the footprint cells.

Conventions (Kalliorinne et al. 2023, §3.2 and eq. 3): x positive toward the tip, ξ = x − x_m
the lever arm about the load point x_m, the load W = m·g₀ carried as Σp·ΔA, so the iteration's
constraint is Σp = W/ΔA over the cells.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from skisnow._checks import positive_finite
from skisnow._errors import InputError
from skisnow.contact._kernels import (
    Convolution,
    line_convolution,
    strip_convolution,
    surface_convolution,
)
from skisnow.contact._operators import CellOperator

__all__ = ["DEFAULT_WIDTH", "ContactProblem", "build_problem"]

Model = Literal["strip", "surface", "line"]
Control = Literal["moment", "load", "displacement"]

#: Default ski width [m] (the paper's skis are about 44 mm wide under the foot).
DEFAULT_WIDTH = 0.044


@dataclass(frozen=True, kw_only=True, eq=False)
class ContactProblem:
    """One rigid-profile / half-space contact problem on its grid (SI units).

    Attributes
    ----------
    x, y, dx
        Cell centres along [m], across [m] (surface model; else None) and the cell length [m].
    height
        Rigid profile h on the grid [m], shape ``(nx,)`` or ``(nx, ny)``.
    two_d_height
        Whether the caller gave a 2D height (then ``y`` is the caller's grid).
    footprint
        Boolean grid mask of the cells inside the ski's outline.
    cells
        Flat indices of the footprint cells, or None when the footprint is the whole grid.
    h, arm
        h and the lever arm ξ = x − x_m on the footprint cells (flat vectors).
    arm_grid
        ξ on the grid (a broadcast view).
    conv
        The half-space operator of the model on the grid.
    model, control
        'strip' | 'surface' | 'line' and 'moment' | 'load' | 'displacement'.
    load, load_position, modulus, width, cell_area
        W [N] (None under displacement control), x_m [m] as given (None if not), E' [Pa], the
        ski width [m] (a number, or an array over x for a varying outline) and ΔA [m²].
    translation, rotation
        δ [m] and θ [rad] for displacement control (else None and 0).
    reference_length, workers
        As given to :func:`build_problem` (the multilevel start builds coarser problems).
    """

    x: np.ndarray
    y: np.ndarray | None
    dx: float
    height: np.ndarray
    two_d_height: bool
    footprint: np.ndarray = field(repr=False)
    cells: np.ndarray | None = field(repr=False)
    h: np.ndarray = field(repr=False)
    arm: np.ndarray = field(repr=False)
    arm_grid: np.ndarray = field(repr=False)
    conv: Convolution = field(repr=False)
    model: Model
    control: Control
    load: float | None
    load_position: float | None
    modulus: float
    width: float | np.ndarray
    cell_area: float
    translation: float | None
    rotation: float
    reference_length: float
    workers: int | None

    @property
    def xm(self) -> float:
        """x_m [m] (0 when no load position was given: the rotation centre of displacement
        control)."""
        return 0.0 if self.load_position is None else float(self.load_position)

    @property
    def total(self) -> float | None:
        """Σp over the cells that carries the load [Pa] (W/ΔA), None under displacement control."""
        return None if self.load is None else self.load / self.cell_area

    @property
    def moment(self) -> bool:
        """Moment balance (the paper's eq. 3) is imposed."""
        return self.control == "moment"

    @property
    def dims(self) -> int:
        """Dimensions of the contact area (2 for the surface model, else 1)."""
        return 2 if self.model == "surface" else 1

    @property
    def target(self) -> np.ndarray | None:
        """δ + θξ on the cells under displacement control."""
        if self.control != "displacement":
            return None
        return float(self.translation) + float(self.rotation) * self.arm  # type: ignore[arg-type]

    @property
    def operator(self) -> CellOperator:
        """K on the flat footprint cells."""
        return CellOperator(self.conv, self.cells)

    def on_cells(self, grid: np.ndarray) -> np.ndarray:
        """A grid field's values on the footprint cells (flat)."""
        return grid.ravel() if self.cells is None else grid.ravel()[self.cells]

    def to_grid(self, values: np.ndarray) -> np.ndarray:
        """A flat cell vector on the grid (zero off the footprint)."""
        if self.cells is None:
            return values.reshape(self.height.shape)
        out = np.zeros(self.height.size)
        out[self.cells] = values
        return out.reshape(self.height.shape)


def build_problem(
    x: ArrayLike,
    height: ArrayLike,
    *,
    load: float | None,
    load_position: float | None,
    modulus: float,
    model: str,
    control: str,
    width: float | ArrayLike | Callable[[np.ndarray], np.ndarray] | None,
    y: ArrayLike | None,
    n_across: int,
    translation: float | None,
    rotation: float,
    reference_length: float,
    workers: int | None,
) -> ContactProblem:
    """Validate the arguments of :func:`~skisnow.contact.solve_contact` (same names) and set up
    the grid, the footprint and the operator; raises :class:`~skisnow.InputError`."""
    if model not in ("strip", "surface", "line"):
        raise InputError(f"model must be 'strip', 'surface' or 'line', got {model!r}")
    if control not in ("moment", "load", "displacement"):
        raise InputError(f"control must be 'moment', 'load' or 'displacement', got {control!r}")
    x, dx = _uniform_grid("x", x)
    h = np.asarray(height, dtype=np.float64)
    two_d = h.ndim == 2
    modulus = positive_finite("modulus (E')", modulus, "Pa")
    if control in ("moment", "load"):
        if load is None:
            raise InputError(f"control={control!r} needs load= (the normal force in N)")
        load = positive_finite("load", load, "N")
    if control == "moment" and load_position is None:
        raise InputError("control='moment' needs load_position= (x_m in m)")
    if control == "displacement":
        if translation is None or not np.isfinite(translation):
            raise InputError("control='displacement' needs a finite translation= (δ in m)")
        if not np.isfinite(rotation):
            raise InputError(f"rotation must be finite, got {rotation!r}")
    xm = 0.0 if load_position is None else float(load_position)
    if not np.isfinite(xm):
        raise InputError(f"load_position must be finite, got {load_position!r}")
    if load_position is not None and not (x[0] <= xm <= x[-1]):
        raise InputError(
            f"load position x_m = {xm * 1e3:.1f} mm lies outside the profile "
            f"[{x[0] * 1e3:.1f}, {x[-1] * 1e3:.1f}] mm"
        )
    if model == "surface":
        h, yy, footprint, conv, cell_area, width_out = _surface_grid(
            x, dx, h, y, width, n_across, modulus, workers
        )
        y_out: np.ndarray | None = yy
    else:
        if h.shape != x.shape:
            raise InputError(f"height has shape {h.shape}; x has shape {x.shape} (must match)")
        if width is None:
            w = DEFAULT_WIDTH
        elif callable(width) or np.ndim(width) != 0:
            raise InputError(
                f"model={model!r} needs a constant width (a number); use model='surface' "
                "for a width profile w(x)"
            )
        else:
            w = positive_finite("width", width, "m")  # type: ignore[arg-type]
        footprint = np.ones(x.shape, dtype=bool)
        extra = w if model == "strip" else float(reference_length)
        conv = _operator(model, (x.size,), dx, 0.0, modulus, extra, workers)
        cell_area = dx * w
        width_out = w
        y_out = None
    if not np.all(np.isfinite(h)):
        bad = np.argwhere(~np.isfinite(h))[0]
        raise InputError(f"height has a non-finite value (NaN or inf) at index {tuple(bad)}")
    cells = None if footprint.all() else np.flatnonzero(footprint.ravel())
    arm_grid = np.broadcast_to((x - xm)[:, None] if h.ndim == 2 else x - xm, h.shape)
    on_cells = (lambda a: a.ravel()) if cells is None else (lambda a: a.ravel()[cells])
    return ContactProblem(
        x=x,
        y=y_out,
        dx=dx,
        height=h,
        two_d_height=two_d,
        footprint=footprint,
        cells=cells,
        h=on_cells(h),
        arm=on_cells(arm_grid),
        arm_grid=arm_grid,
        conv=conv,
        model=model,  # type: ignore[arg-type]
        control=control,  # type: ignore[arg-type]
        load=load,
        load_position=None if load_position is None else xm,
        modulus=modulus,
        width=width_out,
        cell_area=cell_area,
        translation=None if translation is None else float(translation),
        rotation=float(rotation),
        reference_length=float(reference_length),
        workers=workers,
    )


def _surface_grid(
    x: np.ndarray,
    dx: float,
    h: np.ndarray,
    y: ArrayLike | None,
    width: float | ArrayLike | Callable[[np.ndarray], np.ndarray] | None,
    n_across: int,
    modulus: float,
    workers: int | None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, Convolution, float, float | np.ndarray]:
    """The surface model's grid: (h on the grid, y, footprint, operator, ΔA, width)."""
    if h.ndim == 2:
        if y is None:
            raise InputError("a 2D height needs y= (cell centres across, m)")
        yy, dy = _uniform_grid("y", y)
        if h.shape != (x.size, yy.size):
            raise InputError(
                f"height has shape {h.shape}, but x and y give a grid of ({x.size}, {yy.size})"
            )
        full_width = np.full(x.size, yy[-1] - yy[0] + dy)
        wx = full_width if width is None else _width_profile(width, x)
    elif h.ndim == 1:
        wx = _width_profile(DEFAULT_WIDTH if width is None else width, x)
        n_across = int(n_across)
        if n_across < 1:
            raise InputError(f"n_across must be ≥ 1, got {n_across}")
        wmax = float(wx.max())
        dy = wmax / n_across
        yy = (np.arange(n_across) + 0.5) * dy - wmax / 2
        if h.shape != x.shape:
            raise InputError(f"height has shape {h.shape}; x has shape {x.shape}")
        h = np.repeat(h[:, None], n_across, axis=1)
    else:
        raise InputError(f"height must be 1D or 2D, got shape {h.shape}")
    footprint = np.abs(yy)[None, :] <= wx[:, None] / 2 + 1e-9 * dy
    if not footprint.any(axis=1).all():
        raise InputError("the width profile leaves stations without any cell; refine n_across")
    conv = _operator("surface", (x.size, yy.size), dx, dy, modulus, 0.0, workers)
    width_out: float | np.ndarray = wx if not np.allclose(wx, wx[0]) else float(wx[0])
    return h, yy, footprint, conv, dx * dy, width_out


@functools.lru_cache(maxsize=8)
def _operator(
    model: str,
    shape: tuple[int, ...],
    dx: float,
    dy: float,
    modulus: float,
    extra: float,
    workers: int | None,
) -> Convolution:
    """The half-space operator of a model on a grid, cached (sweeps reuse the same few grids)."""
    if model == "surface":
        return surface_convolution(shape, dx, dy, modulus=modulus, workers=workers)  # type: ignore[arg-type]
    if model == "strip":
        return strip_convolution(shape[0], dx, extra, modulus=modulus, workers=workers)
    return line_convolution(shape[0], dx, modulus=modulus, reference_length=extra, workers=workers)


def _uniform_grid(name: str, x: ArrayLike) -> tuple[np.ndarray, float]:
    x = np.asarray(x, dtype=np.float64)
    if x.ndim != 1 or x.size < 2:
        raise InputError(f"{name} must be a 1D array of at least 2 stations, got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        bad = int(np.flatnonzero(~np.isfinite(x))[0])
        raise InputError(f"{name} has a non-finite value at index {bad}")
    d = np.diff(x)
    dx = float(d.mean())
    if dx <= 0 or np.max(np.abs(d - dx)) > 1e-6 * abs(dx):
        raise InputError(
            f"{name} must be uniformly spaced and increasing (the FFT half-space needs a regular "
            f"grid); spacing varies from {d.min():.6g} to {d.max():.6g} m — resample the profile"
        )
    return x, dx


def _width_profile(
    width: float | ArrayLike | Callable[[np.ndarray], np.ndarray], x: np.ndarray
) -> np.ndarray:
    w = width(x) if callable(width) else width
    w = np.broadcast_to(np.asarray(w, dtype=np.float64), x.shape) if np.ndim(w) == 0 else w
    w = np.asarray(w, dtype=np.float64)
    if w.shape != x.shape:
        raise InputError(f"width profile has shape {w.shape}; x has shape {x.shape}")
    if not np.all(np.isfinite(w)) or np.any(w <= 0):
        raise InputError("width must be finite and positive at every station")
    return w.copy()
