"""A ski carrying a posterior as an identified ski does (smooth modes of stated size): the
tests of the intervals carried to every answer (issue 25, item 4) need one without running an
identification."""

from __future__ import annotations

import dataclasses

import numpy as np


def with_posterior(ski, *, ei_sd: float = 0.03, z0_sd: float = 2e-6, k: int = 4, scale=1.0):
    """``ski`` carrying k smooth posterior modes (log EI sd ~``ei_sd``, z0 sd ~``z0_sd`` [m])."""
    ex, cx = np.asarray(ski.stiffness_x), np.asarray(ski.camber_x)
    u = (ex - ex[0]) / np.ptp(ex)
    v = (cx - cx[0]) / np.ptp(cx)
    me = np.array([ei_sd / np.sqrt(k) * np.sin((i + 1) * np.pi * u) for i in range(k)]) * scale
    mz = np.array([z0_sd / np.sqrt(k) * np.cos((i + 1) * np.pi * v) for i in range(k)]) * scale
    return dataclasses.replace(
        ski, stiffness_log_sd=tuple(np.sqrt(np.sum(me**2, axis=0))),
        camber_sd=tuple(np.sqrt(np.sum(mz**2, axis=0))),
        stiffness_modes=tuple(map(tuple, me)), camber_modes=tuple(map(tuple, mz)),
    )  # fmt: skip
