"""Figures of the technician workflows: a fleet overlaid, a ranking across snow, a load cycle
and its animation (Kalliorinne et al. 2023: loaded profile, apparent pressure, zones)."""

from __future__ import annotations

import shutil
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from skisnow._errors import InputError
from skisnow.plot._style import COLORS, ZONE_COLORS, ZONE_LABELS, new_figure, style

__all__ = ["animate_cycle", "plot_cycle", "plot_fleet", "plot_pairs", "plot_snow_ranking"]


def plot_fleet(comparison: Any) -> Figure:
    """Loaded profiles (top) and contact pressures (bottom) of every ski of a
    :class:`~skisnow.workflows.FleetComparison`, overlaid: full body weight solid, half dashed."""
    fig, axes = new_figure(1, 2, width=8.0, height=5.6, sharex=True)
    ax_h, ax_p = axes[0, 0], axes[1, 0]
    cycle = [f"C{i}" for i in range(10)]
    with style():
        for k, entry in enumerate(comparison.entries):
            color = cycle[k % len(cycle)]
            for load, ls in (("full", "-"), ("half", "--")):
                sol = entry.cases[load].solution
                x_mm = sol.x * 1e3
                # the profile as it lies on the snow: h − δ − θ(x − x_m) + u is the gap; show h
                ax_h.plot(x_mm, sol.height * 1e3, ls, color=color, lw=1.0)
                ax_p.plot(x_mm, sol.pressure * 1e-3, ls, color=color, lw=1.0)
            ax_h.plot([], [], "-", color=color, label=entry.ski.label)
            kz = entry.ski.ski.kick_zone
            if kz is not None:
                ax_p.axvspan(kz[0] * 1e3, kz[1] * 1e3, color=color, alpha=0.06)
        ax_h.plot([], [], "k-", label=f"{comparison.body_mass:g} kg")
        ax_h.plot([], [], "k--", label=f"{comparison.body_mass / 2:g} kg")
        ax_h.set_ylabel("loaded camber height h [mm]")
        # the running surface matters, not the shovel: scale to the central 60 % of each ski
        tops = []
        for entry in comparison.entries:
            sol = entry.cases["half"].solution
            a, b = sol.x[0], sol.x[-1]
            mid = (sol.x > a + 0.2 * (b - a)) & (sol.x < b - 0.2 * (b - a))
            tops.append(float(sol.height[mid].max()) * 1e3)
        ax_h.set_ylim(0, 1.4 * max(tops, default=1.0))
        ax_h.legend(loc="upper right", ncols=2)
        ax_p.set_ylabel("pressure [kPa]")
        ax_p.set_xlabel("x from the balance point [mm] (tip →)")
        ax_h.set_title(
            f"Fleet at x_m = {comparison.load_position * 1e3:g} mm on "
            f"{comparison.snow_modulus * 1e-6:g} MPa snow ({comparison.ski_model}); shaded: "
            "kick zones"
        )
    return fig


def plot_snow_ranking(ranking: Any) -> Figure:
    """A criterion across snow moduli (left) and the rank of each ski (right) of a
    :class:`~skisnow.workflows.SnowRanking`; where the order changes is shaded."""
    fig, axes = new_figure(2, 1, width=9.0, height=3.6)
    ax_v, ax_r = axes[0, 0], axes[0, 1]
    e = ranking.snow_moduli * 1e-6
    with style():
        for i, label in enumerate(ranking.skis):
            ax_v.plot(e, ranking.values[i], "o-", ms=3, label=label)
            ax_r.step(e, ranking.ranks[i], where="mid", label=label)
        for lo, hi, *_ in ranking.changes:
            for ax in (ax_v, ax_r):
                ax.axvspan(lo * 1e-6, hi * 1e-6, color="0.5", alpha=0.15, lw=0)
        for ax in (ax_v, ax_r):
            ax.set_xscale("log")
            ax.minorticks_off()
            ax.set_xticks(e, [f"{v:g}" for v in e])
            ax.set_xlabel("snow modulus [MPa]")
        crit = ranking.criterion
        ax_v.set_ylabel(crit.axis_label)
        ax_v.set_title(f"{crit.name}: {crit.better} is better")
        ax_r.set_ylabel("rank (1 = best)")
        ax_r.set_yticks(range(1, len(ranking.skis) + 1))
        ax_r.invert_yaxis()
        ax_r.set_title(
            "order changes in the shaded bands" if ranking.changes else "order never changes"
        )
        ax_r.legend(loc="best")
    return fig


