"""Analytic reference solutions of frictionless normal contact (Johnson 1985, ch. 2–5).

All take the **paper's equivalent modulus** E' of eq. 2 as ``modulus`` (E' = 2·E*, with E* the
Hertz/Johnson contact modulus), so that they can be compared with
:func:`~skisnow.contact.solve_contact` without conversion. Each is checked on its own by
quadrature and equilibrium in ``tests/contact/test_reference.py``.

* :func:`hertz_line` — a cylinder (radius R) on a half-space, plane strain, load per length W'.
* :func:`hertz_sphere` — a sphere (radius R) on a half-space, load W.
* :func:`flat_punch` — a rigid flat punch of half-width a in plane strain, load per length W'
  at eccentricity e (full contact while |e| < a/2):
  p(x) = W'/(π √(a² − x²)) · (1 + 2 e x / a²), tilt θ = 8 W' e/(π E' a²).
* :func:`winkler_free_beam` — a free beam of finite length on a Winkler foundation under a point
  force (Hetényi 1946, *Beams on Elastic Foundation*, ch. IV), with the closed form of the
  deflection under a central load, y = (Pλ/2k)(cosh λL + cos λL + 2)/(sinh λL + sin λL).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from skisnow._checks import positive_finite as _pos
from skisnow._errors import InputError

__all__ = [
    "FlatPunch",
    "HertzLine",
    "HertzSphere",
    "WinklerBeam",
    "flat_punch",
    "hertz_line",
    "hertz_sphere",
    "winkler_free_beam",
]


def _semi_elliptic(r: ArrayLike, a: float, p0: float) -> np.ndarray:
    """The Hertz distribution p₀ √(1 − r²/a²) [Pa], 0 outside |r| < a: the same form in line
    contact (r = x, a the half-width; :func:`hertz_line`) and point contact (a the contact
    radius; :func:`hertz_sphere`)."""
    s = 1.0 - (np.asarray(r, dtype=float) / a) ** 2
    return p0 * np.sqrt(np.clip(s, 0.0, None))


@dataclass(frozen=True, kw_only=True)
class HertzLine:
    """Hertz line contact: half-width a [m], peak p₀ [Pa], load per length W' [N/m]."""

    load_per_length: float
    radius: float
    modulus: float
    half_width: float
    max_pressure: float

    def pressure(self, x: ArrayLike) -> np.ndarray:
        """p(x) = p₀ √(1 − x²/a²) [Pa] (0 outside |x| < a)."""
        return _semi_elliptic(x, self.half_width, self.max_pressure)


def hertz_line(load_per_length: float, radius: float, *, modulus: float) -> HertzLine:
    """Cylinder on a half-space (plane strain): a = √(8 W' R/(π E')), p₀ = 2 W'/(π a).

    (Johnson eq. 4.45–4.46 with E* = E'/2.)
    """
    w, r, e = (
        _pos("load_per_length", load_per_length),
        _pos("radius", radius),
        _pos("modulus", modulus),
    )
    a = np.sqrt(8.0 * w * r / (np.pi * e))
    return HertzLine(
        load_per_length=w,
        radius=r,
        modulus=e,
        half_width=float(a),
        max_pressure=2 * w / (np.pi * a),
    )


@dataclass(frozen=True, kw_only=True)
class HertzSphere:
    """Hertz point contact: radius a [m], peak p₀ [Pa], approach δ [m]."""

    load: float
    radius: float
    modulus: float
    contact_radius: float
    max_pressure: float
    approach: float

    def pressure(self, r: ArrayLike) -> np.ndarray:
        """p(r) = p₀ √(1 − r²/a²) [Pa] (0 outside r < a)."""
        return _semi_elliptic(r, self.contact_radius, self.max_pressure)


