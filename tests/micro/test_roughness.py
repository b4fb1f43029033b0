"""Roughness parameters against analytic surfaces; synthesis → analysis round trips."""

from __future__ import annotations

import numpy as np
import pytest

from skisnow.micro import (
    PRESETS,
    GrindSpec,
    GroovePass,
    areal_parameters,
    grind,
    grind_preset,
    line_parameters,
    lowpass,
    make_topography,
    prepare,
    roughness,
    scherge2021,
)


def _sine(
    amplitude: float, wavelength: float, n: int = 400, dx: float = 1e-6, phase: float = 0.0
) -> object:
    x = np.arange(n) * dx
    h = amplitude * np.sin(2 * np.pi * x / wavelength + phase)[:, None] * np.ones((1, 64))
    return make_topography(h, dx=dx)


def test_sine_amplitude_parameters() -> None:
    a, lam, dx = 2e-6, 40e-6, 1e-6  # 10 full periods on 400 pixels
    p = areal_parameters(_sine(a, lam))
    # Sq: the discrete mean of sin² over whole periods is exactly 1/2
    assert p["Sq"] == pytest.approx(a / np.sqrt(2), rel=1e-12)
    # Sa: N = 40 samples per period starting at a zero give exactly A·2·cot(π/N)/N, which
    # tends to the continuum 2A/π (0.2 % below it here)
    n_per = round(lam / dx)
    assert p["Sa"] == pytest.approx(a * 2 / np.tan(np.pi / n_per) / n_per, rel=1e-12)
    assert p["Sa"] == pytest.approx(2 * a / np.pi, rel=3e-3)
    assert p["Ssk"] == pytest.approx(0.0, abs=1e-9)
    assert p["Sku"] == pytest.approx(1.5, rel=1e-9)  # ⟨sin⁴⟩/⟨sin²⟩² = 3/8 / 1/4
    # Sdq: forward differences of a sine have rms (2/dx)·sin(π dx/λ)·A/√2 over whole periods;
    # the open map has 399 differences, not 400, so the cos² average is off by < 1/399
    exact_fd = (2 / dx) * np.sin(np.pi * dx / lam) * a / np.sqrt(2)
    assert p["Sdq"] == pytest.approx(exact_fd, rel=2.5e-3)
    # continuum 2πA/(λ√2): finite differences lose (π dx/λ)²/6 = 0.1 %, the open end < 0.25 %
    assert p["Sdq"] == pytest.approx(2 * np.pi * a / lam / np.sqrt(2), rel=4e-3)


