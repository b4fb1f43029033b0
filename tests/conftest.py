"""Shared test fixtures."""

from __future__ import annotations

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared"

#: Prefix of the session's temporary root on a RAM file system (see pytest_configure).
_RAM_ROOT = "skisnow-pytest-"


def pytest_configure(config: pytest.Config) -> None:
    _ram_basetemp(config)
    _start_numba_warm(config)
    _jax_compilation_cache(config)


def _ram_basetemp(config: pytest.Config) -> None:
    """The session's temporary files (``tmp_path``) on the RAM file system ``/dev/shm``, where
    the system has one (writable, at least 1 GiB free; the same rule as the explorer's store,
    :func:`skisnow._atomic.scratch_directory`), unless ``--basetemp`` is given.

    The tests write real stores, files and folders there and check the same things; only the
    disk is faster: on this project's machines unlinking a file on disk took ~3.5 ms (a
    removed 58-file Zarr skeleton 0.2 s, against 1-5 ms in RAM), and the kill-point test,
    which creates and removes 101 stores, took 37 s against 18 s (load 10). One root per
    session (``/dev/shm/skisnow-pytest-PID``, several engineers' suites may run at once),
    removed at the end; roots of sessions that ended without removing theirs are removed
    first."""
    import os
    import shutil

    from skisnow._atomic import _alive, _ram_disk

    if config.option.basetemp is not None or os.environ.get("SKISNOW_TEST_DISK_TMP"):
        return
    ram = _ram_disk()
    if ram is None:
        return
    for entry in Path(ram).glob(f"{_RAM_ROOT}*"):
        pid = entry.name[len(_RAM_ROOT) :].removesuffix("-jax")
        if pid.isdigit() and not _alive(int(pid)):
            shutil.rmtree(entry, ignore_errors=True)
    config.option.basetemp = str(Path(ram) / f"{_RAM_ROOT}{os.getpid()}")
    config._skisnow_ram_root = config.option.basetemp  # type: ignore[attr-defined]


def _start_numba_warm(config: pytest.Config) -> None:
    """Compile the numba kernels a fresh clone has not cached yet, once, before the tests run.

    With no numba cache (a fresh clone: ``cache=True`` writes beside the sources), each of the
    two xdist workers compiled the contact's and the bearing model's kernels itself (~11 s and
    ~6 s of CPU each, measured with an empty cache), and every CLI subprocess started before a
    worker had written the cache compiled them again. Here the session's first process starts
    one process per group of kernels (``tests/_numba_warm.py``: the contact's; the bearing
    model's and identification's) while the workers start and collect, and the tests are handed
    out once they have written the cache (see ``_wait_for_numba_warm``); every process of the
    suite then loads the kernels from it. Nothing is started where every kernel of a group is
    cached and newer than its source, or with ``SKISNOW_TEST_NO_WARM=1``. The kernels are
    numba's compilations of the same sources: no test computes anything differently."""
    import contextlib
    import os
    import subprocess
    import sys

    if hasattr(config, "workerinput") or os.environ.get("SKISNOW_TEST_NO_WARM"):
        return  # an xdist worker (its controller warms), or not wanted
    import _numba_warm

    src = REPO / "src" / "skisnow"
    procs = []
    for groups in (("contact",), ("micro", "identify")):
        todo = [g for g in groups if not _numba_warm.cached(g, src)]
        if todo:
            # an OSError is only slower: the workers compile what they need, as before
            with contextlib.suppress(OSError):
                procs.append(subprocess.Popen(
                    [sys.executable, _numba_warm.__file__, *todo], stdin=subprocess.DEVNULL,
                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                ))  # fmt: skip
    config._skisnow_numba_warm = procs  # type: ignore[attr-defined]


def _wait_for_numba_warm(config: pytest.Config) -> None:
    """Wait until the warming processes of :func:`pytest_configure` have ended (their exit
    status does not matter: a kernel they did not cache is compiled where it is needed; one
    still running after 5 minutes is ended, and the tests start)."""
    import subprocess

    for proc in getattr(config, "_skisnow_numba_warm", []):
        try:
            proc.wait(timeout=300)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
    config._skisnow_numba_warm = []  # type: ignore[attr-defined]


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_node_collection_finished(node, ids) -> None:
    """(xdist controller) the workers have collected: hand out no test before the cache is."""
    _wait_for_numba_warm(node.config)


def pytest_collection_finish(session: pytest.Session) -> None:
    """(a serial run) the tests start after the cache is written."""
    _wait_for_numba_warm(session.config)


def _jax_compilation_cache(config: pytest.Config) -> None:
    """One JAX compilation cache on disk for the session's processes (the xdist workers, the CLI
    subprocesses), removed at the end; unless ``JAX_COMPILATION_CACHE_DIR`` is set already.

    ``train_network`` jits closures over its data, so each call compiles again; a computation
    compiled before with the same program and data (a seed trained twice, the session fixture's
    network trained on both workers) is then read from the cache: JAX keys an entry by the
    program, the compile options and the backend, and the executable read back is the one
    compiled, so every result is the same to the bit (``tests/network`` 38.4 s -> 34.7 s of
    CPU serially; the reproducibility test 6.8 -> 4.7 s). Every compilation is cached (no
    minimum compile time). Set in the session's first process before JAX is imported; workers
    and subprocesses inherit the environment."""
    import os
    import tempfile

    if hasattr(config, "workerinput") or os.environ.get("JAX_COMPILATION_CACHE_DIR"):
        return
    ram = getattr(config, "_skisnow_ram_root", None)
    d = Path(ram).parent if ram else Path(tempfile.gettempdir())
    d = d / f"{_RAM_ROOT}{os.getpid()}-jax"  # removed with the stale roots if left behind
    d.mkdir(exist_ok=True)
    os.environ["JAX_COMPILATION_CACHE_DIR"] = str(d)
    os.environ["JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS"] = "0"
    config._skisnow_jax_cache = d  # type: ignore[attr-defined]


def pytest_unconfigure(config: pytest.Config) -> None:
    import os
    import shutil

    jax_cache = getattr(config, "_skisnow_jax_cache", None)
    if jax_cache is not None:
        shutil.rmtree(jax_cache, ignore_errors=True)
        for name in ("JAX_COMPILATION_CACHE_DIR", "JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS"):
            os.environ.pop(name, None)

    for proc in getattr(config, "_skisnow_numba_warm", []):  # a session that ended early
        proc.kill()
        proc.wait()

    root = getattr(config, "_skisnow_ram_root", None)
    if root is not None:
        shutil.rmtree(root, ignore_errors=True)


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