def hertz_sphere(load: float, radius: float, *, modulus: float) -> HertzSphere:
    """Sphere on a half-space: a = (3 W R/(4 E*))^(1/3) with E* = E'/2; p₀ = 3W/(2πa²); δ = a²/R.

    (Johnson eq. 4.22–4.23.)
    """
    w, r, e = _pos("load", load), _pos("radius", radius), _pos("modulus", modulus)
    a = (3.0 * w * r / (4.0 * (e / 2.0))) ** (1.0 / 3.0)
    return HertzSphere(
        load=w,
        radius=r,
        modulus=e,
        contact_radius=float(a),
        max_pressure=float(3 * w / (2 * np.pi * a * a)),
        approach=float(a * a / r),
    )


@dataclass(frozen=True, kw_only=True)
class FlatPunch:
    """Rigid flat punch of half-width a in plane strain, load W' at eccentricity e."""

    load_per_length: float
    half_width: float
    eccentricity: float
    modulus: float

    @property
    def rotation(self) -> float:
        """Tilt θ = 8 W' e/(π E' a²) [rad] (positive: the side x > 0 goes down)."""
        return (
            8.0
            * self.load_per_length
            * self.eccentricity
            / (np.pi * self.modulus * self.half_width**2)
        )

    def pressure(self, x: ArrayLike) -> np.ndarray:
        """p(x) = W'/(π √(a² − x²))·(1 + 2 e x/a²) [Pa] for |x| < a, 0 outside."""
        x = np.asarray(x, dtype=float)
        a = self.half_width
        inside = np.abs(x) < a
        root = np.sqrt(np.where(inside, a * a - x * x, 1.0))
        p = self.load_per_length / (np.pi * root) * (1.0 + 2.0 * self.eccentricity * x / a**2)
        return np.where(inside, p, 0.0)

    def cell_average(self, edges: ArrayLike) -> np.ndarray:
        """Mean pressure over cells [edges[i], edges[i+1]] (exact integral, for BEM comparison).

        ∫ p dx = (W'/π)·[asin(x/a) − (2e/a²)·√(a² − x²)].
        """
        e = np.clip(np.asarray(edges, dtype=float), -self.half_width, self.half_width)
        a = self.half_width
        prim = (self.load_per_length / np.pi) * (
            np.arcsin(e / a)
            - 2 * self.eccentricity / a**2 * np.sqrt(np.clip(a * a - e * e, 0, None))
        )
        return np.diff(prim) / np.diff(np.asarray(edges, dtype=float))


def flat_punch(
    load_per_length: float, half_width: float, *, modulus: float, eccentricity: float = 0.0
) -> FlatPunch:
    """Rigid flat punch in plane strain (Johnson §2.8), centred or eccentric (|e| < a/2)."""
    w, a = _pos("load_per_length", load_per_length), _pos("half_width", half_width)
    e = float(eccentricity)
    if not abs(e) < a / 2:
        raise InputError(
            f"eccentricity {e:g} m: the punch stays in full contact only while "
            f"|e| < a/2 = {a / 2:g} m"
        )
    return FlatPunch(
        load_per_length=w, half_width=a, eccentricity=e, modulus=_pos("modulus", modulus)
    )


# the four Krylov-type functions cosh·cos, cosh·sin, sinh·cos, sinh·sin of ξ = λx and their
# derivative map: d/dξ F = _DERIV @ F
_DERIV = np.array([[0, -1, 1, 0], [1, 0, 0, 1], [1, 0, 0, -1], [0, 1, 1, 0]], dtype=float)


def _krylov(xi: np.ndarray) -> np.ndarray:
    ch, sh, c, s = np.cosh(xi), np.sinh(xi), np.cos(xi), np.sin(xi)
    return np.stack([ch * c, ch * s, sh * c, sh * s])