def plot_pairs(pairing: Any, *, threshold: float = 1.0) -> Figure:
    """The pairing of a fleet (:func:`~skisnow.workflows.match_pairs`): the distance between
    every two skis (left, the numbers written in the cells; the pairs chosen framed) and the
    chosen pairs' distances with their three terms (right), against the poor-match threshold.
    """
    import matplotlib.colors as mcolors
    from matplotlib.patches import Rectangle

    from skisnow.plot._style import MAP_CMAP

    skis = list(pairing.skis)
    d = np.asarray(pairing.distances, dtype=float)
    n = len(skis)
    fig, axes = new_figure(2, 1, width=8.0, height=max(3.2, 0.35 * n + 2.0), layout="constrained")
    ax_m, ax_b = axes[0, 0], axes[0, 1]
    with style():
        hi = float(np.nanmax(d)) if n > 1 and np.nanmax(d) > 0 else 1.0
        im = ax_m.imshow(d, cmap=MAP_CMAP, norm=mcolors.Normalize(0.0, hi))
        for i in range(n):
            for j in range(n):
                if i != j:
                    ax_m.text(j, i, f"{d[i, j]:.2g}", ha="center", va="center", fontsize=7,
                              color="white" if d[i, j] < 0.6 * hi else "black")  # fmt: skip
        used: set[int] = set()
        for a, b, _ in pairing.pairs:  # two skis may share a label: take each index once
            i = next(k for k in range(n) if skis[k] == a and k not in used)
            used.add(i)
            j = next(k for k in range(n) if skis[k] == b and k not in used)
            used.add(j)
            for r, c in ((i, j), (j, i)):
                ax_m.add_patch(Rectangle((c - 0.5, r - 0.5), 1, 1, fill=False, ec="red", lw=1.5))
        ax_m.set_xticks(range(n), skis, rotation=45, ha="right")
        ax_m.set_yticks(range(n), skis)
        ax_m.grid(False)
        fig.colorbar(im, ax=ax_m, label="distance (1 = the tolerances)", shrink=0.85)
        ax_m.set_title("distance between every two skis (pairs framed)")
        labels = [f"{a} + {b}" for a, b, _ in pairing.pairs]
        y = np.arange(len(labels))
        left = np.zeros(len(labels))
        for term, color in (("camber", "#1f5fbf"), ("stiffness", "#8e44ad"),
                            ("contact", "#e67e22")):  # fmt: skip
            v = np.array([getattr(p[2], term) ** 2 for p in pairing.pairs])
            ax_b.barh(y, v, left=left, color=color, label=f"{term} term²")
            left += v
        ax_b.axvline(threshold**2, color="red", ls="--", lw=1.0,
                     label=f"poor match: d > {threshold:g}")  # fmt: skip
        ax_b.set_yticks(y, labels)
        ax_b.invert_yaxis()
        ax_b.set_xlabel("distance² (sum of the terms²)")
        ax_b.set_title("the pairs chosen, best first")
        ax_b.legend(loc="lower right", fontsize="small")
    return fig


def plot_cycle(ds: Any) -> Figure:
    """A load cycle (:func:`~skisnow.workflows.run_cycle`): load and centre of pressure, contact
    lengths, mean and peak pressures, load shares — by region of the ski (rear glide, kick zone,
    front glide: they never jump when two contact patches join); the frames where the grip wax
    touches the snow are shaded."""
    fig, axes = new_figure(1, 4, width=7.5, height=8.0, sharex=True)
    t = ds["time"].values
    touch = ds["kick_contact"].values.astype(bool)
    with style():
        ax = axes[0, 0]
        ax.plot(t, ds["load"].values, color=COLORS["load"], label="force [N]")
        ax.set_ylabel("force on the ski [N]")
        ax2 = ax.twinx()
        ax2.plot(t, ds["load_position"].values * 1e3, color="0.3", ls="--",
                 label="centre of pressure")  # fmt: skip
        ax2.set_ylabel("centre of pressure from\nthe balance point [mm]")
        ax2.grid(False)
        lines = ax.get_lines() + ax2.get_lines()
        ax.legend(lines, [ln.get_label() for ln in lines], loc="upper right", ncols=2)
        stored = [str(z) for z in ds["zone"].values]
        regions = [z for z in ("rear_glide", "kick", "front_glide") if z in stored]
        if not regions:  # a cycle stored before the regions existed
            regions = ["rear", "middle", "front"]
        for name in [*regions, "total"]:
            z = ds.sel(zone=name)
            c = ZONE_COLORS[name]
            label = "kick zone" if name == "kick" else ZONE_LABELS[name].split(" (")[0]
            axes[1, 0].plot(t, z["length"].values * 1e3, color=c, label=label)
            axes[2, 0].plot(t, z["mean_pressure"].values * 1e-3, color=c, label=f"{label} mean")
            if name == "total":
                axes[2, 0].plot(t, z["max_pressure"].values * 1e-3, color=c, ls=":", label="peak")
            else:
                axes[3, 0].plot(t, z["load_share"].values * 100, color=c, label=label)
        axes[1, 0].set_ylabel("contact length [mm]")
        axes[2, 0].set_ylabel("pressure [kPa]")
        axes[3, 0].set_ylabel("load share [%]")
        axes[3, 0].set_xlabel("time [s]")
        axes[1, 0].legend(loc="upper right", ncols=4)
        axes[2, 0].legend(loc="upper right", ncols=3)
        axes[3, 0].legend(loc="upper right", ncols=3)
        for row in axes[:, 0]:
            _shade(row, t, touch)
        kick = "grip wax touches (shaded)" if ds.attrs.get("kick_zone") else "no kick zone"
        axes[0, 0].set_title(
            f"{ds.attrs['ski']} — {ds.attrs['history']}, snow modulus "
            f"{ds.attrs['snow_modulus'] * 1e-6:g} MPa ({ds.attrs['route']} route); {kick}"
        )
    return fig


