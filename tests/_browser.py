"""Helpers of the browser tests (the browser itself is the ``make_browser`` fixture of
``tests/conftest.py``)."""

from __future__ import annotations

import time

import pytest


def wait_ready(driver) -> None:  # type: ignore[no-untyped-def]
    """Wait (up to 10 s) until a skisnow page has decoded its data (``body[data-ready=1]``);
    fail the test if it never does."""
    for _ in range(100):
        if driver.execute_script("return document.body.dataset.ready") == "1":
            return
        time.sleep(0.1)
    pytest.fail("the page did not finish decoding its data")
