"""The explorer: its packing is lossless to the stated quantisation, its data are the solver's
(force balance on the display grid, identical metrics), and the page works in a real browser.

The browser test drives Debian's ``chromium`` through ``chromedriver`` with Selenium (never a
downloaded browser or driver): it moves the mass and snow sliders with the keyboard, as a user
would, and checks that the zone lengths shown are the precomputed ones for that grid point and
that the console stays clean. It skips, saying why, where Chromium or its driver is absent.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from _browser import wait_ready
from skisnow.constants import STANDARD_GRAVITY
from skisnow.explore import (
    ExplorerGrid,
    explorer_dataset,
    pack,
    quantise_curves,
    render_explorer,
    unpack,
)
from skisnow.explore._pack import QMAX
from skisnow.sweep import block_mean

GRID = ExplorerGrid(
    masses=(30.0, 60.0, 90.0),
    load_positions=(-0.12, -0.04),
    snow_moduli=(50e6, 200e6),
    n_points=1024,
    n_display=128,
)


@settings(max_examples=60, deadline=None)
@given(
    arrays(
        np.float64,
        st.tuples(st.integers(1, 4), st.integers(2, 40)),
        elements=st.floats(-1e4, 1e4).filter(lambda f: f == 0 or abs(f) > 1e-30),
    )
)
def test_pack_round_trip_within_half_a_step(values: np.ndarray) -> None:
    manifest, blob = pack({"c": values}, {"m": values.astype(np.float32)})
    out = unpack(manifest, blob)
    _, scale = quantise_curves(values)
    assert np.all(np.abs(out["c"] - values) <= 0.5 * scale[..., None].astype(float) * (1 + 1e-6))
    np.testing.assert_array_equal(out["m"], values.astype(np.float32))
    assert all(a["offset"] % 8 == 0 for a in manifest.values())


def test_quantisation_keeps_deltas_in_int16() -> None:
    # the worst case: a curve jumping between its two extremes
    v = np.tile([1.0, -1.0], 50)[None, :] * 3.7
    levels, _ = quantise_curves(v)
    assert np.abs(levels).max() == QMAX
    assert np.abs(np.diff(levels)).max() <= np.iinfo(np.int16).max
    manifest, blob = pack({"c": v}, {})
    np.testing.assert_allclose(unpack(manifest, blob)["c"], v, atol=3.7 / QMAX)


def test_block_mean_conserves_the_integral() -> None:
    rng = np.random.default_rng(0)
    p = rng.random((3, 1024))
    np.testing.assert_allclose(block_mean(p, 128).sum(-1) * 8, p.sum(-1), rtol=1e-13)


@pytest.fixture(scope="module")
def dataset():
    return explorer_dataset(["classic"], GRID, ski_models=("rigid", "flexible"))


def test_display_pressure_carries_the_load(dataset) -> None:
    """Force balance on the display grid: Σ p̄ · Δx̄ · w = m·g at every converged point."""
    from skisnow.ski import get_ski

    width = get_ski("classic").width
    x = dataset["x_mm"].values[0] * 1e-3
    dx = x[1] - x[0]
    for k in range(2):  # rigid, flexible
        p = dataset["pressure_kpa"].values[0, k] * 1e3  # (mass, pos, mod, station)
        force = p.sum(-1) * dx * width
        expected = np.asarray(GRID.masses)[:, None, None] * STANDARD_GRAVITY
        ok = dataset["converged"].values[0, k]
        assert ok.all()
        np.testing.assert_allclose(force, np.broadcast_to(expected, force.shape), rtol=1e-6)
        # in contact the ski base lies on the snow surface (b = −u where p > 0); nowhere does
        # it sink below it — to the quantisation, on the display grid
        b, s = dataset["base_um"].values[0, k], dataset["snow_um"].values[0, k]
        code = dataset["zone_code"].values[0, k] > 0
        # blocks inside a patch (a block at a patch end also holds cells out of contact)
        inside = code & np.roll(code, 1, axis=-1) & np.roll(code, -1, axis=-1)
        assert inside.any()
        assert np.all(b - s > -1.0)
        assert np.all(np.abs(b[inside] - s[inside]) < 1.0)


def test_metrics_are_the_solvers(dataset) -> None:
    # The reference is solved to 1e-11: at the default 1e-8 a cold flexible solve of the classic
    # (60 kg, -40 mm, 200 MPa) can stop with one edge cell of near-zero pressure still open
    # (front 131.0 against 132.9 mm at 1e-11), which the warm-started explorer has closed.
    from skisnow.pipeline import solve_case

    for model in ("rigid", "flexible"):
        zones = solve_case("classic", mass=60.0, load_position=-0.04, snow_modulus=200e6,
                           n_points=GRID.n_points, ski_model=model, tol=1e-11).zones  # fmt: skip
        point = dataset.sel(ski="classic", model=model, mass_kg=60.0, load_position_mm=-40.0,
                            snow_modulus_mpa=200.0)  # fmt: skip
        _same_zones(point, zones)


def _same_zones(point, zones) -> None:
    for z in ("rear", "middle", "front", "total", "rear_glide", "kick_zone", "front_glide"):
        assert point["length_mm"].sel(zone=z).item() == pytest.approx(zones[z].length * 1e3)
        assert point["patches"].sel(zone=z).item() == zones[z].patches
        if zones[z].area > 0:
            assert point["mean_pressure_kpa"].sel(zone=z).item() == pytest.approx(
                zones[z].mean_pressure * 1e-3, rel=1e-6
            )


def test_page_is_self_contained(dataset) -> None:
    page = render_explorer(dataset, title="t")
    assert "http://" not in page.replace("http://www.w3.org", "")
    assert "https://" not in page and "<link" not in page and " src=" not in page
    assert "__" not in page.split('id="skisnow-blob"')[0].split("<script")[0]  # all filled in


@pytest.mark.slow
def test_page_in_a_real_browser(dataset, tmp_path: Path, make_browser) -> None:
    from selenium.webdriver.common.keys import Keys

    page = tmp_path / "explore.html"
    page.write_text(render_explorer(dataset, title="skisnow explorer"), encoding="utf-8")
    driver = make_browser()
    try:
        driver.get(page.as_uri())
        wait_ready(driver)

        def shown():
            rows = driver.find_elements("css selector", "#zones tr[data-zone]")
            return {r.get_attribute("data-zone"): r.find_element("css selector", ".length").text
                    for r in rows}  # fmt: skip

        def expect(mass: float, pos: float, mod: float, model="rigid") -> dict[str, str]:
            pt = dataset.sel(ski="classic", model=model, mass_kg=mass, load_position_mm=pos,
                             snow_modulus_mpa=mod)  # fmt: skip
            return {z: f"{pt['length_mm'].sel(zone=z).item():.1f}"
                    for z in ("rear", "middle", "front", "total", "rear_glide", "kick_zone",
                              "front_glide")}  # fmt: skip

        # the page opens nearest to 60 kg, −120 mm, 100 MPa
        assert shown() == expect(60.0, -120.0, 50.0)
        mass = driver.find_element("id", "mass")
        mass.send_keys(Keys.RIGHT)  # 60 → 90 kg
        mod = driver.find_element("id", "mod")
        mod.send_keys(Keys.RIGHT)  # 50 → 200 MPa
        assert driver.find_element("id", "mass-value").text == "90 kg"
        assert driver.find_element("id", "mod-value").text == "200 MPa"
        assert shown() == expect(90.0, -120.0, 200.0)
        driver.find_element("id", "pos").send_keys(Keys.RIGHT)
        mass.send_keys(Keys.HOME)
        assert shown() == expect(30.0, -40.0, 200.0)
        from selenium.webdriver.support.ui import Select

        Select(driver.find_element("id", "model")).select_by_visible_text("flexible")
        assert shown() == expect(30.0, -40.0, 200.0, "flexible")
        shot = Path(os.environ.get("SKISNOW_SCREENSHOT", tmp_path / "explore.png"))
        driver.save_screenshot(str(shot))
        assert shot.stat().st_size > 10_000
        errors = [e for e in driver.get_log("browser") if e["level"] in ("SEVERE", "WARNING")]
        assert errors == []
    finally:
        driver.quit()


def test_cli_writes_a_page_and_refuses_bad_options(tmp_path: Path, capsys) -> None:
    import json

    from skisnow.cli import main

    out = tmp_path / "e.html"
    args = ["explore", "skate", "--mass-kg", "30,60", "--load-position-mm", "-120",
            "--workers", "0", "--snow-modulus-mpa", "100", "--out", str(out), "--json"]  # fmt: skip
    assert main(args) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["points"] == 2 and doc["converged"] is True and out.stat().st_size > 10_000
    assert main([*args, "--ski-model", "stiff"]) == 2
    assert "--ski-model" in capsys.readouterr().err
    assert main([*args, "--stations", "500"]) == 2  # must divide the 4096 solver stations
    assert main(["explore", "no-such-ski", "--out", str(tmp_path / "x.html")]) == 2
    assert not (tmp_path / "x.html").exists()


#: An uneven grid (the demo's snow axis is uneven): the map must be drawn on the true values.
UNEVEN = ExplorerGrid(
    masses=(30.0, 45.0, 60.0, 100.0),
    load_positions=(-0.12, -0.07),
    snow_moduli=(20e6, 40e6, 100e6, 400e6),
    n_points=1024,
    n_display=128,
)


@pytest.fixture(scope="module")
def uneven():
    return explorer_dataset([_renamed_classic()], UNEVEN)


def _renamed_classic() -> str:
    """A ski file in a temporary folder (its folder must never show on the page)."""
    import tempfile

    from skisnow.ski import get_ski, write_ski

    folder = Path(tempfile.mkdtemp(prefix="skisnow-private-folder-"))
    path = folder / "my_classic.json"
    write_ski(get_ski("classic"), path)
    return str(path)


def test_page_names_no_local_folder_and_embeds_the_figures_palette(uneven) -> None:
    import json

    from skisnow.plot import ZONE_COLORS

    page = render_explorer(uneven, title="t", subtitle="my_classic.json")
    assert "skisnow-private-folder" not in page
    meta = json.loads(page.split('id="skisnow-meta">')[1].split("</script>")[0])
    assert meta["palette"] == ZONE_COLORS and meta["grid"]["ski"] == ["my_classic.json"]
    assert meta["kick_zone_mm"][0] == pytest.approx([-254.2, 256.2])


@pytest.mark.slow
def test_page_on_an_uneven_grid_in_a_real_browser(uneven, tmp_path: Path, make_browser) -> None:
    """The marker lies on the cell of the selected value, the colour bar's numbers are the
    data's range, the kick-zone marks are drawn, the link restores the settings, the export
    carries the case shown."""
    import json

    from selenium.webdriver.common.keys import Keys

    page = tmp_path / "explore.html"
    page.write_text(render_explorer(uneven, title="skisnow explorer"), encoding="utf-8")
    driver = make_browser()
    try:
        driver.get(page.as_uri())
        wait_ready(driver)
        driver.find_element("id", "mod").send_keys(Keys.END)  # 400 MPa
        driver.find_element("id", "mod").send_keys(Keys.LEFT)  # 100 MPa
        driver.find_element("id", "mass").send_keys(Keys.END)  # 100 kg
        assert driver.find_element("id", "mod-value").text == "100 MPa"
        canvas = driver.find_element("id", "map-area")
        marker = json.loads(canvas.get_attribute("data-marker"))
        # the cell of 100 MPa spans the midpoints to its neighbours 40 and 400 (70 … 250 MPa)
        # and the cell of 100 kg from 80 kg to 120 kg (mirrored outer half-width), to a pixel
        lo, hi = marker["modulus"]
        assert (
            lo < 100.0 < hi
            and lo == pytest.approx(70.0, abs=4)
            and hi == pytest.approx(250.0, abs=6)
        )
        m0, m1 = marker["mass"]
        assert m0 == pytest.approx(80.0, abs=1) and m1 == pytest.approx(120.0, abs=1)
        # the colour bar's numbers: the data's range (total area at this position and model)
        area = uneven["area_cm2"].sel(zone="total", load_position_mm=-120.0).values
        shown = [float(v) for v in canvas.get_attribute("data-colorbar").split()]
        assert shown == pytest.approx([np.nanmin(area), np.nanmax(area)], rel=5e-3)
        # the kick-zone marks are drawn on the ski
        assert len(driver.find_element("id", "profile").get_attribute("data-kick-marks")
                   .split(",")) == 2  # fmt: skip
        # hover: value and grid point
        from selenium.webdriver.common.action_chains import ActionChains

        ActionChains(driver).move_to_element(canvas).perform()
        assert "MPa" in driver.find_element("id", "map-area-readout").text
        # export of the case shown
        doc = json.loads(driver.execute_script("return window.skisnowExplorer.exportText('json')"))
        assert (doc["mass_kg"], doc["snow_modulus_mpa"], doc["load_position_mm"]) == (
            100.0, 100.0, -120.0)  # fmt: skip
        assert doc["profile_route"] == "beam" and "kick_zone" in doc["zones"]
        csv = driver.execute_script("return window.skisnowExplorer.exportText('csv')")
        assert csv.splitlines()[1].startswith("zone,length_mm")
        # the link keeps the settings: change them, reload with the link, find them again
        driver.find_element("id", "pos").send_keys(Keys.END)  # -70 mm
        driver.execute_script("arguments[0].click()", driver.find_element("id", "zoom"))
        url = driver.current_url
        assert "#" in url and "pos=-70" in url
        driver.get("about:blank")
        driver.get(url)
        wait_ready(driver)
        assert driver.find_element("id", "mass-value").text == "100 kg"
        assert driver.find_element("id", "mod-value").text == "100 MPa"
        assert driver.find_element("id", "pos-value").text == "-70 mm"
        assert not driver.find_element("id", "zoom").is_selected()
        for width in (1400, 420):
            driver.set_window_size(width, 1800)
            time.sleep(0.3)
            shot = Path(os.environ.get("SKISNOW_SCREENSHOT_DIR", tmp_path)) / f"uneven_{width}.png"
            driver.save_screenshot(str(shot))
            assert shot.stat().st_size > 10_000
        errors = [e for e in driver.get_log("browser") if e["level"] in ("SEVERE", "WARNING")]
        assert errors == []
    finally:
        driver.quit()
