"""The elastic–plastic flat-ice curves against closed forms, limits and refinement.

References (each test names its own): Westergaard's elastic wavy contact and the
rigid–perfectly-plastic truncated sinusoid of :mod:`skisnow.micro.reference` (both checked on
their own in ``test_wavy_reference.py``); the purely plastic limit A = F/H of a stiff body on a
grind; Johnson's periodic indentation 2p/(E*q). E* = E'/2 (skisnow's equivalent modulus is twice
Johnson's contact modulus).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from skisnow.micro import (
    MirrorOperator,
    elastoplastic_curve,
    grind_preset,
    make_topography,
    prepare,
)
from skisnow.micro.reference import plastic_sinusoid, westergaard


def _sinusoid(delta: float, wavelength: float, periods: int, dx: float, ny: int = 4):
    """Δ cos(2πx/λ) sampled at pixel centres (x = (i + ½)dx): its mirror continuation at the
    map's edges is the same sinusoid (the map holds whole half-periods), so the mirror half-space
    sees an infinite periodic wavy surface. Heights toward the ice: peaks at x = 0, λ, ..."""
    n = round(periods * wavelength / dx)
    x = (np.arange(n) + 0.5) * dx
    h = delta * np.cos(2 * np.pi * x / wavelength)
    return make_topography(np.repeat(h[:, None], ny, axis=1), dx=dx), x


def test_mirror_operator_indents_a_cosine_as_johnson_says() -> None:
    # a periodic pressure p cos(qx) indents the half-space by 2p/(E* q) (E* = E'/2)
    e, lam, dx = 2e9, 100e-6, 1e-6
    topo, x = _sinusoid(1.0, lam, 3, dx)
    op = MirrorOperator(topo.shape, dx, dx, e)
    p = np.repeat(np.cos(2 * np.pi * x / lam)[:, None], 4, axis=1)
    u = op(p.ravel()).reshape(p.shape)
    expected = 2.0 / (0.5 * e * 2 * np.pi / lam) * p
    assert np.max(np.abs(u - expected)) < 1e-12 * np.max(np.abs(expected))
    # a uniform pressure moves nothing (the mean load is carried at infinity)
    assert np.max(np.abs(op(np.ones(p.size)))) < 1e-20


def test_light_load_is_westergaards_elastic_contact() -> None:
    e, delta, lam, dx = 1e9, 1e-6, 200e-6, 0.5e-6
    topo, _ = _sinusoid(delta, lam, 2, dx)
    pstar = math.pi * (e / 2) * delta / lam
    loads = np.array([0.02, 0.1, 0.3]) * pstar
    c = elastoplastic_curve(topo, pressures=loads, hardness=np.inf, modulus=e)
    assert c.converged.all()
    assert np.all(c.plastic_fraction == 0)
    for pbar, frac, ubar in zip(loads, c.fractional_area, c.mean_separation, strict=True):
        ref = westergaard(pbar, amplitude=delta, wavelength=lam, contact_modulus=e / 2)
        # contact width counted in whole 0.5 µm pixels: within one pixel per edge
        assert frac == pytest.approx(ref.contact_fraction, abs=2 * dx / lam)
        # mean separation ⟨max(g, 0)⟩ about the texture's mean plane, as Westergaard's
        assert ubar == pytest.approx(ref.mean_gap, rel=2e-3)


def test_stiff_limit_is_the_rigid_plastic_truncated_sinusoid() -> None:
    # half a period on the map: its mirror images make the whole wavy surface
    delta, lam, dx, hard = 2e-6, 100e-6, 0.05e-6, 10e6
    topo, _ = _sinusoid(delta, lam, 0.5, dx)
    loads = np.array([0.05, 0.2, 0.5]) * hard
    c = elastoplastic_curve(topo, pressures=loads, hardness=hard, modulus=1e14, tol=1e-11)
    assert c.converged.all()
    # every contact pixel plastic, A = F/H to the pixel (the last one is partly loaded)
    assert np.all(c.plastic_fraction > 0.95)
    n = topo.shape[0]
    assert c.fractional_area == pytest.approx(loads / hard, abs=1.0 / n)
    uc = 10 ** (-7.5)  # a bin edge of the gap distribution: exact there
    recip = c.reciprocal_separation(uc)
    for i, ph in enumerate(loads / hard):
        ref = plastic_sinusoid(ph, amplitude=delta, film_cutoff=uc)
        ubar, rec = ref.mean_separation, ref.reciprocal_separation
        # the truncation level is found to within one pixel's height step at the contact edge
        step = delta * 2 * np.pi / lam * np.sin(np.pi * ph) * dx
        assert c.mean_separation[i] == pytest.approx(ubar, abs=step)
        # ⟨1/u⟩ moves with the level by ⟨1/u²⟩ ≈ 1/(π·Δ·sin φ·u_c) per metre: one step's worth
        sensitivity = 1.0 / (np.pi * delta * np.sin(np.pi * ph) * uc)
        assert recip[i] == pytest.approx(rec, abs=sensitivity * step)


def test_full_plastic_flow_on_a_grind_carries_the_load_at_the_hardness() -> None:
    topo = prepare(grind_preset("S3", size=300e-6, dx=1e-6, seed=2))
    t = make_topography(np.asarray(topo.heights)[::3, ::3], dx=3e-6)
    hard = 15.9e6
    loads = np.array([0.02, 0.2]) * hard
    soft = elastoplastic_curve(t, pressures=loads, hardness=hard, modulus=1.93e9)
    stiff = elastoplastic_curve(t, pressures=loads, hardness=hard, modulus=1e13, tol=1e-11)
    # A_r = F/H in the rigid-plastic limit (one partly loaded pixel: 1/N of the area)
    assert stiff.fractional_area == pytest.approx(loads / hard, abs=2.0 / t.heights.size)
    # the elastic rims of the ice/UHMWPE contact only add area, and less at higher load
    excess = soft.fractional_area / (loads / hard)
    assert np.all(excess >= 1.0) and excess[1] <= excess[0]
    # separations shrink with load; the stiff body leaves the texture's own gaps
    assert soft.mean_separation[1] < soft.mean_separation[0]


def test_curves_converge_under_refinement_of_the_topography_grid() -> None:
    # one band-limited surface (S3 after the 33 µm low-pass) sampled every 8, 4, 2 and 1 µm
    base = prepare(grind_preset("S3", size=400e-6, dx=1e-6, seed=3))
    loads = np.array([20e3, 500e3])
    ubar, area, recip = [], [], []
    for k in (8, 4, 2, 1):
        t = make_topography(np.asarray(base.heights)[::k, ::k], dx=k * 1e-6)
        c = elastoplastic_curve(t, pressures=loads, hardness=15.9e6, modulus=1.93e9)
        assert c.converged.all()
        ubar.append(c.mean_separation)
        area.append(c.fractional_area / (loads / 15.9e6))
        recip.append(c.reciprocal_separation(1e-7))
    ubar, area, recip = np.array(ubar), np.array(area), np.array(recip)
    # separation and reciprocal separation: the distance to the 1 µm value shrinks at every
    # refinement; at the 2 µm default it is below 0.3 % and 2 %
    du = np.abs(ubar[:-1] - ubar[-1])
    dr = np.abs(recip[:-1] - recip[-1])
    assert np.all(np.diff(du, axis=0) < 0) and np.all(np.diff(dr, axis=0) < 0)
    assert np.all(du[2] < 3e-3 * ubar[-1]) and np.all(dr[2] < 2e-2 * recip[-1])
    # the real area approaches F/H from above, monotonically, as the elastic rims of the
    # contact spots are resolved (first order in the pixel: the slow one)
    assert np.all(area >= 1.0) and np.all(np.diff(area, axis=0) < 0)
