"""The camber network: the block-architecture neural network h = f(x, m, x_m) (eq. 1).

Kalliorinne et al. (2023), section 3.1 and Figure 3, replace one bench measurement per load case by
a small artificial neural network trained on a whole measurement sequence. Its inputs are the
coordinate along the ski ``x`` (0 at the balance point) and the load condition -- the mass ``m``
and its position ``x_m`` -- and its output is the camber height ``h`` (eq. 1). The paper's
MATLAB network has seven fully connected hidden layers in four blocks:

1. *load condition*: one tanh ("tansig") layer on (m, x_m);
2. *ski collapse*: three tanh layers; the first is fed by x **and** the load block;
3. *ski camber*: two tanh layers fed by x **only** (independent of the load);
4. *prediction*: one linear ("purelin") layer on the collapse and camber outputs together.

This module reproduces that wiring (:class:`BlockNetwork`, an Equinox module) with configurable
widths (:class:`Architecture`). As in MATLAB (``mapminmax``), every input and the output are
mapped linearly to [-1, 1] over the training data; the map (:class:`Scaling`) and the trained
(m, x_m) range (:class:`Domain`) are stored with the model (both in
:mod:`skisnow.network._scaling`). :class:`CamberNetwork` bundles one or
a few trained members (an ensemble: the mean is the prediction, the spread an uncertainty).

Units: SI inside (x, x_m, h in metres, m in kg). The camber height is the gap between the ski
base and the rigid bench plane, so it is never negative; predictions are clipped at 0 by default
(the linear prediction layer can dip a few µm below 0 in the contact zones where the truth is 0).

JAX runs in float64 here, but only inside this module's functions (``jax.enable_x64`` as a
context manager): importing skisnow never flips JAX's global configuration for other code.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from skisnow._checks import check_value
from skisnow._errors import DomainWarning, InputError, SolverStatus
from skisnow.network._jax import eqx, jax, jnp
from skisnow.network._scaling import Domain, ReferenceProfile, Scaling

__all__ = [
    "Architecture",
    "BlockNetwork",
    "CamberNetwork",
    "Domain",
    "ReferenceProfile",
    "Scaling",
    "x64",
]


def x64():
    """Context manager: float64 JAX inside, the caller's configuration restored outside."""
    return jax.enable_x64(True)


# --------------------------------------------------------------------------------------------
# Architecture, scaling, domain


@dataclass(frozen=True, kw_only=True)
class Architecture:
    """Widths of the paper's four blocks (Figure 3): 1 + 3 + 2 tanh layers and 1 linear layer.

    ``load``: neurons of the load-condition layer; ``collapse``: the three ski-collapse layers;
    ``camber``: the two ski-camber layers. The prediction layer has one output.
    """

    load: int = 6
    collapse: tuple[int, int, int] = (16, 16, 16)
    camber: tuple[int, int] = (12, 12)

    def __post_init__(self) -> None:
        widths = self.widths
        if len(self.collapse) != 3 or len(self.camber) != 2:
            raise InputError(
                "architecture needs 3 collapse and 2 camber widths (Kalliorinne et al. 2023, "
                f"Figure 3); "
                f"got collapse={self.collapse}, camber={self.camber}"
            )
        if any((not isinstance(w, (int, np.integer))) or w < 1 for w in widths):
            raise InputError(f"layer widths must be positive integers, got {widths}")

    @property
    def widths(self) -> tuple[int, ...]:
        """The six hidden widths in the order load, collapse ×3, camber ×2."""
        return (self.load, *self.collapse, *self.camber)

    @classmethod
    def from_widths(cls, widths: Sequence[int] | str) -> Architecture:
        """Six widths ``load, c1, c2, c3, k1, k2`` (sequence or ``"6,16,16,16,12,12"``)."""
        if isinstance(widths, str):
            try:
                widths = [int(w) for w in widths.replace(" ", "").split(",") if w]
            except ValueError:
                raise InputError(
                    f"widths must be six comma-separated integers (load, 3 collapse, 2 camber), "
                    f"got {widths!r}"
                ) from None
        widths = [int(w) for w in widths]
        if len(widths) != 6:
            raise InputError(
                "widths must be six integers: load, collapse1, collapse2, collapse3, camber1, "
                f"camber2 (Kalliorinne et al. 2023, Figure 3); got {len(widths)}: {widths}"
            )
        return cls(load=widths[0], collapse=tuple(widths[1:4]), camber=tuple(widths[4:6]))

    def n_parameters(self) -> int:
        """Number of trainable weights and biases of one member."""
        n = 3 * self.load  # 2 inputs + bias
        prev = 1 + self.load
        for w in self.collapse:
            n += (prev + 1) * w
            prev = w
        prev = 1
        for w in self.camber:
            n += (prev + 1) * w
            prev = w
        return n + self.collapse[-1] + self.camber[-1] + 1


