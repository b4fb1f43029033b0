"""Shared test fixtures."""

from __future__ import annotations

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared"


@pytest.fixture(scope="session")
def shared_dir() -> Path:
    """``../shared`` beside the checkout; tests that need it skip cleanly where it is absent."""
    if not SHARED.is_dir():
        pytest.skip("../shared is not present beside this checkout (as in a user's clone)")
    return SHARED


@pytest.fixture(scope="session")
def topography_dir(shared_dir: Path) -> Path:
    """The five real instrument files of ``../shared/data/topographies``."""
    d = shared_dir / "data" / "topographies"
    if not d.is_dir():
        pytest.skip("../shared/data/topographies is not present")
    return d


@pytest.fixture(scope="session", autouse=True)
def _one_blas_thread():
    """The suite's dense linear algebra (identification's small solves, SVDs and Cholesky
    factors; the contact's dense blocks) on one BLAS thread: on a shared 2-core machine
    OpenBLAS's second thread spins for more than it computes (measured: the same
    identification test 5 s or 42 s depending on the load). The answers are those of any
    thread count; the tests check numbers, not BLAS's threading."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        yield


@pytest.fixture(scope="session", autouse=True)
def _micro_curve_cache(tmp_path_factory: pytest.TempPathFactory):
    """The micro-curve cache of the test session in a temporary directory (never the user's
    ``~/.cache/skisnow``); subprocesses and Dask workers inherit it through the environment."""
    import os

    old = os.environ.get("SKISNOW_CACHE_DIR")
    os.environ["SKISNOW_CACHE_DIR"] = str(tmp_path_factory.mktemp("skisnow-cache"))
    yield
    if old is None:
        os.environ.pop("SKISNOW_CACHE_DIR", None)
    else:
        os.environ["SKISNOW_CACHE_DIR"] = old


def _chromium():
    import shutil

    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    chromedriver = shutil.which("chromedriver")
    if not (chromium and chromedriver):
        pytest.skip(
            "Debian's chromium and chromium-driver are not installed (.ci/run installs them)"
        )
    webdriver = pytest.importorskip("selenium.webdriver")
    from selenium.webdriver.chrome.service import Service

    opts = webdriver.ChromeOptions()
    opts.binary_location = chromium
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-quic",
                "--no-first-run", "--disable-background-networking", "--disable-sync",
                "--disable-component-update", "--window-size=420,900"):  # fmt: skip
        opts.add_argument(arg)  # a phone-sized window
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service(chromedriver), options=opts)


@pytest.fixture
def make_browser():
    """A function that starts Debian's ``chromium`` through ``chromedriver`` with Selenium
    (never a downloaded browser or driver; the caller quits it), or skips saying why where
    either is absent. The browser console is logged (``driver.get_log("browser")``)."""
    return _chromium