def test_paraboloid_moments() -> None:
    # h = c·(x² + y²) on a square [-L, L]²: mean 2cL²/3; variance of x² is 4L⁴/45 per axis
    n, dx, c = 401, 1e-6, 1e3
    x = (np.arange(n) - n // 2) * dx
    half = x[-1]
    h = c * (x[:, None] ** 2 + x[None, :] ** 2)
    p = areal_parameters(make_topography(h, dx=dx))
    sq_exact = c * np.sqrt(2 * 4 * half**4 / 45)
    assert p["Sq"] == pytest.approx(sq_exact, rel=5e-3)  # 401² samples vs the continuum
    # rms gradient: ⟨(2cx)² + (2cy)²⟩ = 8c²L²/3
    assert p["Sdq"] == pytest.approx(np.sqrt(8 * c * c * half**2 / 3), rel=5e-3)


def test_line_parameters_of_a_sine() -> None:
    a, lam = 1.5e-6, 50e-6
    # a cosine: its least-squares mean line over whole periods is flat (∫x·cos kx = 0), so
    # ISO 4287's line removal does not tilt it (a sine's would, by 0.5 % here)
    t = _sine(a, lam, n=500, phase=np.pi / 2)
    line = line_parameters(t, axis=0)
    assert line["Ra"] == pytest.approx(2 * a / np.pi, rel=3e-3)  # 50 samples per period
    # each of the 5 sampling lengths (100 µm) holds two full periods: peak-to-valley 2A
    # the sampled cosine's least-squares line keeps an O(1/N) tilt, worth < 1 % of 2A over
    # the whole profile (Rt) and less within one sampling length (Rz)
    assert line["Rz"] == pytest.approx(2 * a, rel=5e-3)
    assert line["Rt"] == pytest.approx(2 * a, rel=1e-2)


def test_lowpass_separates_wavelengths() -> None:
    n, dx = 512, 1e-6
    x = (np.arange(n) + 0.5) * dx
    long_ = 1e-6 * np.cos(np.pi * 8 * x / (n * dx))  # λ = 128 µm, a DCT basis function
    short = 0.3e-6 * np.cos(np.pi * 64 * x / (n * dx))  # λ = 16 µm
    t = make_topography((long_ + short)[:, None] * np.ones((1, 8)), dx=dx)
    out = np.asarray(lowpass(t, cutoff=33e-6).heights)[:, 0]
    np.testing.assert_allclose(out, long_, atol=1e-15)  # exact: both are DCT-II modes


def test_prepare_removes_the_plane_then_the_short_wavelengths() -> None:
    # a tilted plane + a 128 µm and a 16 µm mode: the one preparation of skisnow (plane removal,
    # 33 µm low-pass) returns the 128 µm mode (orthogonal to the plane over its 4 periods)
    n, dx = 512, 1e-6
    x = (np.arange(n) + 0.5) * dx
    y = (np.arange(8) + 0.5) * dx
    long_ = 1e-6 * np.cos(np.pi * 8 * x / (n * dx))
    short = 0.3e-6 * np.cos(np.pi * 64 * x / (n * dx))
    plane = 2e-6 + 0.01 * x[:, None] - 0.02 * y[None, :]
    t = make_topography((long_ + short)[:, None] + plane, dx=dx)
    out = np.asarray(prepare(t).heights)
    np.testing.assert_allclose(out, long_[:, None] * np.ones((1, 8)), atol=1e-12)
    # roughness() sees exactly this map: Sq of a cosine is its amplitude / √2
    assert roughness(t).Sq == pytest.approx(1e-6 / np.sqrt(2), rel=1e-6)
    assert np.asarray(prepare(t, cutoff=None).heights) == pytest.approx(
        (long_ + short)[:, None] * np.ones((1, 8)), abs=1e-12
    )


def test_parabolic_groove_round_trip() -> None:
    # uniform position across a parabolic groove of full width: Ssk = 0.639, Sku = 2.143,
    # Ra = 4d/(9√3) (the moments of v², v uniform on [-1, 1])
    spec = GrindSpec("t", "", (GroovePass(pitch=50e-6, depth=6e-6),))
    t = grind(spec, shape=(1000, 16), dx=0.5e-6)
    p = areal_parameters(t)
    # 100 samples per groove, sampled on a grid that includes the cusps: moments within 0.5 %
    assert p["Ssk"] == pytest.approx(0.6389, rel=5e-3)
    assert p["Sku"] == pytest.approx(2.1429, rel=5e-3)
    line = line_parameters(t, axis=0, n_sampling=5)
    assert line["Ra"] == pytest.approx(4 * 6e-6 / (9 * np.sqrt(3)), rel=5e-3)


def test_grinding_is_seeded() -> None:
    a = grind_preset("S2", size=200e-6, dx=2e-6, seed=3)
    b = grind_preset("S2", size=200e-6, dx=2e-6, seed=3)
    c = grind_preset("S2", size=200e-6, dx=2e-6, seed=4)
    np.testing.assert_array_equal(a.heights, b.heights)
    assert not np.array_equal(a.heights, c.heights)


@pytest.mark.slow
def test_presets_in_table1_ranges() -> None:
    """Line roughness of S1–S5 after the seed's processing lies in Table 1's ranges."""
    ra_lo, ra_hi = min(scherge2021.TABLE1_RA_UM.values()), max(scherge2021.TABLE1_RA_UM.values())
    rz_lo, rz_hi = min(scherge2021.TABLE1_RZ_UM.values()), max(scherge2021.TABLE1_RZ_UM.values())
    for name in PRESETS:
        r = roughness(grind_preset(name))
        assert ra_lo <= r.Ra * 1e6 <= ra_hi, (name, r.Ra)
        assert rz_lo <= r.Rz * 1e6 <= 13.0, (name, r.Rz)
        assert rz_hi <= 13.0
        # areal values "near Table 4": Sa within a factor 2, Sdq within 0.1–0.25
        assert 0.8 <= r.Sa * 1e6 <= 3.5 and 0.1 <= r.Sdq <= 0.25, (name, r.Sa, r.Sdq)


# ---- Sdq of a map with missing pixels (trust audit finding 13) ---------------------------------


def _wavy_map(n: int = 256, d: float = 1e-6) -> np.ndarray:
    """Two crossed sinusoids: a map of known, smoothly varying slope."""
    x = np.arange(n) * d
    xx, yy = np.meshgrid(x, x, indexing="ij")
    return 1e-6 * np.sin(2 * np.pi * xx / (64 * d)) + 0.5e-6 * np.sin(2 * np.pi * yy / (32 * d))


def _holes_where(h: np.ndarray, d: float, keep: str) -> np.ndarray:
    """The map with the 2 % flattest or steepest interior pixels removed (NaN)."""
    gx, gy = np.gradient(h, d)
    slope = np.hypot(gx, gy)
    interior = np.zeros(h.shape, bool)
    interior[4:-4, 4:-4] = True
    cut = np.quantile(slope[interior], 0.02 if keep == "flat" else 0.98)
    sel = interior & ((slope <= cut) if keep == "flat" else (slope >= cut))
    out = h.copy()
    out[sel] = np.nan
    return out


def test_sdq_spread_brackets_the_complete_maps_value() -> None:
    from skisnow.micro import sdq_spread

    d = 1e-6
    h = _wavy_map(d=d)
    full = areal_parameters(make_topography(h, dx=d, dy=d))["Sdq"]
    # the discrete slope of the complete map: rms of the forward differences of each sinusoid
    k = 2 * np.sin(np.pi * d / np.array([64 * d, 32 * d])) / d
    assert full == pytest.approx(np.hypot(1e-6 * k[0], 0.5e-6 * k[1]) / np.sqrt(2), rel=0.02)
    assert sdq_spread(make_topography(h, dx=d, dy=d)) is None  # no holes: nothing to report
    # holes where the surface is flattest: the skipping definitions lose low-slope pairs (above
    # the complete value), the harmonic fill is the smoothest surface meeting the rims (below)
    flat = sdq_spread(make_topography(_holes_where(h, d, "flat"), dx=d, dy=d))
    assert flat is not None and flat.missing > 0
    assert flat.low <= full <= flat.high
    assert flat.values["filled"] == flat.low and flat.sdq == flat.values["skipped"]
    assert flat.digits < 4  # the printed Sdq is rounded to what the holes leave of it


def test_sdq_spread_filled_value_is_a_lower_bound() -> None:
    """Dirichlet's principle: the harmonic fill minimises the squared differences inside the
    holes, so it never exceeds the complete map's Sdq. Holes at the steepest pixels (as optical
    profilers lose them) put every definition below the complete value: the spread then does NOT
    bracket it, only the fill bounds it from below."""
    from skisnow.micro import sdq_spread

    d = 1e-6
    h = _wavy_map(d=d)
    full = areal_parameters(make_topography(h, dx=d, dy=d))["Sdq"]
    steep = sdq_spread(make_topography(_holes_where(h, d, "steep"), dx=d, dy=d))
    assert steep.high == steep.values["filled"] <= full
    rng = np.random.default_rng(0)
    for _ in range(5):
        hh = h.copy()
        for i, j in rng.integers(4, 250, size=(40, 2)):
            hh[i : i + 3, j : j + 3] = np.nan
        assert sdq_spread(make_topography(hh, dx=d, dy=d)).values["filled"] <= full


@pytest.mark.shared
def test_topo_of_a_real_map_with_holes_says_so(topography_dir, capsys) -> None:
    import json

    from skisnow.cli import main

    f = str(topography_dir / "sur-2.sur")
    assert main(["topo", f, "--form", "plane", "--cutoff-um", "0", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    holes = doc["Sdq_holes"]
    assert holes["missing_pixels"] == doc["missing_pixels"] == 117
    assert holes["definitions"]["skipped"]["Sdq"] == doc["parameters"]["Sdq"]
    assert holes["low"] <= doc["parameters"]["Sdq"] <= holes["high"]
    digits = holes["significant_digits"]
    assert 1 <= digits < 4
    assert main(["topo", f, "--form", "plane", "--cutoff-um", "0"]) == 0
    text = capsys.readouterr().out
    assert "note: Sdq of a map with 117 missing pixels" in text
    assert f"{doc['parameters']['Sdq']:#.{digits}g}" in text
    # a complete map: no note, Sdq to 4 digits
    assert main(["topo", str(topography_dir / "x3p-2.x3p"), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["Sdq_holes"] is None
