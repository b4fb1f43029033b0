"""``skisnow bench-plan``: how well would ``skisnow identify`` determine EI(x) and z0(x) from a
bench plan, before measuring (thin: parse the plans, call
:func:`skisnow.identify.predict_identification_uncertainty`, render)."""

from __future__ import annotations

import math
from typing import Annotated, Any

import typer

from skisnow._errors import InputError
from skisnow._values import parse_values
from skisnow.cli._app import app
from skisnow.cli._render import (
    JsonOption,
    NCamberOption,
    NStiffnessOption,
    RegularisationOption,
    emit_json,
    print_table,
)

#: The issue's targets of the identification: EI within 5 % rms between the glide zones, z0
#: within 10 µm rms (modulo a line).
TARGET_EI_PERCENT = 5.0
TARGET_Z0_UM = 10.0


def parse_plan(text: str) -> tuple[list[float], list[float]]:
    """``"20,40,60,80@-120,-40"`` (masses [kg] @ load positions [mm]; each a list, one value or
    start:stop:step) -> (masses [kg], load positions [mm])."""
    from skisnow._checks import check_option_values

    if text.count("@") != 1:
        raise InputError(
            f"--plan {text!r}: write MASSES_KG@POSITIONS_MM, e.g. '20,40,60,80@-120' or "
            "'10:130:10@-40,-120,-200'"
        )
    m_text, p_text = text.split("@")
    masses = check_option_values(parse_values(m_text, name=f"--plan {text!r} masses"), "mass",
                                 f"--plan {text!r} masses")  # fmt: skip
    positions = check_option_values(
        parse_values(p_text, name=f"--plan {text!r} load positions"), "load_position",
        f"--plan {text!r} load positions",
    )  # fmt: skip
    return masses.tolist(), positions.tolist()


def _number(v: float, scale: float, digits: int = 3) -> float | None:
    return None if not math.isfinite(v) else round(v * scale, digits)


