"""Figures of the micro contact: height map with its roughness, and A_fr(D) of the bearing model."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from skisnow.plot._style import new_figure, style

__all__ = ["bearing_figure", "topography_figure"]


def topography_figure(topo: Any, *, title: str = "") -> Figure:
    """Height map [µm] over x, y [µm] (x across the ski, y along it) and one line profile."""
    fig, ax = new_figure(2, 1, width=8.0, height=3.4)
    h = np.asarray(topo.heights) * 1e6
    nx, ny = h.shape
    with style():
        im = ax[0, 0].imshow(
            h.T,
            origin="lower",
            extent=(0, nx * topo.dx * 1e6, 0, ny * topo.dy * 1e6),
            cmap="cividis",
            aspect="equal",
        )
        fig.colorbar(im, ax=ax[0, 0], label="height [µm]")
        ax[0, 0].set_xlabel("x across the ski [µm]")
        ax[0, 0].set_ylabel("y along the ski [µm]")
        x = np.arange(nx) * topo.dx * 1e6
        ax[0, 1].plot(x, h[:, ny // 2], color="#1f5fbf")
        ax[0, 1].set_xlabel("x across the ski [µm]")
        ax[0, 1].set_ylabel("height [µm]")
        ax[0, 1].set_title("profile at mid-length")
        if title:
            fig.suptitle(title)
    return fig


def bearing_figure(
    diameters: np.ndarray,
    fractional_area: np.ndarray,
    *,
    reference: float | None = None,
    grain_density: Any = None,
    title: str = "",
) -> Figure:
    """A_fr(D) of the bearing model (Scherge et al. 2021, Fig. 6–7 style), p/H line and f(D)."""
    fig, ax = new_figure(1, 1, width=5.5, height=3.4)
    a = ax[0, 0]
    d_um = np.asarray(diameters) * 1e6
    with style():
        a.plot(d_um, fractional_area, "o-", color="#c0392b", ms=3, label="A_fr(D)")
        if reference is not None:
            a.axhline(reference, color="black", ls="--", lw=0.8, label="p/H (flat base)")
        a.set_xlabel("grain diameter D [µm]")
        a.set_ylabel("fractional contact area A_fr [-]")
        if grain_density is not None:
            b = a.twinx()
            dd = np.linspace(d_um.min(), d_um.max(), 200)
            b.plot(dd, grain_density(dd * 1e-6), color="0.5", lw=0.8)
            b.set_ylabel("f(D) (eq. 12)", color="0.4")
        a.legend(loc="best")
        if title:
            a.set_title(title)
    return fig
