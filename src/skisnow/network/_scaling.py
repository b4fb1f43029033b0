"""The camber network's units and range: input/output scaling, reference profile, trained domain.

As in MATLAB's ``mapminmax`` (the toolbox Kalliorinne et al. 2023 trained their network with,
§3.1), every input and the output are mapped linearly to [-1, 1] over the training data
(:class:`Scaling`); :class:`ReferenceProfile` is skisnow's x-only output reference (not in the
paper); :class:`Domain` is the trained (m, x_m, x) range that predictions are checked against.
Pure NumPy; SI units (x, x_m, h in metres, m in kg).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["Domain", "ReferenceProfile", "Scaling"]


def _minmax(lo: float, hi: float) -> tuple[float, float]:
    """Centre and half-range of MATLAB's ``mapminmax`` to [-1, 1] (half-range 1 if degenerate)."""
    half = 0.5 * (hi - lo)
    return 0.5 * (hi + lo), (half if half > 0 else 1.0)


@dataclass(frozen=True, kw_only=True)
class Scaling:
    """Affine maps to the network's [-1, 1] units: ``u = (v - centre) / half_range``.

    Computed from the training data as MATLAB's ``mapminmax`` does. Units: x, x_m, h in metres,
    m in kg.
    """

    x_center: float
    x_scale: float
    mass_center: float
    mass_scale: float
    position_center: float
    position_scale: float
    height_center: float
    height_scale: float

    @classmethod
    def from_data(
        cls, x: np.ndarray, mass: np.ndarray, position: np.ndarray, height: np.ndarray
    ) -> Scaling:
        xc, xs = _minmax(float(np.min(x)), float(np.max(x)))
        mc, ms = _minmax(float(np.min(mass)), float(np.max(mass)))
        pc, ps = _minmax(float(np.min(position)), float(np.max(position)))
        hc, hs = _minmax(float(np.min(height)), float(np.max(height)))
        return cls(
            x_center=xc,
            x_scale=xs,
            mass_center=mc,
            mass_scale=ms,
            position_center=pc,
            position_scale=ps,
            height_center=hc,
            height_scale=hs,
        )

    def scale_inputs(self, x: Any, mass: Any, position: Any) -> tuple[Any, Any, Any]:
        """(x, m, x_m) in SI → network units."""
        return (
            (x - self.x_center) / self.x_scale,
            (mass - self.mass_center) / self.mass_scale,
            (position - self.position_center) / self.position_scale,
        )

    def scale_height(self, height: Any) -> Any:
        """h [m] → network output units."""
        return (height - self.height_center) / self.height_scale

    def unscale_height(self, u: Any) -> Any:
        """Network output units → h [m]."""
        return u * self.height_scale + self.height_center