@app.command("bench-plan")
def bench_plan(
    ski: Annotated[
        str, typer.Argument(help="Shipped ski name or a ski file (.json): true or provisional.")
    ],
    plan: Annotated[
        list[str],
        typer.Option(
            "--plan",
            help="A bench plan MASSES_KG@POSITIONS_MM, e.g. '20,40,60,80@-120' (repeatable).",
        ),
    ],
    noise_um: Annotated[
        float, typer.Option("--noise-um", help="Bench noise of one sample [µm] (std).")
    ] = 10.0,
    stations_mm: Annotated[
        str | None,
        typer.Option(
            "--stations-mm",
            help="First,last measured station [mm], e.g. '-900,850' (default: the whole ski).",
        ),
    ] = None,
    regularisation: RegularisationOption = None,
    n_stiffness: NStiffnessOption = 14,
    n_camber: NCamberOption = 100,
    target_ei_percent: Annotated[
        float, typer.Option("--target-ei-percent", help="EI target, rms % (-450..+400 mm).")
    ] = TARGET_EI_PERCENT,
    target_z0_um: Annotated[
        float, typer.Option("--target-z0-um", help="z0 target, rms µm modulo a line.")
    ] = TARGET_Z0_UM,
    json_out: JsonOption = False,
) -> None:
    """Predict the identification's EI and z0 uncertainty for bench plans (Fisher information)."""
    from skisnow.identify import predict_identification_uncertainty
    from skisnow.ski import get_ski

    if not (math.isfinite(noise_um) and 0 < noise_um <= 5000):
        raise InputError(f"--noise-um must be in (0, 5000] µm, got {noise_um:g}")
    for opt, val in (("--n-stiffness", n_stiffness), ("--n-camber", n_camber)):
        if val < 6:
            raise InputError(f"{opt} must be >= 6, got {val}")
    stations = None
    if stations_mm is not None:
        vals = parse_values(stations_mm, name="--stations-mm")
        if vals.size != 2 or not vals[0] < vals[1]:
            raise InputError(f"--stations-mm {stations_mm!r}: give FIRST,LAST in mm, FIRST < LAST")
        stations = (float(vals[0]) / 1e3, float(vals[1]) / 1e3)
    plans = [(text, *parse_plan(text)) for text in plan]
    sk = get_ski(ski)
    rows: list[dict[str, Any]] = []
    ei_window = (-0.45, 0.40)  # the issue's: between the glide zones (the library's default)
    for text, masses, positions in plans:
        r = predict_identification_uncertainty(
            sk, masses, [p / 1e3 for p in positions], noise_um / 1e6, stations=stations,
            regularisation=regularisation, n_stiffness=n_stiffness, n_camber=n_camber,
            ei_window=ei_window,
        )  # fmt: skip
        rows.append(
            {
                "plan": text,
                "load_cases": r.n_cases,
                "parameters": r.n_parameters,
                "null_dimension": r.null_dimension,
                "ei_identifiable": r.ei_identifiable,
                "z0_identifiable": r.z0_identifiable,
                "ei_sd_crb_percent": _number(r.ei_sd_crb, 100.0),
                "z0_sd_crb_um": _number(r.z0_sd_crb, 1e6, 2),
                "regularisation": r.regularisation,
                "ei_sd_percent": _number(r.ei_sd, 100.0),
                "z0_sd_um": _number(r.z0_sd, 1e6, 2),
                "ei_bias_percent": _number(r.ei_bias, 100.0),
                "z0_bias_um": _number(r.z0_bias, 1e6, 2),
                "ei_rms_percent": _number(r.ei_rms, 100.0),
                "z0_rms_um": _number(r.z0_rms, 1e6, 2),
                "ei_target_reachable": bool(r.ei_rms * 100 <= target_ei_percent),
                "z0_target_reachable": bool(r.z0_rms * 1e6 <= target_z0_um),
            }
        )
    doc = {
        "ski": sk.name,
        "noise_um": noise_um,
        "stations_mm": None if stations is None else [s * 1e3 for s in stations],
        "ei_window_mm": [v * 1e3 for v in ei_window],
        "targets": {"ei_percent": target_ei_percent, "z0_um": target_z0_um},
        "plans": rows,
    }
    if json_out:
        emit_json(doc)
        return

    def crb(v: float | None, ok: bool, nd: int) -> str:
        return f"{v:.3g}" if ok and v is not None else f"not identifiable (null dim {nd})"

    def yes(ok: bool) -> str:
        return "yes" if ok else "no"

    def fmt(v: float | None) -> str:
        return "-" if v is None else f"{v:.3g}"

    lines: list[tuple[str, Any]] = [
        ("load cases", lambda r: r["load_cases"]),
        ("CRB: EI sd %", lambda r: crb(r["ei_sd_crb_percent"], r["ei_identifiable"],
                                       r["null_dimension"])),
        ("CRB: z0 sd µm", lambda r: crb(r["z0_sd_crb_um"], r["z0_identifiable"],
                                        r["null_dimension"])),
        ("λ" if regularisation else "λ (expected GCV)", lambda r: f"{r['regularisation']:g}"),
        ("EI sd %", lambda r: fmt(r["ei_sd_percent"])),
        ("EI mean error %", lambda r: fmt(r["ei_bias_percent"])),
        ("EI expected rms %", lambda r: fmt(r["ei_rms_percent"])),
        ("z0 sd µm", lambda r: fmt(r["z0_sd_um"])),
        ("z0 mean error µm", lambda r: fmt(r["z0_bias_um"])),
        ("z0 expected rms µm", lambda r: fmt(r["z0_rms_um"])),
        (f"EI ≤ {target_ei_percent:g} % reachable", lambda r: yes(r["ei_target_reachable"])),
        (f"z0 ≤ {target_z0_um:g} µm reachable", lambda r: yes(r["z0_target_reachable"])),
    ]  # fmt: skip
    print_table(
        f"{sk.name} at {noise_um:g} µm: predicted identification uncertainty (EI rms over "
        f"{ei_window[0] * 1e3:g}..+{ei_window[1] * 1e3:g} mm, z0 rms modulo a line; CRB: "
        "Cramér–Rao bound without regularisation; "
        "below it with the fit's penalty at λ)",
        ["plan (kg@mm)", *[r["plan"] for r in rows]],
        [[label, *[get(r) for r in rows]] for label, get in lines],
    )
