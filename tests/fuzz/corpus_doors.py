"""The corpus of the doors added after the first one (issue 27): ski files, load histories,
fleets, the explorer's and the report's options, topography side-cars, re-signed model files,
archive bombs, nested JSON and name injection. Same :class:`corpus.Case` and classification as
``corpus.py`` (which runs these groups after its own); valid but hostile inputs (a ski named
``</script><!--``) are ``expect="accept"`` cases whose ``post`` checks where the name went.

Cases that would compute are kept small (256 stations, one mass, one snow) so that a door that
wrongly lets a value through costs seconds, not minutes.
"""

from __future__ import annotations

import copy
import hashlib
import io
import json
import os
import re
import zipfile
from collections.abc import Callable
from pathlib import Path

import numpy as np
from corpus import Case, _write

SMALL = ["--points", "256"]
CONTACT = ["--mass-kg", "60", "--load-position-mm", "-120", "--snow-modulus-mpa", "100", *SMALL]


def _skate() -> dict:
    from skisnow.ski import shipped_ski_path

    return json.loads(shipped_ski_path("skate").read_text())


def _ski_file(d: Path, name: str, edit: Callable[[dict], object] | None = None,
              raw: str | None = None) -> Path:  # fmt: skip
    path = d / f"ski_{name}.json"
    if raw is not None:
        return _write(path, raw)
    doc = _skate()
    doc["name"] = f"ski_{name}"
    if edit is not None:
        edit(doc)
    return _write(path, json.dumps(doc, indent=1))


def _scale(keys: tuple[str, ...], factor: float) -> Callable[[dict], None]:
    def edit(doc: dict) -> None:
        node = doc
        for k in keys[:-1]:
            node = node[k]
        v = node[keys[-1]]
        node[keys[-1]] = [a * factor for a in v] if isinstance(v, list) else v * factor

    return edit


def _all_x(factor: float) -> Callable[[dict], None]:
    def edit(doc: dict) -> None:
        doc["x_tail_mm"] *= factor
        doc["x_tip_mm"] *= factor
        for sec in ("stiffness", "camber"):
            doc[sec]["x_mm"] = [a * factor for a in doc[sec]["x_mm"]]
        doc["boot_plate_mm"] = [a * factor for a in doc["boot_plate_mm"]]

    return edit


def _set(key: str, value: object) -> Callable[[dict], None]:
    return lambda doc: doc.__setitem__(key, value)


