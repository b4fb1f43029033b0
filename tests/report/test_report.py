"""The HTML report: self-contained (no scripts, no external resources), its numbers are the
solver's, and it renders in headless Chromium (Debian's ``chromium``) with no console message.

The maps come from a small sweep with the analytic chunk function (``tests/_hertz_chunk.py``) so the
test stays fast; the metrics and the standard-load zones are the real ones.
"""

from __future__ import annotations

import itertools
import os
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from _hertz_chunk import hertz_chunk
from skisnow.sweep import SweepSpec, open_sweep, run_sweep

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
SKI = "skate"


@pytest.fixture(scope="module")
def report(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from skisnow.report import study_ski, write_report

    out = tmp_path_factory.mktemp("report")
    spec = SweepSpec(
        skis=(SKI,), masses=np.arange(5.0, 131.0, 25.0), load_positions=(-0.12,),
        snow_moduli=(20e6, 200e6, 400e6),
    )  # fmt: skip
    run_sweep(spec, out / "maps.zarr", chunk_function=hertz_chunk, workers=0)
    study = study_ski(
        SKI, dataset=open_sweep(out / "maps.zarr"), profile_source="beam", n_points=1024,
        snows=(100e6, 400e6),
    )  # fmt: skip
    return write_report(study, out)


def test_report_is_self_contained(report: Path) -> None:
    text = report.read_text(encoding="utf-8")
    assert report.name == "skate_report.html"
    assert "<script" not in text.lower() and "<link" not in text.lower()
    # every src/href points inside the document (data: or #), never to a network or a file
    # (but the explorer page beside the report, when there is one: see test_report_links_...)
    for ref in re.findall(r'(?:src|href)\s*=\s*"([^"]*)"', text):
        assert ref.startswith(("data:", "#")), ref
    # no URL at all but the SVG/XLink namespace names (identifiers, never fetched)
    assert re.findall(r"https?://(?!www\.w3\.org/)", text) == []
    for title in ("practitioner metrics", "Contact at the standard loads", "Maps over load"):
        assert title in text
    assert text.count("<svg") >= 3  # area map, pressure map, load share


def test_report_numbers_are_the_solvers(report: Path) -> None:
    from skisnow.pipeline import solve_case

    zones = solve_case(SKI, mass=60.0, load_position=-0.12, snow_modulus=100e6,
                       profile_source="beam", n_points=1024).zones  # fmt: skip
    text = report.read_text(encoding="utf-8")
    row = re.search(r"<tr><td>full \(60 kg\)</td><td>100</td><td>rear</td><td>([^<]+)</td>", text)
    assert row is not None
    assert float(row.group(1)) == pytest.approx(zones.rear.length * 1e3, rel=5e-3)  # 3 digits


def test_report_sets_the_rigid_method_against_the_flexible_ski(report: Path) -> None:
    """The rigid-vs-flexible table holds both solvers' numbers for the same case."""
    from skisnow.pipeline import solve_case

    kw = dict(mass=60.0, load_position=-0.12, snow_modulus=100e6, profile_source="beam",
              n_points=1024)  # fmt: skip
    rigid = solve_case(SKI, **kw).zones.total
    flexible = solve_case(SKI, ski_model="flexible", **kw).zones.total
    text = report.read_text(encoding="utf-8")
    section = text.split("The rigid-profile method against the flexible ski", 1)[1]
    row = re.search(r"<tr><td>full \(60 kg\)</td><td>100</td><td>total</td>"
                    r"<td>([^<]+)</td><td>([^<]+)</td>", section)  # fmt: skip
    assert row is not None
    assert float(row.group(1)) == pytest.approx(rigid.length * 1e3, rel=5e-3)
    assert float(row.group(2)) == pytest.approx(flexible.length * 1e3, rel=5e-3)


def _chromium(args: list[str], tmp: Path) -> subprocess.CompletedProcess[str]:
    assert CHROMIUM is not None
    return subprocess.run(
        [
            CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu",
            "--disable-background-networking", "--disable-component-update", "--disable-sync",
            "--no-first-run", f"--user-data-dir={tmp / 'chromium-profile'}",
            "--enable-logging=stderr", "--v=0", *args,
        ],
        capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip


def _console_messages(stderr: str) -> list[str]:
    """Console messages of the page (Chromium logs each as ``...:CONSOLE...] "text"``)."""
    return [line for line in stderr.splitlines() if ":CONSOLE" in line]


def _need_chromium() -> None:
    if CHROMIUM is None:
        if os.environ.get("CI") and shutil.which("apt-get"):
            pytest.fail("chromium is missing in CI although apt is there (.ci/run installs it)")
        pytest.skip("headless Chromium not installed (apt-get install chromium); .ci/run does it")


def test_console_detector_catches_errors(tmp_path: Path) -> None:
    """The check below can fail: a page that logs an error is caught."""
    _need_chromium()
    bad = tmp_path / "bad.html"
    bad.write_text(
        '<!DOCTYPE html><html><body><script>console.error("boom")</script></body></html>'
    )
    run = _chromium(["--dump-dom", bad.as_uri()], tmp_path)
    assert any("boom" in m for m in _console_messages(run.stderr)), run.stderr[-2000:]


def test_report_renders_in_headless_chromium(report: Path, tmp_path: Path) -> None:
    _need_chromium()
    shot = report.with_name("skate_report_screenshot.png")
    run = _chromium(
        ["--hide-scrollbars", "--window-size=1200,3000", f"--screenshot={shot}", report.as_uri()],
        tmp_path,
    )
    assert run.returncode == 0, run.stderr[-2000:]
    assert _console_messages(run.stderr) == []
    from matplotlib.image import imread

    pixels = imread(shot)
    assert pixels.shape[:2] == (3000, 1200)
    assert pixels[..., :3].std() > 0.05  # not a blank page: header, tables and figures drawn
    dom = _chromium(["--dump-dom", report.as_uri()], tmp_path).stdout
    assert dom.count("<svg") >= 3 and "Contact at the standard loads" in dom


def test_report_links_an_explorer_beside_it_and_nothing_else() -> None:
    from skisnow.report import Link
    from skisnow.report._html import Section, render_page

    page = render_page("t", "s", [Section("x", (), (Link("ski_explore.html", "open"),))])
    assert re.findall(r'href\s*=\s*"([^"]*)"', page) == ["ski_explore.html"]
    for bad in ("https://example.org/x.html", "/tmp/x.html", "../x.html", "file:x.html"):
        with pytest.raises(ValueError, match="only a file name"):
            Link(bad, "no")


def test_report_progress_reaches_its_total(tmp_path: Path) -> None:
    """The report's progress bar: the study reports every map chunk and every standard case."""
    from skisnow.pipeline import study_ski

    calls = []

    def record(done: int, total: int, **_: object) -> None:
        calls.append((done, total))

    study_ski(SKI, store=tmp_path / "m.zarr", masses=(30.0, 60.0), map_moduli=(50e6, 200e6),
              snows=(100e6,), n_points=512, progress=record)  # fmt: skip
    assert calls and calls[-1][0] == calls[-1][1] == 2 + 4  # 2 map chunks, 2 loads × 2 models
    assert all(b[0] >= a[0] for a, b in itertools.pairwise(calls))


@pytest.mark.slow
def test_report_reads_on_a_phone(report: Path) -> None:
    """At 420 px: the page never scrolls sideways, tables scroll inside their box, and no text
    in a figure shows smaller than 12 px (a figure too wide for the phone scrolls in its box)."""
    import time

    _need_chromium()
    webdriver = pytest.importorskip("selenium.webdriver")
    from selenium.webdriver.chrome.service import Service

    opts = webdriver.ChromeOptions()
    opts.binary_location = CHROMIUM
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--no-first-run"):
        opts.add_argument(arg)
    driver = webdriver.Chrome(service=Service(shutil.which("chromedriver")), options=opts)
    try:
        driver.execute_cdp_cmd("Emulation.setDeviceMetricsOverride",
                               {"width": 420, "height": 900, "deviceScaleFactor": 1,
                                "mobile": False})  # fmt: skip
        driver.get(report.as_uri())
        time.sleep(0.5)
        page_width, figures, tables = driver.execute_script("""
          const figs = [];
          for (const svg of document.querySelectorAll('figure svg')) {
            const r = svg.getBoundingClientRect(); if (r.width === 0) continue;
            const scale = r.width / svg.viewBox.baseVal.width; let m = Infinity;
            for (const t of svg.querySelectorAll('text')) {
              const fs = parseFloat(getComputedStyle(t).fontSize);
              if (fs > 0 && t.textContent.trim()) m = Math.min(m, fs * scale);
            }
            figs.push([r.width, m]);
          }
          const tabs = [...document.querySelectorAll('table')].map(
            (t) => getComputedStyle(t.parentElement).overflowX);
          return [document.documentElement.scrollWidth, figs, tabs];""")  # fmt: skip
    finally:
        driver.quit()
    assert page_width <= 420
    assert figures and all(m >= 11.95 for _, m in figures), figures
    assert sum(w >= 380 for w, _ in figures) >= len(figures) // 2  # most figures full width
    assert tables and set(tables) == {"auto"}