@dataclass(frozen=True, kw_only=True, eq=False)
class ReferenceProfile:
    """An x-only reference profile h_ref(x) [m] added to the network output (output scaling).

    Not in the paper: the bench heights span ~35 mm (the raised tip and tail) while the
    accuracy that matters is µm near contact, so the network learns ``h - h_ref(x)`` (where
    ``h_ref`` is the mean of the training profiles, tabulated on a uniform grid of
    ``height.size`` points over [x_min, x_max] and interpolated linearly) and the range it
    must resolve shrinks to the load-dependent part (a few mm). The block structure is
    unchanged; ``reference=None`` is the paper's plain network.

    ``mass_scaled=True`` (issue 30, fifth pass): ``h_ref`` is the *unloaded* profile h_0(x)
    (the bench's two lightest masses extrapolated to m = 0, :meth:`unloaded`) and the network
    learns the deflection per kilogram, ``(h - h_0(x)) / m``, so that h = h_0(x) + m·f(x, m,
    x_m). An Euler–Bernoulli beam on fixed supports deflects in proportion to its load, so
    between contact changes f does not depend on m: the product structure of the beam is built
    in rather than learned.
    """

    x_min: float
    x_max: float
    height: np.ndarray
    mass_scaled: bool = False

    @classmethod
    def mean_of_profiles(
        cls, x: np.ndarray, height: np.ndarray, condition: np.ndarray, *, n: int = 4001
    ) -> ReferenceProfile:
        """Mean over load conditions of each profile interpolated on ``n`` uniform points."""
        grid = np.linspace(float(np.min(x)), float(np.max(x)), n)
        acc = np.zeros(n)
        labels = np.unique(condition)
        for c in labels:
            rows = condition == c
            order = np.argsort(x[rows])
            acc += np.interp(grid, x[rows][order], height[rows][order])
        return cls(x_min=float(grid[0]), x_max=float(grid[-1]), height=acc / labels.size)

    @classmethod
    def unloaded(
        cls,
        x: np.ndarray,
        mass: np.ndarray,
        position: np.ndarray,
        height: np.ndarray,
        *,
        n: int = 4001,
    ) -> ReferenceProfile:
        """The unloaded profile h_0(x), ``mass_scaled``: at every load position, the profiles
        of the two lightest bench masses m_1 < m_2 extrapolated linearly to m = 0,
        h_1 - m_1 (h_2 - h_1) / (m_2 - m_1), averaged over the positions and tabulated on
        ``n`` uniform points."""
        masses = np.unique(mass)
        if masses.size < 2 or masses[0] <= 0:
            raise ValueError("the unloaded profile needs two bench masses > 0")
        m1, m2 = masses[:2]
        grid = np.linspace(float(np.min(x)), float(np.max(x)), n)
        acc, count = np.zeros(n), 0
        for pos in np.unique(position):
            rows = [(mass == mk) & (position == pos) for mk in (m1, m2)]
            if not (rows[0].any() and rows[1].any()):
                continue
            h1, h2 = (
                np.interp(grid, x[r][np.argsort(x[r])], height[r][np.argsort(x[r])]) for r in rows
            )
            acc += h1 - m1 * (h2 - h1) / (m2 - m1)
            count += 1
        if count == 0:
            raise ValueError("no load position has profiles at both lightest masses")
        return cls(
            x_min=float(grid[0]), x_max=float(grid[-1]), height=acc / count, mass_scaled=True
        )

    def __call__(self, x: np.ndarray) -> np.ndarray:
        grid = np.linspace(self.x_min, self.x_max, self.height.size)
        return np.interp(x, grid, self.height)


@dataclass(frozen=True, kw_only=True)
class Domain:
    """The trained range: load conditions (mass [kg], position [m]) and x [m] of the bench."""

    mass_min: float
    mass_max: float
    position_min: float
    position_max: float
    x_min: float
    x_max: float

    def violations(self, x: np.ndarray, mass: np.ndarray, position: np.ndarray) -> list[str]:
        """Human-readable list of what lies outside the trained range (empty if nothing)."""
        out = []

        # a relative slack of 1e-9 so that values read back from mm columns stay inside
        def outside(v: np.ndarray, lo: float, hi: float) -> bool:
            slack = 1e-9 * max(abs(lo), abs(hi), 1.0)
            return v.size > 0 and bool(np.any((v < lo - slack) | (v > hi + slack)))

        def span(v: np.ndarray, factor: float) -> str:
            lo, hi = factor * float(np.min(v)), factor * float(np.max(v))
            return f"{lo:.4g}" if lo == hi else f"{lo:.4g}..{hi:.4g}"

        if outside(mass, self.mass_min, self.mass_max):
            out.append(
                f"mass {span(mass, 1.0)} kg outside the trained "
                f"{self.mass_min:.4g}..{self.mass_max:.4g} kg"
            )
        if outside(position, self.position_min, self.position_max):
            out.append(
                f"load position {span(position, 1e3)} mm outside the trained "
                f"{1e3 * self.position_min:.4g}..{1e3 * self.position_max:.4g} mm"
            )
        if outside(x, self.x_min, self.x_max):
            out.append(
                f"x {span(x, 1e3)} mm outside the trained "
                f"{1e3 * self.x_min:.4g}..{1e3 * self.x_max:.4g} mm"
            )
        return out