# --------------------------------------------------------------------------------------------
# The block network (Equinox)


class BlockNetwork(eqx.Module):
    """One member: the paper's 4-block network (Figure 3) on scaled inputs, scaled output.

    All hidden layers use tanh (MATLAB's ``tansig``), the prediction layer is linear
    (``purelin``). The x input enters the first collapse layer and the first camber layer; the
    load condition (m, x_m) enters only the load-condition layer, whose output feeds the first
    collapse layer. Hence the camber block is a function of x alone (tested).
    """

    load: eqx.nn.Linear
    collapse: tuple[eqx.nn.Linear, eqx.nn.Linear, eqx.nn.Linear]
    camber: tuple[eqx.nn.Linear, eqx.nn.Linear]
    prediction: eqx.nn.Linear

    def __init__(self, architecture: Architecture, *, key: jax.Array) -> None:
        a = architecture
        keys = jax.random.split(key, 7)
        f64 = jnp.float64
        self.load = eqx.nn.Linear(2, a.load, key=keys[0], dtype=f64)
        c_in = (1 + a.load, a.collapse[0], a.collapse[1])
        self.collapse = tuple(
            eqx.nn.Linear(i, o, key=k, dtype=f64)
            for i, o, k in zip(c_in, a.collapse, keys[1:4], strict=True)
        )
        k_in = (1, a.camber[0])
        self.camber = tuple(
            eqx.nn.Linear(i, o, key=k, dtype=f64)
            for i, o, k in zip(k_in, a.camber, keys[4:6], strict=True)
        )
        self.prediction = eqx.nn.Linear(
            a.collapse[-1] + a.camber[-1], "scalar", key=keys[6], dtype=f64
        )

    # Layers by name: what a model file stores (see skisnow.network.save_network).
    def layers(self) -> list[tuple[str, eqx.nn.Linear]]:
        """The seven layers as ``(name, layer)``: ``load``, ``collapse0..2``, ``camber0..1``,
        ``prediction`` (the names of the model file's arrays)."""
        return [
            ("load", self.load),
            *[(f"collapse{i}", layer) for i, layer in enumerate(self.collapse)],
            *[(f"camber{i}", layer) for i, layer in enumerate(self.camber)],
            ("prediction", self.prediction),
        ]

    @classmethod
    def layer_shapes(cls, architecture: Architecture) -> dict[str, tuple[tuple[int, ...], ...]]:
        """``{name: (weight shape, bias shape)}`` of a member with ``architecture``."""
        with x64():
            template = eqx.filter_eval_shape(cls, architecture, key=jax.random.PRNGKey(0))
        return {name: (layer.weight.shape, layer.bias.shape) for name, layer in template.layers()}

    @classmethod
    def from_layer_arrays(
        cls, architecture: Architecture, arrays: Mapping[str, tuple[np.ndarray, np.ndarray]]
    ) -> BlockNetwork:
        """A member whose layers hold ``arrays[name] = (weight, bias)`` (float64, the shapes of
        :meth:`layer_shapes`; the caller checks them)."""
        with x64():
            # shapes only (no random initialisation to run and compile: measured 3.4 s of a 4 s
            # load); every leaf is replaced by a stored array below
            member = eqx.filter_eval_shape(cls, architecture, key=jax.random.PRNGKey(0))
            for name, _ in member.layers():
                weight, bias = (jnp.asarray(a, dtype=jnp.float64) for a in arrays[name])

                def where(m: BlockNetwork, name: str = name) -> tuple[jax.Array, jax.Array]:
                    layer = dict(m.layers())[name]
                    return layer.weight, layer.bias

                member = eqx.tree_at(where, member, (weight, bias))
        return member

    # Blocks on batches: rows are points (or load cases), columns are neurons.
    def load_block(self, load: jax.Array) -> jax.Array:
        """Block 1: (k, 2) scaled (m, x_m) → (k, n_load)."""
        return jnp.tanh(load @ self.load.weight.T + self.load.bias)

    def camber_block(self, xs: jax.Array) -> jax.Array:
        """Block 3: (n,) scaled x → (n, n_camber2); depends on x only."""
        first, second = self.camber
        a = jnp.tanh(xs[:, None] * first.weight[:, 0] + first.bias)
        return jnp.tanh(a @ second.weight.T + second.bias)

    def _collapse_first(self, xs: jax.Array, load_features: jax.Array) -> jax.Array:
        w = self.collapse[0].weight  # columns: [x, load features...]
        return xs[..., None] * w[:, 0] + load_features @ w[:, 1:].T + self.collapse[0].bias

    def _collapse_rest(self, a: jax.Array) -> jax.Array:
        a = jnp.tanh(a)
        for layer in self.collapse[1:]:
            a = jnp.tanh(a @ layer.weight.T + layer.bias)
        return a

    def _predict(self, collapse: jax.Array, camber: jax.Array) -> jax.Array:
        n_c = collapse.shape[-1]
        w = self.prediction.weight  # (1, n_c + n_k)
        return collapse @ w[0, :n_c] + camber @ w[0, n_c:] + self.prediction.bias[0]

    def points(self, xs: jax.Array, ms: jax.Array, ps: jax.Array) -> jax.Array:
        """Scaled output at scattered points (all (N,), scaled) → (N,)."""
        lf = self.load_block(jnp.stack([ms, ps], axis=-1))
        collapse = self._collapse_rest(self._collapse_first(xs, lf))
        return self._predict(collapse, self.camber_block(xs))

    def grid(self, xs: jax.Array, ms: jax.Array, ps: jax.Array) -> jax.Array:
        """Scaled output on a grid: x (n,), load cases m, x_m (k,) → (k, n).

        The camber block runs once per x and the load block once per load case.
        """
        lf = self.load_block(jnp.stack([ms, ps], axis=-1))  # (k, L)
        w = self.collapse[0].weight
        pre = (
            xs[None, :, None] * w[:, 0] + (lf @ w[:, 1:].T)[:, None, :] + self.collapse[0].bias
        )  # (k, n, C1)
        collapse = self._collapse_rest(pre)
        return self._predict(collapse, self.camber_block(xs)[None, :, :])


