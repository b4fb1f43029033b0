"""Markers for tests of optional features (extras of ``pyproject.toml``): CI installs every extra
(``.ci/run``); a user's clone without one skips its tests and says which extra to install."""

from __future__ import annotations

import importlib.util

import pytest

#: The camber network: JAX, Equinox, Optax (the ``network`` extra).
HAS_NETWORK = importlib.util.find_spec("jax") is not None
NETWORK_REASON = "the camber network needs the 'network' extra (uv sync --extra network)"
needs_network = pytest.mark.skipif(not HAS_NETWORK, reason=NETWORK_REASON)
