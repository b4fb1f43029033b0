"""The explorer with base textures: the real contact on the page is the sweep's, the base
selector switches it, and a page without bases is unchanged."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from _browser import wait_ready
from skisnow.explore import ExplorerGrid, explorer_dataset, render_explorer, unpack
from skisnow.micro import grind_preset, write_topography
from skisnow.snow import snow_preset

GRID = ExplorerGrid(
    masses=(40.0, 80.0), load_positions=(-0.12,), snow_moduli=(100e6,), n_points=1024,
    n_display=128,
)  # fmt: skip


@pytest.fixture(scope="module")
def real_dataset(tmp_path_factory):
    d = tmp_path_factory.mktemp("texture")
    path = write_topography(grind_preset("S3", size=0.3e-3, seed=2), d / "s3small.npz")
    snow = snow_preset("machine-made")
    return explorer_dataset(["skate"], GRID, bases=(str(path), "smooth"), snow=snow)


def test_real_fields_are_the_sweeps_and_the_page_carries_them(real_dataset) -> None:
    ds = real_dataset
    assert list(ds["base"].values) == ["s3small.npz", "smooth"]
    frac = ds["real_fraction_percent"].sel(ski="skate", model="rigid")
    assert frac.sizes["station"] == 128
    # the smooth base on flat ice: where the ski bears, the whole apparent area is real
    smooth = frac.sel(base="smooth").values
    assert np.nanmin(smooth) == pytest.approx(100.0)
    textured = frac.sel(base="s3small.npz").values
    assert 0 < np.nanmax(textured) < 5.0
    page = render_explorer(ds, title="t")
    import base64
    import json
    import re

    meta = json.loads(re.search(r'id="skisnow-meta">(.*?)</script>', page).group(1))
    blob = base64.b64decode(re.search(r'id="skisnow-blob">(.*?)</script>', page).group(1))
    data = unpack(meta["arrays"], blob)
    assert meta["real"] and meta["grid"]["base"] == ["s3small.npz", "smooth"]
    got = data["real_fraction_percent"].reshape(ds["real_fraction_percent"].shape)
    want = np.nan_to_num(ds["real_fraction_percent"].values)
    step = np.abs(want).max(axis=-1, keepdims=True) / 16000
    assert np.all(np.abs(got - want) <= 0.5 * step + 1e-12)


def test_a_page_without_bases_has_no_real_panel(real_dataset) -> None:
    ds = explorer_dataset(["skate"], GRID)
    assert list(ds["base"].values) == [""]
    assert "real_fraction_percent" not in ds
    page = render_explorer(ds, title="t")
    assert '"real":false' in page


@pytest.mark.slow
def test_base_selector_in_a_real_browser(real_dataset, tmp_path: Path, make_browser) -> None:
    from selenium.webdriver.support.ui import Select

    page = tmp_path / "explore.html"
    page.write_text(render_explorer(real_dataset, title="real"), encoding="utf-8")
    driver = make_browser()
    try:
        driver.get(page.as_uri())
        wait_ready(driver)
        note = driver.find_element("id", "real-note")
        assert driver.find_element("id", "real-panel").is_displayed()
        first = note.text
        assert "s3small.npz" in first and "µ" in first
        Select(driver.find_element("id", "base")).select_by_visible_text("smooth")
        assert "smooth" in note.text and note.text != first
        errors = [e for e in driver.get_log("browser") if e["level"] in ("SEVERE", "WARNING")]
        assert errors == []
    finally:
        driver.quit()