@dataclass(frozen=True, kw_only=True)
class WinklerBeam:
    """A free beam of length L on a Winkler foundation under a downward point force P.

    The deflection y(x) (downward, into the foundation) solves EI y⁗ + k y = P δ(x − a) on
    [0, L] with free ends (y″ = y‴ = 0), k the foundation modulus per unit length [N/m²]
    (Hetényi 1946, ch. IV; λ = (k/4EI)^¼). Each side of the load is a combination of
    cosh λx·cos λx, cosh λx·sin λx, sinh λx·cos λx, sinh λx·sin λx whose eight coefficients
    follow from the end conditions and the continuity of y, y′, y″ and the jump P/EI of y‴
    at the load: exact, with no approximation beyond the beam equation.
    """

    length: float
    stiffness: float
    foundation: float
    force: float
    load_position: float
    coefficients: tuple[float, ...]

    @property
    def characteristic(self) -> float:
        """λ = (k/(4 EI))^¼ [1/m]."""
        return float((self.foundation / (4.0 * self.stiffness)) ** 0.25)

    def deflection(self, x: ArrayLike, derivative: int = 0) -> np.ndarray:
        """y(x) [m] (downward) at 0 ≤ x ≤ L, or its ``derivative``-th derivative."""
        x = np.asarray(x, dtype=float)
        lam, a = self.characteristic, self.load_position
        c = np.asarray(self.coefficients).reshape(2, 4)
        mk = np.linalg.matrix_power(_DERIV, derivative) * lam**derivative
        left = c[0] @ np.tensordot(mk, _krylov(lam * x), axes=1)
        right = c[1] @ np.tensordot(mk, _krylov(lam * (x - a)), axes=1)
        return np.where(x < a, left, right)

    @property
    def centre_deflection_closed_form(self) -> float:
        """Hetényi's closed form under a central load, (Pλ/2k)(cosh λL + cos λL + 2)/(sinh λL +
        sin λL) [m] (valid when the load is at L/2)."""
        lam, ell = self.characteristic, self.length
        return float(
            self.force
            * lam
            / (2.0 * self.foundation)
            * (np.cosh(lam * ell) + np.cos(lam * ell) + 2.0)
            / (np.sinh(lam * ell) + np.sin(lam * ell))
        )


def winkler_free_beam(
    *, length: float, stiffness: float, foundation: float, force: float, load_position: float
) -> WinklerBeam:
    """Free beam on a Winkler foundation (Hetényi 1946): ``length`` L [m], EI [N m²],
    ``foundation`` k [N/m²] (pressure per settlement × width), downward ``force`` P [N] at
    ``load_position`` a [m] from the left end (0 < a < L)."""
    ell = _pos("length", length)
    ei = _pos("stiffness", stiffness)
    k = _pos("foundation", foundation)
    p = _pos("force", force)
    a = float(load_position)
    if not 0.0 < a < ell:
        raise InputError(f"load_position must lie inside (0, L) = (0, {ell}) m, got {a}")
    lam = (k / (4.0 * ei)) ** 0.25

    def rows(xi: float, derivative: int) -> np.ndarray:
        basis = _krylov(np.asarray(xi, dtype=float))
        return (np.linalg.matrix_power(_DERIV, derivative) @ basis) * lam**derivative

    m = np.zeros((8, 8))
    rhs = np.zeros(8)
    # free ends: y″ = y‴ = 0 at x = 0 (left basis at ξ = 0) and x = L (right basis at λ(L − a))
    m[0, :4], m[1, :4] = rows(0.0, 2), rows(0.0, 3)
    m[2, 4:], m[3, 4:] = rows(lam * (ell - a), 2), rows(lam * (ell - a), 3)
    # at the load: y, y′, y″ continuous; EI (y‴(a+) − y‴(a−)) = P
    for d in range(4):
        m[4 + d, :4] = -rows(lam * a, d)
        m[4 + d, 4:] = rows(0.0, d)
    rhs[7] = p / ei
    coef = np.linalg.solve(m, rhs)
    return WinklerBeam(
        length=ell,
        stiffness=ei,
        foundation=k,
        force=p,
        load_position=a,
        coefficients=tuple(float(c) for c in coef),
    )
