"""Whether a camber network's training converged, read from its metadata (no JAX needed)."""

from __future__ import annotations

from typing import Any

__all__ = ["training_converged"]


def training_converged(meta: dict[str, Any]) -> tuple[bool, str | None]:
    """Whether a training converged, from its metadata, and if not why (naming the limit).

    Converged: every member stopped on a stopping criterion — early stopping (``patience``
    Levenberg–Marquardt steps without a lower held-out error) or no step lowering the error
    (status ``successful``). Not converged: a member was stopped by its step or time limit
    (``--lm-steps``; ``--adam-steps`` alone when ``--lm-steps 0``; ``time_limit``) or by a
    non-finite value. The message names the limit and the network's held-out error, by which a
    network stopped early is judged (it is written either way).
    """
    if meta["status"] == "successful":
        return True, None
    opts = meta["options"]
    stops = list(meta["stopped_by"])
    limits = {
        "step_limit": (
            f"its step limit (--lm-steps {opts['lm_steps']})"
            if opts["lm_steps"] > 0
            else f"its step limit (--adam-steps {opts['adam_steps']}, no LM phase: --lm-steps 0)"
        ),
        "time_limit": f"its time limit ({opts['time_limit_s']} s per member's LM phase)",
        "nonfinite": "a non-finite value (its last finite weights are kept)",
    }
    which = next((s for s in stops if s in limits), stops[0] if stops else "step_limit")
    members = sum(s == which for s in stops)
    err = meta["validation_errors"]
    return False, (
        f"the training was stopped by {limits.get(which, which)} before its stopping criterion "
        f"(early stopping: {opts['patience']} LM steps without a lower held-out error) was met"
        f"{f' in {members} of {len(stops)} members' if len(stops) > 1 else ''}: not converged; "
        f"the network is written, its held-out error: mean {err['mean_um']:.3g} µm, p95 "
        f"{err['p95_um']:.3g} µm, max {err['max_um']:.3g} µm"
    )
