"""Training the camber network (Kalliorinne et al. 2023, section 3.1) from any bench table.

The procedure follows what the paper's MATLAB toolbox does by default, adapted so that it is
reproducible and honest about its error:

* inputs and output mapped to [-1, 1] (``mapminmax``);
* whole **load conditions** (one bench profile each) are held out for validation, never random
  points -- a network must be judged on load cases it has not seen;
* first-order warm-up with Adam (optax) on all training points, then a second-order finish with
  Levenberg–Marquardt (MATLAB's default ``trainlm``) via :class:`optimistix.LevenbergMarquardt`
  on the residual vector of a subsample of the training points (the Jacobian is
  ``n_points × n_parameters``; ``lm_points`` bounds its size), with early stopping on the
  held-out conditions (the parameters with the lowest validation error are kept);
* everything is seeded (split, initial weights, subsample).

Residuals near contact (bench height below ``contact_height``) can be weighted up
(``contact_weight``): the contact solver is sensitive to µm there, not at the raised tip.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from skisnow._errors import ConvergenceError, InputError, SolverStatus
from skisnow.bench import BenchData
from skisnow.network._bench_split import _bench_table, bench_sha256, split_conditions
from skisnow.network._jax import jax, jnp, optax, ravel_pytree
from skisnow.network._levenberg_marquardt import make_lm_step
from skisnow.network._network import (
    Architecture,
    BlockNetwork,
    CamberNetwork,
    Domain,
    ReferenceProfile,
    Scaling,
    x64,
)

__all__ = ["TrainingProgress", "train_network"]


@dataclass(frozen=True, kw_only=True)
class TrainingProgress:
    """Reported to the ``progress`` callback after every reporting step.

    ``phase`` is ``'adam'`` or ``'lm'``; errors are in µm: ``train_rms_um`` on the (scaled-back)
    training residuals, ``val_mean_um`` / ``val_max_um`` the mean / max |error| on the held-out
    load conditions (clipped at 0 like a prediction).
    """

    member: int
    n_members: int
    phase: str
    step: int
    total: int
    train_rms_um: float
    val_mean_um: float
    val_max_um: float


def _loss_weights(height: np.ndarray, contact_height: float, contact_weight: float) -> np.ndarray:
    return np.where(height < contact_height, contact_weight, 1.0)


def train_network(
    bench: BenchData | pd.DataFrame,
    *,
    seed: int = 0,
    architecture: Architecture | Sequence[int] | str | None = None,
    validation_fraction: float = 0.15,
    adam_steps: int = 600,
    adam_learning_rate: float = 1e-2,
    lm_steps: int = 200,
    lm_points: int = 3000,
    adam_points: int = 20000,
    patience: int = 25,
    contact_height: float = 0.2e-3,
    contact_weight: float = 4.0,
    reference_profile: bool = True,
    mass_scaled_output: bool = False,
    ensemble: int = 1,
    first_member: int = 0,
    initial: CamberNetwork | None = None,
    time_limit: float | None = None,
    progress: Callable[[TrainingProgress], None] | None = None,
    report_every: int = 50,
    raise_on_failure: bool = False,
) -> CamberNetwork:
    """Train the block network h = f(x, m, x_m) on a bench table.

    Kalliorinne et al. (2023), eq. 1 and Figure 3; MATLAB's ``trainlm`` procedure (see the
    module docstring).

    Parameters
    ----------
    bench
        :class:`skisnow.bench.BenchData` (or its ``table``): columns ``ski, mass_kg,
        load_position_mm, x_mm, height_mm``, one ski, several load conditions.
    seed
        Seeds the validation split, the initial weights and the LM subsample.
    architecture
        Widths (:class:`Architecture`, six integers or ``"6,16,16,16,12,12"``).
    validation_fraction
        Share of the load conditions held out (whole profiles).
    adam_steps, adam_learning_rate, adam_points
        The first-order phase (full batch of at most
        ``adam_points`` training points, evenly thinned; cosine-decayed learning rate).
    lm_steps, lm_points
        The Levenberg–Marquardt phase: at most ``lm_steps`` steps on at most
        ``lm_points`` training points (the Jacobian is ``lm_points × n_parameters`` float64).
    patience
        Stop LM after this many steps without a better held-out mean error.
    contact_height, contact_weight
        Residuals where the bench height is below
        ``contact_height`` [m] are weighted by ``contact_weight`` (1 = plain least squares;
        default 4, i.e. twice the residual, as the shipped networks were trained).
    reference_profile
        Learn ``h - h_ref(x)`` with ``h_ref`` the mean training profile (an
        x-dependent output scaling, see :class:`ReferenceProfile`); ``False`` = the paper's
        plain network on ``h``.
    mass_scaled_output
        Learn the deflection per kilogram ``(h - h_0(x)) / m`` with ``h_0`` the unloaded
        profile extrapolated from the two lightest bench masses
        (:meth:`ReferenceProfile.unloaded`; issue 30, fifth pass); the residuals are weighted by
        ``m`` so that the loss stays in heights. Needs ``reference_profile``.
    ensemble
        Number of members (different initial weights); the spread of their predictions is
        reported by :meth:`CamberNetwork.predict_with_spread`.
    first_member
        Train members ``first_member, ..., first_member + ensemble - 1`` of the seed's ensemble
        (same split, scaling and reference; member k's initial weights and LM subsample are
        those it has in a larger ensemble): adds members to a network trained earlier on the
        same bench with the same seed (issue 30, fifth pass).
    initial
        Start from these members instead of random weights (a network trained with the same
        seed on the same bench, possibly widened by :func:`skisnow.network.widen_network`; its
        architecture is used, its scaling and reference must be the ones this bench and seed
        give, and ``ensemble`` its member count).
    time_limit
        Wall-clock budget [s] of each member's Levenberg–Marquardt phase (``None``: none). A
        phase cut by it ends like one cut by ``lm_steps``: status ``MAX_STEPS_REACHED``, its
        best held-out parameters kept, the reason in ``metadata["stopped_by"]``.
    progress
        Called with a :class:`TrainingProgress` every ``report_every`` Adam steps and
        every LM step.
    raise_on_failure
        Raise :class:`~skisnow.ConvergenceError` (carrying the network as
        ``.result``) unless the training status is ``SUCCESSFUL``.

    Returns
    -------
    CamberNetwork
        Its ``metadata`` holds the ski, the bench sha256, the seed, the held-out conditions,
        the held-out errors in µm (mean, p95, max, mean where h < 0.2 mm), the training time in
        seconds, the bench plan (its masses and positions), why each member's LM phase stopped
        (``stopped_by``: ``patience``, ``no_decrease``, ``step_limit``, ``time_limit``,
        ``nonfinite``), and the training ``status`` (see :attr:`CamberNetwork.status`):
        ``SUCCESSFUL`` when every member stopped on a criterion (early stopping on the held-out
        conditions, or Levenberg–Marquardt finding no step that lowers the error, MATLAB's
        "maximum mu reached"), ``MAX_STEPS_REACHED`` when a member used its whole step budget
        (``lm_steps``, or Adam alone when ``lm_steps=0``), ``NONFINITE`` when NaN/inf appeared
        (that member's last finite parameters are kept).

    Raises
    ------
    FileFormatError
        The table fails the bench validation (:func:`skisnow.bench.validate_bench_table`).
    InputError
        Several skis, fewer than 3 load conditions, or invalid options.
    ConvergenceError
        See ``raise_on_failure``.
    """
    t0 = time.perf_counter()
    table = _bench_table(bench)
    if initial is not None:
        arch = initial.architecture
    elif isinstance(architecture, Architecture):
        arch = architecture
    elif architecture is None:
        arch = Architecture()
    else:
        arch = Architecture.from_widths(architecture)
    if not 0 < validation_fraction < 1:
        raise InputError(f"validation_fraction must be in (0, 1), got {validation_fraction}")
    if ensemble < 1:
        raise InputError(f"ensemble must be >= 1, got {ensemble}")
    if adam_steps < 0 or lm_steps < 0:
        raise InputError("adam_steps and lm_steps must be >= 0")
    if time_limit is not None and not time_limit > 0:
        raise InputError(f"time_limit must be > 0 seconds (or None), got {time_limit}")

    x = table["x_mm"].to_numpy(float) * 1e-3
    m = table["mass_kg"].to_numpy(float)
    p = table["load_position_mm"].to_numpy(float) * 1e-3
    h = table["height_mm"].to_numpy(float) * 1e-3
    conds, cond_index = np.unique(np.stack([m, p], axis=1), axis=0, return_inverse=True)
    cond_index = cond_index.ravel()
    if len(conds) < 3:
        raise InputError(f"bench has {len(conds)} load condition(s); at least 3 are needed")
    val_cond = split_conditions(
        conds[:, 0], conds[:, 1], validation_fraction=validation_fraction, seed=seed
    )
    is_val = val_cond[cond_index]
    tr, va = ~is_val, is_val

    if mass_scaled_output and not reference_profile:
        raise InputError("mass_scaled_output needs reference_profile=True")
    if mass_scaled_output:
        reference = ReferenceProfile.unloaded(x[tr], m[tr], p[tr], h[tr])
    elif reference_profile:
        reference = ReferenceProfile.mean_of_profiles(x[tr], h[tr], cond_index[tr])
    else:
        reference = None
    target = h - reference(x) if reference is not None else h
    # the output's multiplier (h = h_ref + mult · network) and the loss weights in heights
    mult = m if mass_scaled_output else np.ones_like(m)
    m_ref = float(np.mean(m[tr])) if mass_scaled_output else 1.0
    target = target / mult
    scaling = Scaling.from_data(x[tr], m[tr], p[tr], target[tr])
    domain = Domain(
        mass_min=float(m.min()),
        mass_max=float(m.max()),
        position_min=float(p.min()),
        position_max=float(p.max()),
        x_min=float(x.min()),
        x_max=float(x.max()),
    )
    if initial is not None and not (
        initial.scaling == scaling
        and len(initial.members) == ensemble
        and (initial.reference is None) == (reference is None)
        and (reference is None or np.array_equal(initial.reference.height, reference.height))
    ):
        raise InputError(
            "initial network: its scaling, reference profile or member count is not the one "
            "this bench, seed and ensemble give (trained on another bench or split?)"
        )
    xs, ms, ps = scaling.scale_inputs(x, m, p)
    hs = scaling.scale_height(target)
    w = _loss_weights(h, contact_height, contact_weight) * (mult / m_ref) ** 2

    rng = np.random.default_rng(seed)
    if first_member < 0:
        raise InputError(f"first_member must be >= 0, got {first_member}")
    member_seeds = rng.integers(0, 2**31 - 1, size=first_member + ensemble)[first_member:]
    members = []
    histories = []
    with x64():
        data_all = tuple(jnp.asarray(a[tr]) for a in (xs, ms, ps, hs, w))
        ref_va = reference(x[va]) if reference is not None else np.zeros(int(va.sum()))
        data_va = tuple(jnp.asarray(a) for a in (xs[va], ms[va], ps[va], h[va], ref_va, mult[va]))
        # LM subsample: every k-th training point (a stratified, deterministic thinning) with
        # a seeded offset, so that every training condition and the whole ski are represented.
        n_tr = int(tr.sum())
        stride = max(1, int(np.ceil(n_tr / max(lm_points, 1))))
        a_stride = max(1, int(np.ceil(n_tr / max(adam_points, 1))))
        for k, mseed in enumerate(member_seeds):
            offset = int(np.random.default_rng(mseed).integers(stride))
            sub = np.arange(offset, n_tr, stride)
            data_lm = tuple(a[sub] for a in data_all)
            data_tr = tuple(a[offset % a_stride :: a_stride] for a in data_all)
            member, hist = _train_member(
                arch,
                scaling,
                m_ref,
                data_tr,
                data_lm,
                data_va,
                key=jax.random.PRNGKey(int(mseed)),
                initial=None if initial is None else initial.members[k],
                adam_steps=adam_steps,
                adam_learning_rate=adam_learning_rate,
                lm_steps=lm_steps,
                patience=patience,
                time_limit=time_limit,
                progress=progress,
                report_every=report_every,
                member_index=k,
                n_members=ensemble,
            )
            members.append(member)
            histories.append(hist)

    net = CamberNetwork(
        architecture=arch,
        scaling=scaling,
        domain=domain,
        members=tuple(members),
        reference=reference,
    )
    # Held-out errors of the final (ensemble-mean, clipped) prediction, in µm.
    err = np.empty(0)
    near = np.empty(0, dtype=bool)
    for c in np.flatnonzero(val_cond):
        rows = cond_index == c
        pred = net.predict(x[rows], conds[c, 0], conds[c, 1], on_domain_error="ignore")
        err = np.concatenate([err, np.abs(pred - h[rows])])
        near = np.concatenate([near, h[rows] < 0.2e-3])
    errors = {
        "mean_um": float(1e6 * err.mean()),
        "p95_um": float(1e6 * np.percentile(err, 95)),
        "max_um": float(1e6 * err.max()),
        "near_contact_mean_um": float(1e6 * err[near].mean()) if near.any() else None,
    }
    metadata = {
        "ski": str(table["ski"].iloc[0]),
        "training_data_sha256": bench_sha256(table),
        "seed": int(seed),
        "n_conditions": len(conds),
        "n_points": len(table),
        "bench_masses_kg": [float(v) for v in np.unique(conds[:, 0])],
        "bench_positions_mm": [float(1e3 * v) for v in np.unique(conds[:, 1])],
        "validation_conditions": [
            {"mass_kg": float(cm), "load_position_mm": float(1e3 * cp)}
            for cm, cp in conds[val_cond]
        ],
        "validation_errors": errors,
        "options": {
            "adam_steps": adam_steps,
            "adam_learning_rate": adam_learning_rate,
            "lm_steps": lm_steps,
            "lm_points": lm_points,
            "adam_points": adam_points,
            "patience": patience,
            "contact_height_m": contact_height,
            "contact_weight": contact_weight,
            "validation_fraction": validation_fraction,
            "reference_profile": reference_profile,
            "mass_scaled_output": mass_scaled_output,
            "time_limit_s": time_limit,
            "architecture": list(arch.widths),
            "ensemble": ensemble,
            "first_member": first_member,
            "initial": initial is not None,
        },
        "lm_steps_taken": [h_["lm_steps"] for h_ in histories],
        "stopped_by": [h_["stopped_by"] for h_ in histories],
        "status": _worst([h_["status"] for h_ in histories]).value,
        "member_status": [h_["status"].value for h_ in histories],
        "training_time_s": time.perf_counter() - t0,
    }
    result = dataclasses.replace(net, metadata=metadata)
    status = result.status
    if raise_on_failure and status is not None and not status.successful:
        raise ConvergenceError(
            f"training of the camber network for ski {metadata['ski']!r}: {status.message} "
            f"(members: {', '.join(metadata['member_status'])})",
            result=result,
        )
    return result


def _worst(statuses: Sequence[SolverStatus]) -> SolverStatus:
    """The status of an ensemble: the first member that did not succeed, else SUCCESSFUL."""
    return next((s for s in statuses if not s.successful), SolverStatus.SUCCESSFUL)


def _train_member(
    arch: Architecture,
    scaling: Scaling,
    m_ref: float,
    data_tr: tuple[jax.Array, ...],
    data_lm: tuple[jax.Array, ...],
    data_va: tuple[jax.Array, ...],
    *,
    key: jax.Array,
    initial: BlockNetwork | None,
    adam_steps: int,
    adam_learning_rate: float,
    lm_steps: int,
    patience: int,
    time_limit: float | None,
    progress: Callable[[TrainingProgress], None] | None,
    report_every: int,
    member_index: int,
    n_members: int,
) -> tuple[BlockNetwork, dict[str, Any]]:
    """Train one member: Adam, then Levenberg–Marquardt with early stopping.

    Returns the member (the parameters with the lowest held-out error in the LM phase) and a
    history ``{"lm_steps": steps taken, "status": SolverStatus, "stopped_by": reason}``.
    """
    model = BlockNetwork(arch, key=key) if initial is None else initial
    theta0, unravel = ravel_pytree(model)
    hscale = scaling.height_scale * m_ref  # residual units -> metres of height

    def residual(theta: jax.Array, data: tuple[jax.Array, ...]) -> jax.Array:
        xs, ms, ps, hs, w = data
        return jnp.sqrt(w) * (unravel(theta).points(xs, ms, ps) - hs)

    @jax.jit
    def val_errors(theta: jax.Array) -> tuple[jax.Array, jax.Array]:
        xs, ms, ps, h, ref, mult = data_va
        pred = scaling.unscale_height(unravel(theta).points(xs, ms, ps)) * mult + ref
        pred = jnp.maximum(pred, 0.0)
        e = jnp.abs(pred - h)
        return 1e6 * jnp.mean(e), 1e6 * jnp.max(e)

    def report(phase: str, step: int, total: int, rms: float, theta: jax.Array) -> None:
        if progress is None:
            return
        vm, vx = val_errors(theta)
        progress(
            TrainingProgress(
                member=member_index,
                n_members=n_members,
                phase=phase,
                step=step,
                total=total,
                train_rms_um=float(rms),
                val_mean_um=float(vm),
                val_max_um=float(vx),
            )
        )

    # ---- Adam (full batch, cosine-decayed learning rate)
    theta = theta0
    if adam_steps > 0:
        schedule = optax.cosine_decay_schedule(adam_learning_rate, adam_steps, alpha=1e-2)
        opt = optax.adam(schedule)
        opt_state = opt.init(theta)

        def loss(th: jax.Array) -> jax.Array:
            return jnp.mean(residual(th, data_tr) ** 2)

        @jax.jit
        def adam_chunk(th, st):
            def body(carry, _):
                th, st = carry
                value, g = jax.value_and_grad(loss)(th)
                upd, st = opt.update(g, st, th)
                return (optax.apply_updates(th, upd), st), value

            (th, st), values = jax.lax.scan(body, (th, st), None, length=report_every)
            return th, st, values[-1]

        done = 0
        while done < adam_steps:
            new_theta, opt_state, value = adam_chunk(theta, opt_state)
            if not (np.isfinite(float(value)) and bool(jnp.all(jnp.isfinite(new_theta)))):
                return unravel(theta), {
                    "lm_steps": 0,
                    "status": SolverStatus.NONFINITE,
                    "stopped_by": "nonfinite",
                }
            theta = new_theta
            done += report_every
            report("adam", min(done, adam_steps), adam_steps, hscale * 1e6 * np.sqrt(value), theta)

    # ---- Levenberg–Marquardt with early stopping on held-out conditions
    lm_taken = 0
    # without LM, Adam ran its fixed budget: no stopping criterion was met
    status = SolverStatus.MAX_STEPS_REACHED
    stopped_by = "step_limit"
    if lm_steps > 0:
        t_lm = time.perf_counter()

        def point_residual(th: jax.Array, *point: jax.Array) -> jax.Array:
            return residual(th, tuple(v[None] for v in point))[0]

        lm_step = make_lm_step(lambda th: residual(th, data_lm), point_residual, data_lm)
        mu = jnp.asarray(1e-3)
        best_theta, best_val = theta, float(val_errors(theta)[0])
        since = 0
        for step in range(1, lm_steps + 1):
            theta, mu, rms, accepted = lm_step(theta, mu)
            lm_taken = step
            vm = float(val_errors(theta)[0])
            if not (np.isfinite(vm) and np.isfinite(float(rms))):
                status, stopped_by = SolverStatus.NONFINITE, "nonfinite"
                break
            if vm < best_val:
                best_val, best_theta, since = vm, theta, 0
            else:
                since += 1
            report("lm", step, lm_steps, hscale * 1e6 * float(rms), theta)
            if not bool(accepted) or since >= patience:
                # no step lowers the error (mu at its maximum) or early stopping on the
                # held-out conditions: a stopping criterion of MATLAB's trainlm was met
                status = SolverStatus.SUCCESSFUL
                stopped_by = "no_decrease" if not bool(accepted) else "patience"
                break
            if time_limit is not None and time.perf_counter() - t_lm > time_limit:
                stopped_by = "time_limit"  # a budget, like lm_steps: MAX_STEPS_REACHED
                break
        theta = best_theta
    return unravel(theta), {"lm_steps": lm_taken, "status": status, "stopped_by": stopped_by}