def ski_file_cases(d: Path) -> list[Case]:
    variants: dict[str, tuple[Path, list[str]]] = {}

    def add(name: str, *detail: str, **kw) -> None:
        variants[name] = (_ski_file(d, name, **kw), list(detail))

    add("width_in_m", "width_mm", edit=_scale(("width_mm",), 1e-3))
    add("width_in_cm", "width_mm", edit=_scale(("width_mm",), 0.1))
    add("width_in_um", "width_mm", edit=_scale(("width_mm",), 1e3))
    add("ei_in_n_mm2", "ei_nm2", edit=_scale(("stiffness", "ei_nm2"), 1e6))
    add("ei_in_kn_m2", "ei_nm2", edit=_scale(("stiffness", "ei_nm2"), 1e-3))
    add("ei_in_n_cm2", "ei_nm2", edit=_scale(("stiffness", "ei_nm2"), 1e4))
    add("camber_in_um", "z0_mm", edit=_scale(("camber", "z0_mm"), 1e3))
    add("camber_in_m", "z0_mm", edit=_scale(("camber", "z0_mm"), 1e-3))
    add("camber_negative", "z0_mm", edit=_scale(("camber", "z0_mm"), -1.0))
    add("ski_20m", "x_tip_mm", edit=_all_x(10.0))
    add("x_in_m", "x_tail_mm", edit=_all_x(1e-3))
    add("x_in_cm", "x_tip_mm", edit=_all_x(0.1))
    add("boot_plate_in_m", "boot_plate_mm", edit=_set("boot_plate_mm", [-0.3, 0.0]))
    add("kick_zone_in_m", "kick_zone_mm", edit=lambda doc: doc.update(
        kind="classic", kick_zone_mm=[-0.265, 0.255]))  # fmt: skip
    add("width_profile_in_m", "width_profile", edit=_set(
        "width_profile", {"x_mm": [-920.0, 940.0], "width_mm": [0.044, 0.044]}))  # fmt: skip
    add("log_ei_sd_huge", "log_ei_sd", edit=lambda doc: doc["stiffness"].update(
        log_ei_sd=[50.0] * len(doc["stiffness"]["x_mm"])))  # fmt: skip
    add("z0_sd_in_um", "z0_sd_mm", edit=lambda doc: doc["camber"].update(
        z0_sd_mm=[20.0] * len(doc["camber"]["x_mm"])))  # fmt: skip
    add("ei_zero", "ei_nm2", edit=lambda doc: doc["stiffness"]["ei_nm2"].__setitem__(3, 0))
    text = json.dumps(_skate())
    add("nested_json", "nested", raw="[" * 100_000 + "]" * 100_000)
    add("nested_in_provenance", "nested", raw=text[:-1] + ', "x": ' + "[" * 50_000
        + "]" * 50_000 + "}")  # fmt: skip
    add(
        "duplicate_key",
        "width_mm",
        raw=text.replace('"width_mm": 44.0', '"width_mm": 44.0, "width_mm": 0.044'),
    )
    # a BOM prefix is not malformed: it reads as the file without it (tests/cli/test_bom_inputs)
    add("nan_literal", "NaN", raw=text.replace('"width_mm": 44.0', '"width_mm": NaN'))
    add("overflow_number", "width_mm", raw=text.replace('"width_mm": 44.0', '"width_mm": 1e400'))
    add("truncated", "JSON", raw=text[: len(text) // 2])
    add("empty_name", "name", edit=_set("name", "  "))
    cases = []
    for name, (path, detail) in variants.items():
        place = [path.name, *detail]
        cases.append(Case(f"metrics ski {name}", ["metrics", str(path)], place, group="ski file"))
        cases.append(Case(f"contact ski {name}", ["contact", "--ski", str(path), *CONTACT],
                          place, group="ski file"))  # fmt: skip
    for name in ("width_in_m", "ei_in_n_mm2", "camber_in_um", "nested_json", "ski_20m"):
        path, detail = variants[name]
        out = d / f"report_{name}"
        cases.append(Case(
            f"report ski {name}",
            ["report", str(path), "--mass-kg", "60", "--snow-modulus-mpa", "100", "--stride",
             "none", "--workers", "0", *SMALL, "--out", str(out)],
            [path.name, *detail], post=_nothing_in(out), group="ski file"))  # fmt: skip
    for name in ("width_in_m", "ei_in_kn_m2", "camber_in_m"):
        path, detail = variants[name]
        store = d / f"sweep_{name}.zarr"
        cases.append(Case(
            f"sweep ski {name}",
            ["sweep", "--ski", str(path), "--mass-kg", "60", "--snow-modulus-mpa", "100",
             "--workers", "0", *SMALL, "--out", str(store)],
            [path.name, *detail], post=_nothing_in(store), group="ski file"))  # fmt: skip
        cases.append(Case(
            f"compare ski {name}",
            ["compare", str(path), "skate", "--body-mass-kg", "60", "--snow-modulus-mpa", "100",
             "--snow-range-mpa", "100,200", *SMALL], [path.name, *detail],
            group="ski file"))  # fmt: skip
    return cases


def _nothing_in(path: Path) -> Callable[[], str | None]:
    def post() -> str | None:
        if path.exists() and (path.is_file() or any(path.iterdir())):
            return f"{path.name} was written by a refused run"
        return None

    return post


# -------------------------------------------------------------------------- load histories

_HISTORY = [(i * 0.01, 700.0 * np.sin(np.pi * i / 100) ** 2, -120.0 + i) for i in range(101)]


def _history(rows=_HISTORY, header="t_s,force_n,load_position_mm", fmt="{:.6g},{:.6g},{:.6g}"):
    return header + "\n" + "\n".join(fmt.format(*r) for r in rows) + "\n"


def history_cases(d: Path) -> list[Case]:
    rows = _HISTORY
    variants: dict[str, tuple[str | bytes, list[str]]] = {
        "mass_in_g": (_history([(t, f / 9.81 * 1e3, p) for t, f, p in rows],
                               header="t_s,mass_kg,load_position_mm"), ["mass_kg"]),
        "force_in_kn": (_history([(t, f / 1e3 + 1e-3, p) for t, f, p in rows]), ["force_n"]),
        "force_in_mn": (_history([(t, f * 1e3, p) for t, f, p in rows]), ["force_n"]),
        "position_in_m": (_history([(t, f, p * 1e-3 - 0.5) for t, f, p in rows]),
                          ["load_position_mm"]),
        "time_in_ms": (_history([(t * 1e3, f, p) for t, f, p in rows]), ["t_s"]),
        "time_in_us": (_history([(t * 1e6, f, p) for t, f, p in rows]), ["t_s"]),
        "force_spike": (_history([(t, 1e6 if i == 50 else f, p)
                                  for i, (t, f, p) in enumerate(rows)]), ["force_n"]),
        "absurd_impulse": (_history([(t, 900.0, p) for t, f, p in rows],
                                    header="t_s,mass_kg,load_position_mm"), ["mean load"]),
        "200k_rows": (_history([(i * 1e-3, 700.0, -120.0) for i in range(200_000)]),
                      ["--frames|frames|solves"]),
        "ragged_row": ("# binding\n# right ski\n" + _history(rows[:5]).replace(
            "0.03,", "0.03,1,", 1), ["line 7"]),
        "extra_column": (_history([(t, f, p, 1) for t, f, p in rows],
                                  header="t_s,force_n,load_position_mm,extra",
                                  fmt="{:.6g},{:.6g},{:.6g},{}"), []),
        "missing_position": (_history([(t, f) for t, f, p in rows], header="t_s,force_n",
                                      fmt="{:.6g},{:.6g}"), ["load_position_mm"]),
        "nan_force": (_history(rows, fmt="{:.6g},{},{:.6g}").replace(
            f"\n0.5,{rows[50][1]},", "\n0.5,nan,", 1), ["line 52", "force_n"]),
        "text_cell": (_history(rows, fmt="{:.6g},{},{:.6g}").replace(
            f"\n0.2,{rows[20][1]},", "\n0.2,abc,", 1), ["line 22", "force_n", "not a number"]),
        "duplicate_time": (_history([*rows[:10], rows[9], *rows[10:]]), ["t_s"]),
        "gap": (_history([*rows[:40], *rows[60:]]), ["t_s", "gap"]),
        "negative_force": (_history([(t, -f, p) for t, f, p in rows]), ["force_n"]),
        "decreasing_time": (_history(list(reversed(rows))), ["t_s"]),
        "both_load_columns": (_history([(t, f, f / 9.81, p) for t, f, p in rows],
                                       header="t_s,force_n,mass_kg,load_position_mm",
                                       fmt="{:.6g},{:.6g},{:.6g},{:.6g}"), ["force_n"]),
        "empty": ("", []),
        "header_only": ("t_s,force_n,load_position_mm\n", []),
        "one_row": (_history(rows[:1]), []),
        "binary": (os.urandom(3000), []),
        "latin1": (("# caf\xe9\n" + _history(rows)).encode("latin-1"), []),
    }  # fmt: skip
    base = ["cycle", "skate", "--snow-modulus-mpa", "100", *SMALL]
    cases = []
    for name, (text, detail) in variants.items():
        p = _write(d / f"history_{name}.csv", text)
        cases.append(Case(f"cycle history {name}", [*base, "--load-history", str(p)],
                          [p.name, *detail] if name != "200k_rows" else detail,
                          group="load history"))  # fmt: skip
    ok = _write(d / "history_ok.csv", _history(rows))
    tpl = [*base, "--template", "diagonal", "--body-mass-kg", "60"]
    for opt, value in (("--frames", "0"), ("--frames", "-1"), ("--frames", "1000000000"),
                       ("--frames", "abc"), ("--cycle-s", "0"), ("--cycle-s", "nan"),
                       ("--cycle-s", "1400"), ("--animation-speed", "0"),
                       ("--animation-speed", "nan"), ("--animation-speed", "1e9"),
                       ("--body-mass-kg", "65000"), ("--template", "bogus"),
                       ("--snow-modulus-mpa", "1e8"), ("--ski-model", "bogus")):  # fmt: skip
        cases.append(Case(f"cycle {opt} {value}", [*tpl, opt, value], [opt], group="option"))
    cases.append(Case("cycle history and template", [*tpl, "--load-history", str(ok)],
                      ["--load-history", "--template"], group="option"))  # fmt: skip
    cases.append(Case("cycle --frames 1e9 on a file", [*base, "--load-history", str(ok),
                      "--frames", "1000000000"], ["--frames"], group="option"))  # fmt: skip
    return cases


# -------------------------------------------------------------------------- fleets


def fleet_cases(d: Path) -> list[Case]:
    wide = _ski_file(d, "fleet_width_in_m", edit=_scale(("width_mm",), 1e-3))
    good = _ski_file(d, "fleet_ok")
    missing = d / "fleet_missing.json"
    cmp = ["--body-mass-kg", "60", "--snow-modulus-mpa", "100", *SMALL]
    cases = [
        Case("pairs classic classic", ["pairs", "classic", "classic", *cmp], ["classic"]),
        Case("compare skate skate", ["compare", "skate", "skate", *cmp], ["skate"]),
        Case("pairs one file twice", ["pairs", str(good), str(good), "skate", "classic", *cmp],
             [good.name]),
        Case("compare a missing file", ["compare", "skate", str(missing), *cmp,
             "--snow-range-mpa", "100,200"], [missing.name]),
        Case("compare all missing", ["compare", str(missing), str(d / "x.json"), *cmp],
             [missing.name]),
        Case("pairs one ski", ["pairs", "skate", *cmp], ["two"]),
        Case("compare ski file width in m", ["compare", str(wide), "skate", *cmp,
             "--snow-range-mpa", "100,200"], [wide.name, "width_mm"]),
        Case("pairs ski file width in m", ["pairs", str(wide), "skate", "classic", *cmp],
             [wide.name, "width_mm"]),
    ]  # fmt: skip
    fleet = ["compare", "skate", "classic", *cmp]
    for opt, value in (("--criterion", "bogus"), ("--snow-range-mpa", "nan"),
                       ("--snow-range-mpa", "0,100"), ("--snow-range-mpa", "100"),
                       ("--snow-range-mpa", "1e8,2e8"), ("--body-mass-kg", "65000"),
                       ("--points", "3"), ("--load-position-mm", "5000"),
                       ("--ski-model", "bogus")):  # fmt: skip
        cases.append(Case(f"compare {opt} {value}", [*fleet, opt, value], [opt]))
    for opt, value in (("--body-mass-kg", "0"), ("--snow-modulus-mpa", "1e8"),
                       ("--load-position-mm", "-0.12e6")):  # fmt: skip
        cases.append(Case(f"pairs {opt} {value}", ["pairs", "skate", "classic", *cmp, opt, value],
                          [opt]))  # fmt: skip
    for c in cases:
        c.group = "fleet"
    return cases


# -------------------------------------------------------------------------- explorer, report


def explorer_cases(d: Path) -> list[Case]:
    page = d / "e.html"
    grid = ["--mass-kg", "60", "--load-position-mm", "-120", "--snow-modulus-mpa", "100",
            "--stations", "16", "--workers", "0", "--out", str(page)]  # fmt: skip
    cases = [
        # the default grid of positions (6) and moduli (10)
        Case("explore 100000 masses", ["--allow-implausible", "explore", "skate", "--out",
             str(page), "--mass-kg", "1:100000:1"], ["--mass-kg", "solves"]),
        Case("explore 30000 masses x 4096 stations", ["explore", "skate", "--out", str(page),
             "--mass-kg", "1:300:0.01", "--stations", "4096"], ["--stations", "GiB"]),
        Case("explore grid of 1e9 values", ["explore", "skate", *grid, "--mass-kg",
             "5:130:1e-7"], ["--mass-kg"]),
        Case("explore unknown ski", ["explore", "skatte", *grid], ["skatte"]),
        Case("explore skate skate", ["explore", "skate", "skate", *grid], ["skate"]),
    ]  # fmt: skip
    for opt, value in (("--stations", "0"), ("--stations", "7"), ("--stations", "100000"),
                       ("--stations", "-1"), ("--snow-modulus-mpa", "nan"),
                       ("--snow-modulus-mpa", "1e8"), ("--snow-modulus-mpa", "0"),
                       ("--load-position-mm", "5000"), ("--mass-kg", "0"), ("--mass-kg", "nan"),
                       ("--ski-model", "bogus"), ("--profile-source", "bogus"),
                       ("--workers", "-1")):  # fmt: skip
        cases.append(Case(f"explore {opt} {value}", ["explore", "skate", *grid, opt, value],
                          [opt]))  # fmt: skip
    for c in cases:
        c.group = "explorer option"
        c.post = _nothing_in(page)
    return cases


def report_cases(d: Path) -> list[Case]:
    out = d / "report"
    base = ["report", "skate", "--mass-kg", "60", "--snow-modulus-mpa", "100", "--stride",
            "none", "--workers", "0", *SMALL, "--out", str(out)]  # fmt: skip
    cases = [Case("report unknown ski", ["report", "skatte", *base[2:]], ["skatte"])]
    for opt, value in (("--body-mass-kg", "0"), ("--body-mass-kg", "nan"),
                       ("--body-mass-kg", "65000"), ("--load-position-mm", "5000"),
                       ("--stride", "bogus"), ("--day-snow-mpa", "0"), ("--day-snow-mpa", "nan"),
                       ("--day-snow-mpa", "1e8"), ("--mass-kg", "nan"),
                       ("--snow-modulus-mpa", "1e8"), ("--points", "3"), ("--workers", "-1"),
                       ("--ski-model", "bogus"), ("--profile-source", "bogus"),
                       ("--compare-with", str(d / "missing.json")), ("--compare-with", "skate"),
                       ("--mass-kg", "1:300:0.00001")):  # fmt: skip
        cases.append(Case(f"report {opt} {Path(value).name}", [*base, opt, value], [opt]))
    for c in cases:
        c.group = "report option"
        c.post = _nothing_in(out)
    return cases


# -------------------------------------------------------------------------- side-cars


def sidecar_cases(d: Path) -> list[Case]:
    heights = np.random.default_rng(1).normal(0, 1e-6, (32, 32))
    cases = []
    docs: dict[str, tuple[str, list[str]]] = {
        "pixel_1m": ('{"dx_m": 1.0, "dy_m": 1.0}', ["dx_m"]),
        "pixel_1e-12": ('{"dx_m": 1e-12, "dy_m": 1e-12}', ["dx_m"]),
        "pixel_nan": ('{"dx_m": NaN, "dy_m": 1e-6}', ["dx_m"]),
        "pixel_negative": ('{"dx_m": -1e-6, "dy_m": 1e-6}', ["dx_m"]),
        "pixel_text": ('{"dx_m": "big", "dy_m": 1e-6}', ["dx_m"]),
        "nested": ('{"dx_m": 1e-6, "dy_m": 1e-6, "x": ' + "[" * 100_000 + "]" * 100_000 + "}",
                   ["nested"]),
        "height_unit_mm": ('{"dx_m": 1e-6, "dy_m": 1e-6, "height_unit": "mm"}', ["height_unit"]),
        "missing_dy": ('{"dx_m": 1e-6}', ["dy_m"]),
        "a_list": ("[1e-6, 1e-6]", []),
        "duplicate_key": ('{"dx_m": 1e-6, "dx_m": 1.0, "dy_m": 1e-6}', ["dx_m"]),
        "two_megabytes": ('{"dx_m": 1e-6, "dy_m": 1e-6, "pad": "' + "x" * (2 << 20) + '"}',
                          ["MiB"]),
    }  # fmt: skip
    for name, (text, detail) in docs.items():
        npy = d / f"side_{name}.npy"
        np.save(npy, heights)
        side = _write(d / f"side_{name}.npy.json", text)
        cases.append(Case(f"topo side-car {name}", ["topo", str(npy)], [side.name, *detail],
                          group="side-car"))  # fmt: skip
    npz = d / "side_npz_pixel_1m.npz"
    np.savez(npz, heights=heights, dx_m=np.float64(1.0), dy_m=np.float64(1.0))
    cases.append(Case("topo .npz pixel 1 m", ["topo", str(npz)], [npz.name, "dx_m"],
                      group="side-car"))  # fmt: skip
    return cases


# -------------------------------------------------------------------------- models, bombs


def _npy_header(shape: tuple[int, ...], dtype: str = "<f8") -> bytes:
    buf = io.BytesIO()
    np.lib.format.write_array_header_1_0(buf, {"descr": dtype, "fortran_order": False,
                                               "shape": shape})  # fmt: skip
    return buf.getvalue()


def _zip(members: dict[str, bytes], *, deflate: bool = False) -> bytes:
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED if deflate else zipfile.ZIP_STORED) as z:
        for name, data in members.items():
            z.writestr(name, data)
    return buf.getvalue()


def _deflate_bomb(name: str, n_bytes: int) -> bytes:
    """A real deflate bomb: one member of ``n_bytes`` zeros (as float64) behind a .npy header."""
    buf = io.BytesIO()
    with (
        zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z,
        z.open(name, "w", force_zip64=True) as fh,
    ):
        fh.write(_npy_header((n_bytes // 8,)))
        block = bytes(1 << 22)
        for _ in range(n_bytes // len(block)):
            fh.write(block)
    return buf.getvalue()


def _resign(doc: dict, npz: bytes) -> dict:
    """The model document re-signed as anyone could: both checksums recomputed."""
    from skisnow.network._files import metadata_checksum

    new = copy.deepcopy(doc)
    new["weights_sha256"] = hashlib.sha256(npz).hexdigest()
    new["metadata_sha256"] = metadata_checksum(new)
    return new


def model_and_bomb_cases(d: Path) -> list[Case]:
    from importlib import resources

    base = resources.files("skisnow.network") / "models"
    # the classic's record says its training ran a full-size LM phase (551 steps) to its budget,
    # so a re-signed edit of it is held to the load-response check (as one that converged)
    npz = (base / "classic.npz").read_bytes()
    doc = json.loads((base / "classic.json").read_text())
    pred = ["--mass-kg", "60", "--load-position-mm", "-120", "--dx-mm", "20"]
    cases = []

    def model(name: str, document: dict | str, weights: bytes = npz, *detail: str,
              group: str = "model (re-signed)", env: dict | None = None) -> None:  # fmt: skip
        (d / f"model_{name}.npz").write_bytes(weights)
        text = document if isinstance(document, str) else json.dumps(document)
        (d / f"model_{name}.json").write_text(text)
        cases.append(Case(f"predict {name}", ["predict", str(d / f"model_{name}"), *pred],
                          [f"model_{name}", *detail], group=group, env=env or {}))  # fmt: skip

    def edited(*path_value: tuple[tuple[str, ...], object]) -> dict:
        new = copy.deepcopy(doc)
        for path, value in path_value:
            node = new
            for k in path[:-1]:
                node = node[k]
            node[path[-1]] = value
        return _resign(new, npz)

    s = doc["scaling"]
    model(
        "height_scale_x1000",
        edited((("scaling", "height_scale"), s["height_scale"] * 1e3)),
        npz,
        "camber",
    )
    model("height_center_1m", edited((("scaling", "height_center"), 1.0)), npz, "camber")
    model(
        "mass_scale_1e-3",
        edited((("scaling", "mass_scale"), s["mass_scale"] * 1e-3)),
        npz,
        "load",
    )
    model("n_members_1000", edited((("n_members",), 1000)), npz, "n_members")
    model("width_100000", edited((("architecture", "load"), 100_000)), npz, "architecture")
    model("domain_mass_1000", edited((("domain", "mass_max"), 1000.0)), npz, "domain")
    nested = json.dumps(doc)[:-1] + ', "x": ' + "[" * 100_000 + "]" * 100_000 + "}"
    model("nested_json", nested, npz, "nested", group="nested JSON")
    dup = json.dumps(_resign(doc, npz)).replace('"n_members": 1', '"n_members": 1, '
                                                '"n_members": 100', 1)  # fmt: skip
    model("duplicate_key", dup, npz, "n_members")
    # archive bombs: a header that declares 298 GiB, a real deflate bomb, too many members
    forged = _zip({"member0/load0/weight.npy": _npy_header((40_000_000_000,)) + bytes(64)})
    model("header_298gib", _resign(doc, forged), forged, "GiB", group="archive bomb")
    bomb = _deflate_bomb("member0/load0/weight.npy", 1 << 28)
    model(
        "deflate_bomb",
        _resign(doc, bomb),
        bomb,
        "GiB",
        group="archive bomb",
        env={"SKISNOW_MEMORY_LIMIT_GIB": "0.1"},
    )
    many = _zip({f"m{i}.npy": _npy_header((1,)) + bytes(8) for i in range(12_000)})
    model("12000_members", _resign(doc, many), many, "members", group="archive bomb")
    topo = [("header_298gib.npz", _zip({"heights.npy": _npy_header((200_000, 200_000)) + bytes(64),
                                        "dx_m.npy": _npy_header(()) + bytes(8),
                                        "dy_m.npy": _npy_header(()) + bytes(8)}), ["GiB"], {}),
            ("deflate_bomb.npz", _deflate_bomb("heights.npy", 1 << 28), ["GiB"],
             {"SKISNOW_MEMORY_LIMIT_GIB": "0.1"}),
            ("header_298gib.npy", _npy_header((200_000, 200_000)) + bytes(64), ["GiB"], {}),
            ("object_header.npz", _zip({"heights.npy": _npy_header((4,), "|O") + bytes(32)}),
             ["pickle"], {})]  # fmt: skip
    for name, data, detail, env in topo:
        p = _write(d / f"bomb_{name}", data)
        args = ["topo", str(p)] + (["--pixel-um", "1"] if name.endswith(".npy") else [])
        cases.append(Case(f"topo {name}", args, [p.name, *detail], group="archive bomb",
                          env=env))  # fmt: skip
    return cases


def nested_json_cases(d: Path) -> list[Case]:
    from corpus import bench_data

    from skisnow.bench import write_bench

    good = d / "bench_ok.csv"
    write_bench(bench_data(), good)
    lines = good.read_text().splitlines()
    tag = "# skisnow-bench-metadata:"
    nested = [tag + " " + "[" * 100_000 + "]" * 100_000 if ln.startswith(tag) else ln
              for ln in lines]  # fmt: skip
    bench = _write(d / "bench_nested_metadata.csv", "\n".join(nested) + "\n")
    cases = [Case("metrics bench nested metadata", ["metrics", str(bench)],
                  [bench.name, "nested"], group="nested JSON")]  # fmt: skip
    # a sweep store whose attributes are a nested bomb, or whose grid is in grams
    from skisnow.sweep import SweepSpec, run_sweep

    spec = SweepSpec(skis=("skate",), masses=(60.0,), load_positions=(-0.12,),
                     snow_moduli=(100e6,), n_points=64)  # fmt: skip
    store = d / "store_ok.zarr"
    run_sweep(spec, store, workers=0, chunk_function=_cheap_chunk)
    for name, edit in (
        ("nested_attrs", lambda t: t[:-1] + ', "x": ' + "[" * 100_000 + "]" * 100_000 + "}"),
        ("grams", lambda t: re.sub(r'(\\"masses\\": \[)60\.0', r"\g<1>60000.0", t)),
    ):
        copy_ = d / f"store_{name}.zarr"
        import shutil

        shutil.copytree(store, copy_)
        attrs = copy_ / ".zattrs"
        attrs.write_text(edit(attrs.read_text()))
        cases.append(Case(f"plot store {name}", ["plot", str(copy_), "--out", str(d / "f")],
                          [copy_.name], group="nested JSON" if "nested" in name
                          else "sweep store"))  # fmt: skip
    return cases


def _cheap_chunk(spec, ski, position, modulus):
    from skisnow.sweep import VARIABLES

    n_m, n_z = len(spec.masses), len(spec.zones)
    out = {}
    for name, var in VARIABLES.items():
        shape = (n_m, n_z) if "zone" in var.dims else (n_m,)
        out[name] = np.ones(shape).astype(var.dtype)
    return out


# -------------------------------------------------------------------------- name injection

NAMES = {
    "path_up": "../../escaped",
    "absolute": "{tmp}/absolute-escape",  # an absolute path inside the corpus's folder
    "script_comment": "</script><!--<script>",
    "quotes": "\"'<b>&amp;",
    "ansi": "\x1b[2J\x1b[31mred",
    "bidi": "\u202eevil",
    "long": "n" * 5000,
    "dots": "..",
    "nul": "a\x00b",
}


def _only_inside(out: Path, outside: list[Path]) -> Callable[[], str | None]:
    def post() -> str | None:
        for p in outside:
            if p.exists():
                return f"wrote outside --out: {p}"
        pages = list(out.glob("*.html")) if out.is_dir() else []
        if not pages:
            return "no report page was written inside --out"
        text = pages[0].read_text(encoding="utf-8")  # the report has no scripts at all
        for raw in ("<script", "<!--<", "<b>"):
            if raw in text:
                return f"{pages[0].name}: holds {raw!r} (a name reached the page unescaped)"
        return None

    return post


def _script_blocks_safe(page: Path) -> str | None:
    """Inside a <script> element the HTML tokenizer stays in script data as long as the text
    holds no '<' (the only character that can end the element, or open '<!--' and move it to a
    state that merges blocks): every script block must be free of it."""
    text = page.read_text(encoding="utf-8")
    blocks = re.findall(r'<script type="application/[^>]*>(.*?)</script>', text, re.S)
    if len(blocks) != 2 or len(re.findall(r"<script", text)) != 3:
        return f"{page.name}: not the page's three script blocks (a name ended or merged one)"
    for b in blocks:  # the data blocks: where the names are
        if "<" in b:
            return f"{page.name}: a data block holds '<' (a name can end or merge blocks)"
    return None


def _no_control(text: str) -> str | None:
    bad = re.search("[\x00-\x08\x0b-\x1f\x7f\u202a-\u202e]", text)
    return f"raw control character {bad.group()!r} printed" if bad else None


def name_cases(d: Path) -> list[Case]:
    cases = []
    for key, name in NAMES.items():
        name = name.replace("{tmp}", str(d.parent))
        path = _ski_file(d, f"name_{key}", edit=_set("name", name))
        out = d / f"out_{key}"
        outside = [d / "escaped_report.html", d.parent / "absolute-escape_report.html",
                   d.parent / "escaped_report.html"]  # fmt: skip
        cases.append(Case(
            f"report named {key}",
            ["report", str(path), "--mass-kg", "60", "--snow-modulus-mpa", "100", "--stride",
             "none", "--workers", "0", *SMALL, "--out", str(out)],
            [], post=_only_inside(out, outside), expect="accept"))  # fmt: skip
        page = d / f"explore_{key}.html"
        cases.append(Case(
            f"explore named {key}",
            ["explore", str(path), "--mass-kg", "60", "--load-position-mm", "-120",
             "--snow-modulus-mpa", "100", "--stations", "16", "--workers", "0", "--out",
             str(page)], [], post=lambda page=page: _script_blocks_safe(page),
            expect="accept"))  # fmt: skip
        cases.append(Case(f"skis --show named {key}", ["skis", "--show", str(path)], [],
                          post_output=_no_control, expect="accept"))  # fmt: skip
    for key in ("ansi", "bidi"):
        weird = _ski_file(d, f"file_{key}")
        renamed = weird.with_name(f"ski{NAMES[key]}.json")
        weird.rename(renamed)
        cases.append(Case(f"compare file named {key}", ["compare", str(renamed), "skate",
                          "--body-mass-kg", "60", "--snow-modulus-mpa", "100",
                          "--snow-range-mpa", "100,200", *SMALL], [],
                          post_output=_no_control, expect="accept"))  # fmt: skip
    for c in cases:
        c.group = "name injection"
    return cases


DOOR_GROUPS = (ski_file_cases, history_cases, fleet_cases, explorer_cases, report_cases,
               sidecar_cases, model_and_bomb_cases, nested_json_cases, name_cases)  # fmt: skip
