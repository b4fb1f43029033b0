"""JAX, Equinox and Optax, the camber network's optional dependencies (the ``network`` extra).

The main job (contact, maps, reports on the beam route) never needs them; building, loading or
training a network does. Importing this module imports them or raises
:class:`~skisnow._optional.MissingDependencyError` (the CLI's exit code 2) naming the extra.
"""

from __future__ import annotations

from skisnow._optional import require

_FEATURE = "the camber network (--profile-source network, training, the paper's network route)"

jax = require("jax", feature=_FEATURE)
jnp = require("jax.numpy", feature=_FEATURE)
eqx = require("equinox", feature=_FEATURE)
optax = require("optax", feature=_FEATURE)
ravel_pytree = require("jax.flatten_util", feature=_FEATURE).ravel_pytree

__all__ = ["eqx", "jax", "jnp", "optax", "ravel_pytree"]