def _shade(ax: Any, t: np.ndarray, mask: np.ndarray) -> None:
    if not mask.any():
        return
    edges = np.concatenate([[t[0]], 0.5 * (t[1:] + t[:-1]), [t[-1]]])
    d = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    for a, b in zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1), strict=True):
        ax.axvspan(edges[a], edges[b], color=ZONE_COLORS["middle"], alpha=0.12, lw=0)


def _frame_plan(t: np.ndarray, speed: float, max_fps: float) -> tuple[np.ndarray, float, float]:
    """Which frames to show and at what rate so that the animation plays at ``speed`` × real
    time with at most ``max_fps`` frames a second (GIF players clamp faster frames: a browser
    shows a GIF frame of less than 20 ms for 100 ms). Returns (frame indices, fps, the speed
    actually played)."""
    dt = float(np.median(np.diff(t))) if t.size > 1 else 1.0
    rate = speed / dt if dt > 0 else max_fps  # frames of the cycle per second of playback
    step = max(1, int(np.ceil(rate / max_fps)))
    fps = rate / step
    # a GIF stores whole hundredths of a second per frame: play what it can store
    delay = max(2, round(100.0 / fps)) / 100.0
    return np.arange(0, t.size, step), 1.0 / delay, dt * step / delay


def animate_cycle(
    ds: Any,
    path: str | Path,
    *,
    speed: float = 1.0,
    max_fps: float = 25.0,
    fps: float | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> Path:
    """Write an animation of a load cycle: loaded profile, deformed snow surface and pressure,
    and the force and centre of pressure over the cycle with the moment shown.

    It plays at ``speed`` × real time (default 1: real time), frames thinned to at most
    ``max_fps`` a second; the speed played is printed on every frame ("real time", or "×0.25:
    slow motion"). ``fps`` forces a frame rate (every frame shown; the speed printed follows).
    GIF (Matplotlib's PillowWriter) for ``.gif``; MP4 (FFMpegWriter) for ``.mp4``, which needs
    ``ffmpeg`` on PATH. ``ds`` must hold the fields (``run_cycle(..., keep_fields=True)``).

    Returns the path written.
    """
    from matplotlib.animation import FFMpegWriter, PillowWriter

    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise InputError(f"{path}: an animation is written as .gif or .mp4, not {suffix!r}")
    if suffix == ".mp4" and shutil.which("ffmpeg") is None:
        raise InputError(
            f"{path}: MP4 needs ffmpeg on PATH (Debian: apt install ffmpeg); write a .gif instead"
        )
    if "pressure" not in ds:
        raise InputError("the cycle dataset holds no fields: run it with keep_fields=True")
    if not (np.isfinite(speed) and speed > 0):
        raise InputError(f"speed must be a positive factor of real time, got {speed!r}")
    x = ds["x"].values * 1e3
    t = ds["time"].values
    h = ds["height"].values * 1e3
    p = ds["pressure"].values * 1e-3
    u = ds["snow_displacement"].values * 1e3
    loaded = ds["loaded"].values.astype(bool)
    # the ski as it lies on the snow: gap + snow surface = h − δ − θ(x − x_m) (rigid-body motion)
    delta = np.nan_to_num(ds["translation"].values)
    theta = np.nan_to_num(ds["rotation"].values)
    xm = ds["load_position"].values
    ski_y = h - (delta[:, None] + theta[:, None] * (ds["x"].values[None, :] - xm[:, None])) * 1e3
    if fps is None:
        shown, fps, played = _frame_plan(t, speed, max_fps)
    else:
        shown = np.arange(t.size)
        dt = float(np.median(np.diff(t))) if t.size > 1 else 1.0
        played = dt * fps
    # GIF frames last whole hundredths of a second: real time to within that, speed printed
    pace = (f"real time (×{played:.2f})" if abs(played - 1.0) < 0.1 else
            f"×{played:.2g} " + ("slow motion" if played < 1 else "fast"))  # fmt: skip
    force = ds["load"].values
    fig, axes = new_figure(1, 3, width=7.0, height=6.4, sharex=False)
    ax_s, ax_p, ax_f = axes[0, 0], axes[1, 0], axes[2, 0]
    kz = ds.attrs.get("kick_zone") or []
    with style():
        (line_ski,) = ax_s.plot(x, ski_y[0], color=COLORS["profile"], label="ski base")
        (line_snow,) = ax_s.plot(x, -u[0], color=COLORS["snow"], lw=0.9, label="snow surface")
        (line_p,) = ax_p.plot(x, p[0], color=COLORS["pressure"])
        marker = ax_s.axvline(xm[0] * 1e3, color=COLORS["load"], ls=":", lw=1.0,
                              label="centre of pressure")  # fmt: skip
        if len(kz) == 2:
            for ax in (ax_s, ax_p):
                ax.axvspan(kz[0] * 1e3, kz[1] * 1e3, color=ZONE_COLORS["kick_zone"], alpha=0.08,
                           label="kick zone" if ax is ax_s else None)  # fmt: skip
        # scale to the running surface (central 60 % of the ski) and the deepest snow, not to
        # the shovel: the contact is a fraction of a millimetre
        mid = (x > x[0] + 0.2 * (x[-1] - x[0])) & (x < x[-1] - 0.2 * (x[-1] - x[0]))
        top = float(np.nanmax(ski_y[:, mid])) if mid.any() else 1.0
        depth = float(np.nanmax(u)) if loaded.any() else 0.0
        ax_s.set_ylim(-1.5 * max(depth, 0.01), 1.3 * max(top, 0.05))
        ax_p.set_ylim(0, max(1.0, float(np.nanmax(p)) * 1.05))
        ax_s.set_ylabel("height [mm]")
        ax_s.legend(loc="upper right", ncols=2, fontsize="small")
        ax_p.set_ylabel("pressure [kPa]")
        ax_p.set_xlabel("x from the balance point [mm] (tip →)")
        # the force and the centre of pressure over the whole cycle, the moment shown marked
        ax_f.plot(t, force, color=COLORS["load"], label="force on the ski [N]")
        ax_f.set_ylabel("force [N]")
        ax_f.set_xlabel("time [s]")
        ax_c = ax_f.twinx()
        ax_c.plot(t, xm * 1e3, color="0.3", ls="--", label="centre of pressure [mm]")
        ax_c.set_ylabel("centre of pressure [mm]")
        ax_c.grid(False)
        now = ax_f.axvline(t[0], color="black", lw=1.0)
        lines = ax_f.get_lines()[:1] + ax_c.get_lines()
        ax_f.legend(lines, [ln.get_label() for ln in lines], loc="upper right", fontsize="small")
        title = ax_s.set_title("")
    writer = PillowWriter(fps=fps) if suffix == ".gif" else FFMpegWriter(fps=fps)
    path.parent.mkdir(parents=True, exist_ok=True)
    with style(), writer.saving(fig, str(path), dpi=80):
        for k, i in enumerate(shown, start=1):
            line_ski.set_ydata(ski_y[i])
            line_snow.set_ydata(-u[i])
            line_p.set_ydata(p[i])
            marker.set_xdata([xm[i] * 1e3, xm[i] * 1e3])
            now.set_xdata([t[i], t[i]])
            title.set_text(
                f"{ds.attrs['ski']} — t = {t[i]:.2f} s, {force[i]:.0f} N at "
                f"{xm[i] * 1e3:.0f} mm" + ("" if loaded[i] else " (unloaded)") + f" · {pace}"
            )
            writer.grab_frame()
            if progress is not None:
                progress(k, shown.size)
    return path