@eqx.filter_jit
def _ensemble_grid(members: tuple[BlockNetwork, ...], xs, ms, ps) -> jax.Array:
    return jnp.stack([m.grid(xs, ms, ps) for m in members])


# --------------------------------------------------------------------------------------------
# The trained network


@dataclass(frozen=True, kw_only=True, eq=False)
class CamberNetwork:
    """A trained camber network: members (ensemble), scaling, trained domain and metadata.

    ``metadata`` holds the ski name, the sha256 of the training data, the seed, the measured
    errors (µm) on the held-out load conditions and the training time (see
    :func:`skisnow.network.train_network`).
    """

    architecture: Architecture
    scaling: Scaling
    domain: Domain
    members: tuple[BlockNetwork, ...]
    reference: ReferenceProfile | None = None
    metadata: Mapping[str, Any] = field(default_factory=dict)

    @property
    def ski(self) -> str | None:
        """Name of the ski the network was trained on (from the bench table)."""
        return self.metadata.get("ski")

    @property
    def status(self) -> SolverStatus | None:
        """How the training ended (:class:`~skisnow.SolverStatus`, from ``metadata["status"]``
        written by :func:`skisnow.network.train_network`); ``None`` for a network whose metadata
        does not say (trained before the status was recorded)."""
        value = self.metadata.get("status")
        return None if value is None else SolverStatus(value)

    def _raw(
        self,
        x: Any,
        mass: Any,
        load_position: Any,
        on_domain_error: Literal["warn", "raise", "ignore"],
    ) -> tuple[np.ndarray, bool]:
        x = np.asarray(x, dtype=float)
        if x.ndim != 1 or x.size == 0:
            raise InputError(
                f"x must be a non-empty 1-D array of positions [m], got shape {x.shape}"
            )
        m = np.asarray(mass, dtype=float)
        p = np.asarray(load_position, dtype=float)
        scalar = m.ndim == 0 and p.ndim == 0
        try:
            m, p = np.broadcast_arrays(np.atleast_1d(m), np.atleast_1d(p))
        except ValueError:
            raise InputError(
                f"mass {m.shape} and load_position {p.shape} must broadcast to one load-case axis"
            ) from None
        if m.ndim != 1:
            raise InputError(f"mass and load_position must be scalars or 1-D, got shape {m.shape}")
        for name, v in (("x", x), ("mass", m), ("load_position", p)):
            if not np.all(np.isfinite(v)):
                raise InputError(f"{name} must be finite (no NaN/inf)")
        if on_domain_error not in ("warn", "raise", "ignore"):
            raise InputError(
                f"on_domain_error must be 'warn', 'raise' or 'ignore', got {on_domain_error!r}"
            )
        bad = self.domain.violations(x, m, p)
        if bad and on_domain_error != "ignore":
            msg = (
                f"camber network for ski {self.ski!r} used outside its trained domain: "
                + "; ".join(bad)
            )
            if on_domain_error == "raise":
                raise InputError(msg)
            warnings.warn(msg + " (extrapolation; accuracy unknown)", DomainWarning, stacklevel=3)
        s = self.scaling
        xs, ms, ps = s.scale_inputs(x, m, p)
        # Pad to bucketed shapes (x: multiple of 256, cases: power of 2) so that one compiled
        # kernel serves many grid sizes and stride lengths; the padding is sliced off.
        n, k = xs.size, ms.size
        n_pad, k_pad = -(-n // 256) * 256, 1 << max(0, (k - 1).bit_length())
        xs_p = np.pad(xs, (0, n_pad - n), mode="edge")
        ms_p, ps_p = (
            np.pad(ms, (0, k_pad - k), mode="edge"),
            np.pad(ps, (0, k_pad - k), mode="edge"),
        )
        with x64():
            out = _ensemble_grid(
                self.members, jnp.asarray(xs_p), jnp.asarray(ms_p), jnp.asarray(ps_p)
            )
            out = np.asarray(out, dtype=float)[:, :k, :n]
        h = s.unscale_height(out)
        if self.reference is not None:
            if self.reference.mass_scaled:  # the network learned (h - h_0(x)) / m
                h = h * m[None, :, None]
            h = h + self.reference(x)
        if on_domain_error != "ignore":  # a derived quantity, checked where it is computed
            check_value(
                float(np.max(h)) * 1e3,
                "camber_height",
                where=f"camber network for ski {self.ski!r}: its highest predicted camber "
                "(a re-scaled or damaged model file?)",
            )
        return h, scalar

    def predict(
        self,
        x: Any,
        mass: Any,
        load_position: Any,
        *,
        on_domain_error: Literal["warn", "raise", "ignore"] = "warn",
        clip: bool = True,
    ) -> np.ndarray:
        """Camber height h = f(x, m, x_m) (Kalliorinne et al. 2023, eq. 1) [m] on the grid ``x``.

        Parameters
        ----------
        x
            Positions along the ski [m], 1-D, any resolution.
        mass, load_position
            The load condition(s): mass [kg] and position [m] from the balance
            point (positive toward the tip); scalars or 1-D arrays broadcast to k load cases.
        on_domain_error
            Outside the trained (m, x_m, x) range: ``'warn'`` (a
            :class:`~skisnow.DomainWarning`), ``'raise'`` (:class:`~skisnow.InputError`) or
            ``'ignore'``.
        clip
            Clip at 0 (the gap to the bench plane is never negative).

        Returns
        -------
        ndarray
            h [m], the ensemble mean: ``(n,)`` for a scalar load condition, ``(k, n)`` for k
            load cases.
        """
        h, scalar = self._raw(x, mass, load_position, on_domain_error)
        h = h.mean(axis=0)
        if clip:
            h = np.maximum(h, 0.0)
        return h[0] if scalar else h

    # The same parameters as predict on purpose (repeated, not shared): the two are one API, and
    # each signature documents its parameters where a reader looks.
    def predict_with_spread(
        self,
        x: Any,
        mass: Any,
        load_position: Any,
        *,
        on_domain_error: Literal["warn", "raise", "ignore"] = "warn",
        clip: bool = True,
    ) -> tuple[np.ndarray, np.ndarray]:
        """Like :meth:`predict`, plus the ensemble spread [m] (sample standard deviation of the
        members, 0 for a single member) as an uncertainty estimate of the same shape."""
        h, scalar = self._raw(x, mass, load_position, on_domain_error)
        if clip:
            h = np.maximum(h, 0.0)
        mean = h.mean(axis=0)
        spread = h.std(axis=0, ddof=1) if h.shape[0] > 1 else np.zeros_like(mean)
        return (mean[0], spread[0]) if scalar else (mean, spread)
