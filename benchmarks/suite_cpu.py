"""CPU seconds of every test of the suite (a pytest plugin): the measure of what a test costs
that a loaded machine does not inflate.

Wall-clock ``--durations`` grow with the load average (on this project's shared 2-core machine
a serial run took 751 s at load 6 for ~400 s of CPU); the CPU a test uses does not. For every
test phase (setup, call, teardown) this plugin records the CPU of the pytest process
(``time.process_time``) plus the CPU of the child processes it waited for
(``resource.getrusage(RUSAGE_CHILDREN)``: the CLI subprocesses, the documentation build, Dask
workers once reaped), and at the end prints the slowest tests, the sum over the suite, and
writes every figure to a JSON file for comparisons.

Run the suite serially (one process: per-test CPU is then the test's own, and the session's
start-up is reported apart)::

    PYTHONPATH=benchmarks uv run pytest -q -p no:randomly -n 0 -p suite_cpu \
        --suite-cpu-json suite_cpu.json --suite-cpu-top 40

Compare two such files (before / after)::

    uv run python benchmarks/suite_cpu.py before.json after.json

CPU of threads other than the main one is included (``process_time`` counts the whole
process); CPU of grandchildren not waited for by their parent is not (none in this suite).
"""

from __future__ import annotations

import json
import resource
import sys
import time
from collections import defaultdict

import pytest

_T0_WALL = time.perf_counter()
_T0_CPU = time.process_time()


def _children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def _cpu() -> float:
    return time.process_time() + _children_cpu()


_per_test: dict[str, dict[str, float]] = defaultdict(dict)
_session: dict[str, float] = {}


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("suite-cpu")
    group.addoption("--suite-cpu-json", default=None, help="write per-test CPU seconds here")
    group.addoption("--suite-cpu-top", type=int, default=30, help="print the N slowest tests")


def pytest_collection_finish(session: pytest.Session) -> None:
    _session["start_cpu"] = _cpu() - _T0_CPU
    _session["start_wall"] = time.perf_counter() - _T0_WALL


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_setup(item: pytest.Item):
    c0, w0 = _cpu(), time.perf_counter()
    yield
    _per_test[item.nodeid]["setup"] = _cpu() - c0
    _per_test[item.nodeid]["wall"] = time.perf_counter() - w0


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_call(item: pytest.Item):
    c0, w0 = _cpu(), time.perf_counter()
    yield
    _per_test[item.nodeid]["call"] = _cpu() - c0
    _per_test[item.nodeid]["wall"] += time.perf_counter() - w0


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_teardown(item: pytest.Item):
    c0, w0 = _cpu(), time.perf_counter()
    yield
    _per_test[item.nodeid]["teardown"] = _cpu() - c0
    _per_test[item.nodeid]["wall"] += time.perf_counter() - w0


def pytest_terminal_summary(terminalreporter, config: pytest.Config) -> None:
    if not _per_test:
        return
    total = {k: sum(v.get(p, 0.0) for p in ("setup", "call", "teardown"))
             for k, v in _per_test.items()}  # fmt: skip
    tr = terminalreporter
    top = config.getoption("--suite-cpu-top")
    tr.write_sep("=", f"CPU seconds per test (process + waited children), {top} slowest")
    for k, v in sorted(total.items(), key=lambda kv: -kv[1])[:top]:
        d = _per_test[k]
        tr.write_line(f"{v:7.2f} s  (setup {d.get('setup', 0):5.2f}, wall {d['wall']:6.2f})  {k}")
    s = sum(total.values())
    tr.write_line(
        f"sum over {len(total)} tests: {s:.1f} s CPU; start-up (imports, collection) "
        f"{_session.get('start_cpu', float('nan')):.1f} s CPU, "
        f"{_session.get('start_wall', float('nan')):.1f} s wall; whole session so far "
        f"{_cpu() - _T0_CPU:.1f} s CPU, {time.perf_counter() - _T0_WALL:.1f} s wall"
    )
    out = config.getoption("--suite-cpu-json")
    if out:
        with open(out, "w", encoding="utf-8") as f:
            json.dump({"session": _session, "tests": _per_test, "total": total}, f, indent=1)


def _compare(before: str, after: str, n: int = 40) -> None:
    from pathlib import Path

    a = json.loads(Path(before).read_text(encoding="utf-8"))["total"]
    b = json.loads(Path(after).read_text(encoding="utf-8"))["total"]
    print(f"{'before':>8} {'after':>8}  test")
    for k in sorted(set(a) | set(b), key=lambda k: -max(a.get(k, 0), b.get(k, 0)))[:n]:
        print(f"{a.get(k, float('nan')):8.2f} {b.get(k, float('nan')):8.2f}  {k}")
    print(f"{sum(a.values()):8.1f} {sum(b.values()):8.1f}  sum ({len(a)} / {len(b)} tests)")


if __name__ == "__main__":
    _compare(sys.argv[1], sys.argv[2], *(int(x) for x in sys.argv[3:4]))
