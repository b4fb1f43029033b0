"""The compliance of the free ski relative to its binding, applied in O(n) by cumulative sums.

Clamp the Euler–Bernoulli beam (bending stiffness EI(x)) at the load point x_m: each half is a
cantilever. An upward force distribution on a half bends it by (Timoshenko & Gere 1961, the
double integration of EI w'' = M)

    w(x) = ∫_{x_m}^{x} (x − t) M(t)/EI(t) dt,   M(t) = ∫_{t}^{end} (s − t) q(s) ds

(distances measured away from x_m on either side; M is the bending moment at t of the load
beyond t). Written with the kernel (x − t)₊ this is w = B C Bᵀ f with B_it = (d_i − t)₊,
C = diag(quadrature weight / EI(t)) and f the nodal forces: symmetric positive semi-definite by
construction, and each factor is a pair of cumulative sums (never an n × n matrix). The
quadrature over t is the trapezoidal rule on the nodes {x_m} ∪ {stations on that side}, exact
to O(Δx²). When the force and moment balance of the whole ski hold, the clamp carries nothing
and w is the deflection of the free ski up to a rigid motion, the one the contact solver's
Lagrange multipliers δ, θ supply.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from skisnow._errors import InputError

__all__ = ["CantileverCompliance", "cantilever_compliance"]


@dataclass(frozen=True, kw_only=True, eq=False)
class _Half:
    """One cantilever: station indices (ordered away from the clamp), distances, weights/EI."""

    index: np.ndarray  # stations of this half, nearest the clamp first
    d: np.ndarray  # their distances from the clamp [m], increasing
    t: np.ndarray  # quadrature nodes [m]: 0, then d
    c: np.ndarray  # trapezoid weight / EI(t) [1/(N m)]

    def apply(self, f: np.ndarray) -> np.ndarray:
        """Deflection [m] (per station of this half) under nodal forces f [N] (last axis)."""
        if self.d.size == 0:
            return f[..., :0]
        if f.ndim == 1:
            # compiled (numba imported on first use: the CLI and sweep workers start without it)
            from skisnow.contact._beam_kernel import cantilever_apply as _cantilever_apply

            out = np.empty(self.d.size)
            _cantilever_apply(np.ascontiguousarray(f), self.d, self.t, self.c, out)
            return out
        # moment at the nodes t: M(t_k) = Σ_{d_i > t_k} (d_i − t_k) f_i
        rev0 = np.cumsum(f[..., ::-1], axis=-1)[..., ::-1]  # Σ_{i >= j} f_i
        rev1 = np.cumsum((f * self.d)[..., ::-1], axis=-1)[..., ::-1]
        zero = np.zeros((*f.shape[:-1], 1))
        a0 = np.concatenate([rev0, zero], axis=-1)  # at t_0 = 0: all; at t_{j+1} = d_j: i > j
        a1 = np.concatenate([rev1, zero], axis=-1)
        moment = a1 - self.t * a0
        return self.deflect(moment)

    def deflect(self, moment: np.ndarray) -> np.ndarray:
        """Deflection of the stations under a bending-moment distribution M(t) at the nodes."""
        kappa = self.c * moment  # curvature × weight
        k0 = np.cumsum(kappa, axis=-1)[..., :-1]  # Σ_{t_k < d_i} κ_k  (t_k <= d_{i-1})
        k1 = np.cumsum(kappa * self.t, axis=-1)[..., :-1]
        return self.d * k0 - k1


@dataclass(frozen=True, kw_only=True, eq=False)
class CantileverCompliance:
    """The beam part of the coupled compliance: w = K_beam f, relative to the clamp at x_m.

    Build with :func:`cantilever_compliance`. Calling it maps nodal forces f [N] at the
    stations (any leading batch axes) to the upward deflection w [m] of the stations.

    Attributes
    ----------
    x
        Stations [m] (increasing).
    load_position
        The clamp x_m [m] (the binding).
    diagonal
        K_beam's diagonal [m/N] (each station's deflection under its own unit force).
    """

    x: np.ndarray
    load_position: float
    rear: _Half = field(repr=False)
    front: _Half = field(repr=False)
    diagonal: np.ndarray = field(repr=False)
    #: (side, d, u, v) at every station: the half (0 rear, 1 front), the distance from the clamp
    #: and the generators of :meth:`block` (G_ij = u_i d_j + v_i within a half, i the station
    #: nearer the clamp), for the compiled assembly of dense blocks
    generators: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] = field(repr=False)

    def __call__(self, force: np.ndarray) -> np.ndarray:
        """Upward deflection [m] of every station under upward nodal forces ``force`` [N]."""
        f = np.asarray(force, dtype=np.float64)
        if f.ndim == 1 and f.size == self.x.size:
            # compiled, straight on the grid (the halves are contiguous runs of stations)
            from skisnow.contact._beam_kernel import cantilever_apply_strided as _apply

            out = np.empty(f.size)
            f = np.ascontiguousarray(f)
            split = self.rear.index.size
            if split:
                _apply(f, split - 1, -1, self.rear.d, self.rear.t, self.rear.c, out)
            if split < f.size:
                _apply(f, split, 1, self.front.d, self.front.t, self.front.c, out)
            return out
        out = np.zeros_like(f)
        for half in (self.rear, self.front):
            if half.index.size:
                out[..., half.index] = half.apply(f[..., half.index])
        return out

    def block(self, cells: np.ndarray, *, lower_only: bool = False) -> np.ndarray:
        """The dense block K_beam[cells, cells] [m/N] (rows and columns of the stations
        ``cells``, increasing): G_ij = Σ_{t_k < min(d_i, d_j)} c_k (d_i − t_k)(d_j − t_k), zero
        between the two halves. With i the station nearer the clamp, G_ij = u_i d_j + v_i
        (u_i = d_i S0_i − S1_i, v_i = S2_i − d_i S1_i, S the cumulative sums of c, c t, c t² up
        to d_i): one outer product per half, mirrored from its triangle (``lower_only``: the
        lower triangle only is right, as a Cholesky factorisation reads it)."""
        cells = np.asarray(cells, dtype=np.intp)
        out = np.zeros((cells.size, cells.size))
        for half in (self.rear, self.front):
            if not half.index.size:
                continue
            pos_of = np.full(self.x.size, -1, dtype=np.intp)
            pos_of[half.index] = np.arange(half.index.size)
            pos = pos_of[cells]
            sel = np.flatnonzero(pos >= 0)
            if not sel.size:
                continue
            # the stations of a half are contiguous in x, ordered away from the clamp: toward
            # the tip (increasing x) in front, toward the tail in the rear
            front = half is self.front
            ordered = sel if front else sel[::-1]  # nearest the clamp first
            ps = pos[ordered]
            d = half.d[ps]
            s0 = np.cumsum(half.c)[ps]
            s1 = np.cumsum(half.c * half.t)[ps]
            s2 = np.cumsum(half.c * half.t * half.t)[ps]
            g = np.multiply.outer(d * s0 - s1, d)
            g += (s2 - d * s1)[:, None]  # right where j is at or beyond i: the upper triangle
            if not front:
                g = g[::-1, ::-1]  # in increasing x: the lower triangle is right
            if not lower_only:
                g = np.triu(g) + np.triu(g, 1).T if front else np.tril(g) + np.tril(g, -1).T
            elif front:
                g = g.T
            lo, hi = int(sel[0]), int(sel[-1]) + 1
            out[lo:hi, lo:hi] = g
        return out

    def boot_deflection(self, force: float, boot_length: float) -> np.ndarray:
        """Deflection [m] of the stations under the boot: ``force`` [N] downward, uniform over
        ``boot_length`` [m] centred on the clamp (0 for a point force at the clamp).

        The bending moment of the uniform load, q (b/2 − t)²/2 for t < b/2, is exact at the
        quadrature nodes.
        """
        w = np.zeros(self.x.size)
        if boot_length <= 0.0:
            return w
        from skisnow.contact._beam_kernel import boot_deflect_strided

        q = -force / boot_length
        half_len = 0.5 * boot_length
        split = self.rear.index.size
        if split:
            boot_deflect_strided(q, half_len, split - 1, -1, self.rear.d, self.rear.t,
                                 self.rear.c, w)  # fmt: skip
        if split < w.size:
            boot_deflect_strided(q, half_len, split, 1, self.front.d, self.front.t,
                                 self.front.c, w)  # fmt: skip
        return w


def _half(index: np.ndarray, d: np.ndarray, ei: np.ndarray) -> _Half:
    t = np.empty(d.size + 1)
    t[0] = 0.0
    t[1:] = d
    weight = np.empty(t.size)  # trapezoid weights: half of each neighbouring interval
    dt = 0.5 * (t[1:] - t[:-1])
    weight[:-1] = dt
    weight[-1] = 0.0
    weight[1:] += dt
    return _Half(index=index, d=d, t=t, c=weight / ei)


def cantilever_compliance(
    x: ArrayLike,
    stiffness: ArrayLike,
    *,
    load_position: float,
) -> CantileverCompliance:
    """The compliance of a beam clamped at ``load_position``, both halves as cantilevers.

    Parameters
    ----------
    x
        Increasing stations [m] (need not be uniform).
    stiffness
        Bending stiffness EI [N m²]: a number, or an array of the same shape as ``x``
        (interpolated linearly at the clamp), or a callable EI(x) (vectorised).
    load_position
        The clamp x_m [m], inside [x[0], x[-1]].

    Returns
    -------
    CantileverCompliance
        The operator w = B C Bᵀ f (see the module docstring), O(n) per application.

    Raises
    ------
    InputError
        Non-increasing or non-finite stations, a non-finite or non-positive EI (the message
        names the station), a clamp outside the stations.
    """
    xs = np.asarray(x, dtype=np.float64)
    if (
        xs.ndim != 1
        or xs.size < 2
        or not (np.isfinite(xs[0]) and np.isfinite(xs[-1]) and np.all(xs[1:] > xs[:-1]))
    ):
        raise InputError("x must be a finite, strictly increasing 1D array of at least 2 stations")
    xm = float(load_position)
    if not (np.isfinite(xm) and xs[0] <= xm <= xs[-1]):
        raise InputError(
            f"load_position x_m = {xm} m must lie on the beam [{xs[0]}, {xs[-1]}] m (the clamp)"
        )
    ei_arr = None
    if callable(stiffness):
        ei_at = stiffness
    else:
        ei_arr = np.asarray(stiffness, dtype=np.float64)
        if ei_arr.ndim == 0:
            ei_at = lambda xx: np.full(np.shape(xx), float(ei_arr))  # noqa: E731
        elif ei_arr.shape == xs.shape:
            ei_at = lambda xx: np.interp(xx, xs, ei_arr)  # noqa: E731 (used when EI is callable)
        else:
            raise InputError(
                f"stiffness EI must be a number, a callable or an array shaped like x "
                f"{xs.shape}, got shape {ei_arr.shape}"
            )
    ei_nodes = ei_arr if ei_arr is not None and ei_arr.ndim == 1 else None
    halves = []
    split = int(np.searchsorted(xs, xm))  # the first station at or beyond x_m
    for side in ("rear", "front"):
        index = np.arange(split - 1, -1, -1) if side == "rear" else np.arange(split, xs.size)
        d = xm - xs[index] if side == "rear" else xs[index] - xm
        t = np.concatenate([[0.0], d])
        if ei_nodes is not None:  # EI at the clamp, then at the stations (the nodes t = d)
            ei = np.concatenate([[np.interp(xm, xs, ei_nodes)], ei_nodes[index]])
        else:
            ei = np.asarray(ei_at(xm + (t if side == "front" else -t)), dtype=np.float64)
        bad = ~np.isfinite(ei) | (ei <= 0.0)
        if np.any(bad):
            k = int(np.flatnonzero(bad)[0])
            at = xm + (t[k] if side == "front" else -t[k])
            raise InputError(
                f"bending stiffness EI must be finite and > 0 N m², got {ei[k]!r} at "
                f"x = {at * 1e3:.1f} mm"
            )
        halves.append(_half(index, d, ei))
    rear, front = halves
    diag = np.zeros(xs.size)
    side = np.zeros(xs.size, dtype=np.int8)
    dd, uu, vv = np.zeros(xs.size), np.zeros(xs.size), np.zeros(xs.size)
    from skisnow.contact._beam_kernel import half_generators

    for k, half in enumerate(halves):
        if half.index.size:
            # the stations of a half as a slice of the grid (rear: from x_m toward the tail);
            # K_ii = Σ_k c_k (d_i − t_k)₊² and the generators of ``block``, compiled
            at = slice(split - 1, None, -1) if k == 0 else slice(split, None)
            half_generators(half.c, half.t, half.d, diag[at], uu[at], vv[at])
            side[at] = k
            dd[at] = half.d
    for arr in (xs, diag, side, dd, uu, vv):
        arr.setflags(write=False)
    return CantileverCompliance(x=xs, load_position=xm, rear=rear, front=front, diagonal=diag,
                                generators=(side, dd, uu, vv))  # fmt: skip
