"""Built-in load cycles: the force on one ski and its centre of pressure over one cycle.

Three techniques, each a table of knots (phase of the cycle, normal force on the ski as a
fraction of body weight BW, centre of pressure x_m in mm from the balance point) joined by the
shape-preserving PCHIP interpolant (no overshoot: the force never goes negative between knots).

HONESTY NOTE. These are *approximated shapes*, not digitised curves: the knots follow the
features the cited studies describe — the phases and their timing, the number and order of the
force peaks, the direction in which the centre of pressure moves. The peak values are our
assumptions, of the order of those reported there, constrained by one balance law: over a
periodic cycle the vertical impulse balances, 2·mean(F_ski) + mean(F_poles) = BW, with the
poles' mean vertical share stated per template. The numbers used are the knots below, printed
by ``skisnow cycle --template NAME --show-template``. For real questions use measured histories
(force bindings, pressure insoles) through :func:`~skisnow.workflows.read_load_history`.

Foot on the ski: the centre of pressure is placed between the heel at −240 mm and the ball of
the foot at −40 mm from the balance point — the span of load positions of the camber bench on
which the shipped networks were trained (Kalliorinne et al. 2023, §2; the paper's reference
position is 120 mm behind the balance point, mid-foot).

* ``diagonal`` — diagonal stride, one ski over one cycle (1.3 s). Ski plant, weight transfer
  with a first peak of 0.95 BW, glide at 0.7 BW while the opposite pole is planted, the
  unloading before the kick (0.55 BW), the kick on the forefoot with a peak of 1.8 BW, toe-off
  at 56 % of the cycle, then the unloaded swing; poles 11 % of BW on average. After Komi
  (1987), *Int. J. Sport Biomech.* 3, 370–381 (6 m force-plate track: an unloading before a
  short, high kick peak) and Vähäsöyrinki et al. (2008), *Med. Sci. Sports Exerc.* 40(6),
  1111–1116 (ski and pole forces over the cycle, the kick a short fraction of it). A kick of
  1.8 BW exceeds the shipped networks' 130 kg for skiers above 72 kg.
* ``double_poling`` — double poling, one ski (both carry the same), 1.1 s. Both skis stay on
  the snow; each carries about half the body weight, less while the poles carry load (down to
  0.25 BW per ski in the poling phase) and more when the body is raised in the recovery
  (0.60 BW); poles 10 % of BW on average. The centre of pressure is on the forefoot at pole
  plant and moves to the heel in the recovery. After Holmberg et al. (2005), *Med. Sci. Sports
  Exerc.* 37(5), 807–818 (plantar forces by pressure insoles; the skiers lean forward onto the
  forefoot before pole plant) and Lindinger & Holmberg (2011), *Eur. J. Appl. Physiol.* 111,
  1103–1119 (leg and pole force patterns over the double-poling cycle).
* ``skate_g3`` — V2 skating (gear 3: one pole push per leg push), one ski, 1.6 s. Ski set down,
  weight transfer to 1.0 BW, glide at 0.85 BW, the push-off with a peak of 1.35 BW on the
  mid-foot, lift-off at 52 % of the cycle, then the swing; poles 9 % of BW on average. After
  Smith (2002), "Biomechanics of cross country skiing", in Rusko (ed.), *Cross Country
  Skiing*, Blackwell, pp. 32–61 (skating ski-force patterns). The ski is on its edge during the
  push; the contact model has no edging: the normal force is applied as if the ski were flat.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import PchipInterpolator

from skisnow._errors import InputError
from skisnow.constants import STANDARD_GRAVITY
from skisnow.workflows._history import LoadHistory

__all__ = ["TEMPLATES", "CycleTemplate", "template_history"]


@dataclass(frozen=True, kw_only=True)
class CycleTemplate:
    """One technique's cycle as knots: phase [0, 1], force [body weights], x_m [mm].

    Attributes
    ----------
    name, technique
        Key and human name.
    duration
        Nominal cycle time [s].
    phase, force_bw, position_mm
        The knots (phase 0 and 1 carry the same values: the cycle is periodic).
    pole_share
        Mean vertical pole force over the cycle as a fraction of BW (an assumption, stated):
        the knots are set so that the cycle's vertical impulse balances,
        2·mean(F_ski) + pole_share·BW = BW (both skis carry the same history, shifted by half
        a cycle in the alternating techniques).
    citation
        The studies whose described features the knots follow (see the module note).
    """

    name: str
    technique: str
    duration: float
    phase: tuple[float, ...]
    force_bw: tuple[float, ...]
    position_mm: tuple[float, ...]
    pole_share: float
    citation: str

    def knots(self) -> list[dict[str, float]]:
        """The knots as records (phase, force_bw, load_position_mm) — the numbers used."""
        return [
            {"phase": p, "force_bw": f, "load_position_mm": x}
            for p, f, x in zip(self.phase, self.force_bw, self.position_mm, strict=True)
        ]


TEMPLATES: dict[str, CycleTemplate] = {
    "diagonal": CycleTemplate(
        name="diagonal",
        technique="diagonal stride",
        duration=1.3,
        phase=(0.0, 0.05, 0.11, 0.24, 0.35, 0.43, 0.50, 0.56, 0.70, 1.0),
        force_bw=(0.0, 0.70, 0.95, 0.70, 0.55, 1.80, 0.60, 0.0, 0.0, 0.0),
        position_mm=(-150.0, -160.0, -150.0, -130.0, -110.0, -50.0, -40.0, -40.0, -150.0, -150.0),
        pole_share=0.11,
        citation=(
            "after Komi (1987) Int. J. Sport Biomech. 3:370-381 and Vähäsöyrinki et al. (2008) "
            "Med. Sci. Sports Exerc. 40(6):1111-1116; approximated shape, not digitised"
        ),
    ),
    "double_poling": CycleTemplate(
        name="double_poling",
        technique="double poling",
        duration=1.1,
        phase=(0.0, 0.10, 0.25, 0.35, 0.50, 0.70, 0.85, 1.0),
        force_bw=(0.50, 0.30, 0.25, 0.40, 0.50, 0.60, 0.50, 0.50),
        position_mm=(-80.0, -90.0, -110.0, -150.0, -190.0, -160.0, -100.0, -80.0),
        pole_share=0.10,
        citation=(
            "after Holmberg et al. (2005) Med. Sci. Sports Exerc. 37(5):807-818 and Lindinger & "
            "Holmberg (2011) Eur. J. Appl. Physiol. 111:1103-1119; approximated shape, not "
            "digitised"
        ),
    ),
    "skate_g3": CycleTemplate(
        name="skate_g3",
        technique="V2 skating (gear 3)",
        duration=1.6,
        phase=(0.0, 0.05, 0.12, 0.25, 0.38, 0.48, 0.52, 0.60, 1.0),
        force_bw=(0.0, 0.60, 1.00, 0.85, 1.35, 0.60, 0.0, 0.0, 0.0),
        position_mm=(-150.0, -150.0, -140.0, -130.0, -120.0, -110.0, -100.0, -150.0, -150.0),
        pole_share=0.09,
        citation=(
            "after Smith (2002) 'Biomechanics of cross country skiing', in Rusko (ed.) Cross "
            "Country Skiing, Blackwell, 32-61; approximated shape, not digitised"
        ),
    ),
}


def template_history(
    name: str,
    *,
    body_mass: float,
    n_frames: int = 100,
    duration: float | None = None,
) -> LoadHistory:
    """One cycle of a built-in technique as a :class:`LoadHistory` (SI units).

    Parameters
    ----------
    name
        A key of :data:`TEMPLATES`: ``'diagonal'``, ``'double_poling'``, ``'skate_g3'``.
    body_mass
        The skier's body mass [kg]; forces scale with body weight BW = m·g₀.
    n_frames
        Samples over the cycle (equally spaced, both ends included).
    duration
        Cycle time [s] (default: the template's nominal one); the shape scales in time.

    Returns
    -------
    LoadHistory
        F(t) = BW·f(t/T) and x_m(t) from the PCHIP interpolant of the knots; F clipped at 0.
    """
    if name not in TEMPLATES:
        raise InputError(f"unknown cycle template {name!r}; built-in: {', '.join(TEMPLATES)}")
    tpl = TEMPLATES[name]
    if not (np.isfinite(body_mass) and 20.0 <= body_mass <= 150.0):
        raise InputError(f"body mass must be within 20..150 kg, got {body_mass:g} kg")
    period = tpl.duration if duration is None else float(duration)
    if not (np.isfinite(period) and period > 0):
        raise InputError(f"cycle duration must be a positive number of seconds, got {duration}")
    if int(n_frames) < 2:
        raise InputError(f"n_frames must be at least 2, got {n_frames}")
    phase = np.linspace(0.0, 1.0, int(n_frames))
    f = PchipInterpolator(tpl.phase, tpl.force_bw)(phase)
    x = PchipInterpolator(tpl.phase, tpl.position_mm)(phase)
    return LoadHistory(
        time=phase * period,
        force=np.maximum(f, 0.0) * body_mass * STANDARD_GRAVITY,
        load_position=x * 1e-3,
        name=f"{tpl.technique} ({body_mass:g} kg)",
        source=tpl.citation,
    )
