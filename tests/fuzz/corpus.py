"""A corpus of malformed inputs over every file skisnow reads and every option it takes.

Each :class:`Case` is one ``skisnow ...`` command line whose input is wrong: impossible (NaN, a
negative mass, a pixel of 0 µm), implausible for a ski (heights in metres in a ``height_mm``
column, a 20 m ski, −300 °C, a load that lifts the ski), corrupt (truncated instrument files,
pickled ``.npy`` payloads, a ``.npz`` named ``.npy``, model files with NaN scales or a widened
domain) or unusable (a grid that would need 149 GiB). Every case is run IN-PROCESS through
``skisnow.cli.main`` and classified:

* ``clean``: rejected with a one-line message (exit code != 0, a skisnow error or a usage error);
* ``traceback``: an exception that is not one of skisnow's errors (a bug) escaped;
* ``silent``: accepted (exit code 0) — a silently wrong result;
* ``side effect``: rejected, but something was left behind (a store created before the input
  was validated) or something was executed (a pickle payload fired).

A clean rejection *names its place* when the message contains the option or the file name and,
where the case knows it, the row or column; it *says what is valid* when it says what was
expected.

Run ``uv run python tests/fuzz/corpus.py`` to print the tally (``--cases`` lists each case,
``--timeout S`` stops a case still computing after S seconds, ``--only TEXT`` runs the cases
whose group or id holds TEXT). The cases of the doors added later (ski files, load histories,
fleets, the explorer and report options, side-cars, re-signed models, archive bombs, nested
JSON, name injection) are in ``corpus_doors.py``.
"""

from __future__ import annotations

import contextlib
import functools
import io
import json
import os
import pickle
import re
import shutil
import sys
import time
import warnings
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

SHARED_TOPOGRAPHIES = Path(__file__).resolve().parents[3] / "shared" / "data" / "topographies"

#: skisnow's own errors (a clean rejection names one of them, or is a usage error)
CLEAN_ERRORS = {
    "SkisnowError",
    "InputError",
    "FileFormatError",
    "ImplausibleValueError",
    "UnsupportedLoadError",
    "ConvergenceError",
    "MissingDependencyError",  # an InputError: an optional extra is needed (it names the extra)
}
VALID_WORDS = re.compile(
    r"need|expect|valid|must|use |should|at least|allowed|give |only|choose|possible|"
    r"implausible|was it|instead|not a |unknown|no such|missing|invalid|is not|cannot|"
    r"look like|corrupt|truncated|differ",
    re.IGNORECASE,
)


@dataclass
class Case:
    """One malformed input: the command line, what must be named, optional after-checks."""

    id: str
    argv: list[str]
    place: list[str]  # every entry must appear in the message; "a|b" means a or b
    post: Callable[[], str | None] | None = None  # returns a problem, or None
    group: str = ""
    #: "refuse" (a malformed input) or "accept" (a valid but hostile one: a ski named
    #: "</script>" must be accepted, its name escaped wherever it goes; ``post`` checks that)
    expect: str = "refuse"
    env: dict[str, str] = field(default_factory=dict)  # environment of the run (memory limit)
    #: checks the text the run printed (stdout and stderr): returns a problem, or None
    post_output: Callable[[str], str | None] | None = None
    builder: str = ""  # the function of the corpus that made it (filled in by build_corpus)


@dataclass
class Outcome:
    case: Case
    kind: str  # clean, traceback, silent, side effect
    code: int
    message: str
    names_place: bool = False
    says_valid: bool = False
    seconds: float = 0.0
    warnings: list[str] = field(default_factory=list)
    cpu: float = 0.0  # CPU seconds of this process (time.process_time): load-independent


# --------------------------------------------------------------------------------------------
# fixtures: valid files, then their corruptions


class _Payload:
    """A pickle payload: unpickling it writes a sentinel file (it must never run)."""

    def __init__(self, sentinel: str) -> None:
        self.sentinel = sentinel

    def __reduce__(self):
        return (Path.write_text, (Path(self.sentinel), "pickle payload executed"))


@functools.cache
def bench_data():
    """The virtual bench of the skate (3 masses at one position, 20 mm step), computed once for
    every group that needs a valid bench file."""
    from skisnow.bench import run_bench

    return run_bench("skate", masses=[20.0, 60.0, 100.0], load_positions=[-0.12], dx=0.02)


def _bench_table(d: Path) -> tuple[Path, list[str]]:
    """A valid bench CSV (:func:`bench_data`) and its lines."""
    from skisnow.bench import write_bench

    path = d / "bench_ok.csv"
    write_bench(bench_data(), path)
    return path, path.read_text().splitlines()


def _write(path: Path, text: str | bytes) -> Path:
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text)
    return path


def _transform_bench(lines: list[str], col: str, fn: Callable[[np.ndarray], np.ndarray]) -> str:
    import pandas as pd

    n_comment = sum(1 for ln in lines if ln.startswith("#"))
    table = pd.read_csv(io.StringIO("\n".join(lines[n_comment:])))
    table[col] = fn(table[col].to_numpy(dtype=float))
    return "\n".join(lines[:n_comment]) + "\n" + table.to_csv(index=False, float_format="%.17g")


def _set_cell(lines: list[str], line_no: int, col: int, value: str) -> tuple[str, int]:
    """Replace one cell of the CSV at 1-based ``line_no``; return the text and that line."""
    out = list(lines)
    cells = out[line_no - 1].split(",")
    cells[col] = value
    out[line_no - 1] = ",".join(cells)
    return "\n".join(out) + "\n", line_no


def bench_cases(d: Path) -> list[Case]:
    good, lines = _bench_table(d)
    n_comment = sum(1 for ln in lines if ln.startswith("#"))
    first = n_comment + 2  # the line of the first data row (1-based; header before it)
    files: dict[str, tuple[Path, list[str]]] = {}

    def add(name: str, text: str | bytes, *detail: str) -> None:
        files[name] = (_write(d / f"bench_{name}.csv", text), list(detail))

    add("heights_in_m", _transform_bench(lines, "height_mm", lambda h: h * 1e-3), "height_mm")
    add("x_in_m", _transform_bench(lines, "x_mm", lambda x: x * 1e-3), "x_mm")
    add("negative_heights", _transform_bench(lines, "height_mm", lambda h: -h), "height_mm")
    add("heights_in_um", _transform_bench(lines, "height_mm", lambda h: h * 1e3), "height_mm")
    add("ski_20m", _transform_bench(lines, "x_mm", lambda x: x * 10.0), "x_mm")
    add("mass_in_g", _transform_bench(lines, "mass_kg", lambda m: m * 1e3), "mass_kg")
    add(
        "position_in_m",
        _transform_bench(lines, "load_position_mm", lambda p: p * 1e-3),
        "load_position_mm",
    )
    add(
        "heavier_sits_higher",
        _transform_bench(lines, "mass_kg", lambda m: 120.0 - m),  # 20 <-> 100 kg
        "mass_kg",
    )
    text, ln = _set_cell(lines, first + 7, 4, "nan")
    add("nan_height", text, f"line {ln}", "height_mm")
    text, ln = _set_cell(lines, first + 3, 3, "inf")
    add("inf_x", text, f"line {ln}", "x_mm")
    text, ln = _set_cell(lines, first + 4, 4, "abc")
    add("text_height", text, f"line {ln}", "height_mm")
    text, ln = _set_cell(lines, first + 2, 1, "0")
    add("zero_mass", text, f"line {ln}", "mass_kg")
    text, ln = _set_cell(lines, first + 2, 1, "-60")
    add("negative_mass", text, f"line {ln}", "mass_kg")
    text, ln = _set_cell(lines, first + 5, 4, "1e300")
    add("huge_height", text, f"line {ln}", "height_mm")
    add("empty", "")
    add("header_only", ",".join(["ski", "mass_kg", "load_position_mm", "x_mm", "height_mm"]))
    add(
        "renamed_column",
        "\n".join(
            [
                *lines[:n_comment],
                lines[n_comment].replace("height_mm", "h"),
                *lines[n_comment + 1 :],
            ]
        ),
        "height_mm",
    )
    add(
        "extra_column",
        "\n".join(
            [*lines[:n_comment], lines[n_comment] + ",extra"]
            + [ln + ",1" for ln in lines[n_comment + 1 :]]
        ),
        "extra",
    )
    add("semicolons", "\n".join(ln.replace(",", ";") for ln in lines))
    add("duplicate_row", "\n".join([*lines, lines[first + 3]]), "x_mm")
    rev = lines[: first - 1] + list(reversed(lines[first - 1 : first + 20])) + lines[first + 20 :]
    add("x_decreasing", "\n".join(rev), "x_mm")
    add("five_point_profile", "\n".join(lines[: first + 4]), "x_mm")
    add("truncated_mid_row", "\n".join(lines)[: len("\n".join(lines)) // 2 + 7])
    add("binary_garbage", os.urandom(3000))
    add("latin1", ("\n".join(lines) + "\n# caf\xe9\n").encode("latin-1"))
    add(
        "broken_metadata",
        "\n".join(
            ln if not ln.startswith("# skisnow-bench-metadata:") else ln[:-5] for ln in lines
        ),
        "metadata",
    )
    files["parquet_named"] = (_write(d / "bench_csv.parquet", "\n".join(lines)), [])
    files["txt_suffix"] = (_write(d / "bench.txt", "\n".join(lines)), [])
    (d / "bench_dir.csv").mkdir()
    files["directory"] = (d / "bench_dir.csv", [])
    files["missing"] = (d / "bench_missing.csv", [])

    cases = []
    for name, (path, detail) in files.items():
        place = [path.name, *detail]
        cases.append(
            Case(
                f"metrics/{name}",
                ["metrics", str(path), "--load-position-mm", "-120"],
                place,
                group="bench file",
            )
        )
    train_opts = ["--adam-steps", "2", "--lm-steps", "0", "--out", str(d / "model_from_bad")]
    for name in (
        "heights_in_m",
        "x_in_m",
        "negative_heights",
        "heavier_sits_higher",
        "nan_height",
        "mass_in_g",
        "five_point_profile",
        "empty",
    ):
        path, detail = files[name]
        cases.append(
            Case(
                f"train/{name}",
                ["train", str(path), *train_opts],
                [path.name, *detail],
                group="bench file",
            )
        )
    for opt, value in (
        ("--body-mass-kg", "0"),
        ("--body-mass-kg", "nan"),
        ("--body-mass-kg", "-65"),
        ("--body-mass-kg", "65000"),
        ("--load-position-mm", "5000"),
        ("--load-position-mm", "nan"),
    ):
        cases.append(
            Case(f"metrics {opt} {value}", ["metrics", "skate", opt, value], [opt], group="option")
        )
    for opt, value in (
        ("--widths", "6,16,16"),
        ("--widths", "0,16,16,16,12,12"),
        ("--widths", "a,b"),
        ("--adam-steps", "-1"),
        ("--lm-steps", "-5"),
        ("--ensemble", "0"),
        ("--ensemble", "-2"),
    ):
        cases.append(
            Case(
                f"train {opt} {value}",
                ["train", str(good), *train_opts, opt, value],
                [opt],
                group="option",
            )
        )
    return cases  # fmt: skip


def virtual_bench_cases(d: Path) -> list[Case]:
    out = d / "vb.csv"
    base = ["bench", "skate", "--out", str(out), "--mass-kg", "20,60", "--load-position-mm",
            "-120", "--dx-mm", "10"]  # fmt: skip
    cases = [
        Case("bench unknown ski", ["bench", "skatte", "--out", str(out)], ["skatte"]),
        Case("bench --out .txt", [*base[:3], str(d / "vb.txt"), *base[4:]], ["--out"]),
    ]
    for opt, value in (
        ("--mass-kg", "0"),
        ("--mass-kg", "-5"),
        ("--mass-kg", "nan"),
        ("--mass-kg", "a:b:c"),
        ("--mass-kg", "10:5:1"),
        ("--mass-kg", "60000"),
        ("--load-position-mm", "5000"),
        ("--load-position-mm", "inf"),
        ("--noise-mm", "-1"),
        ("--noise-mm", "nan"),
        ("--noise-mm", "10"),
        ("--dx-mm", "0"),
        ("--dx-mm", "-1"),
        ("--dx-mm", "nan"),
        ("--dx-mm", "1e-7"),
        ("--dx-mm", "5000"),
    ):
        cases.append(Case(f"bench {opt} {value}", [*base, opt, value], [opt]))
    for c in cases:
        c.group = "option"
    return cases  # fmt: skip


def profile_cases(d: Path) -> list[Case]:
    from skisnow.network import camber_profile

    x = np.linspace(-0.9, 0.92, 200)
    _, h = camber_profile("skate", mass=60.0, load_position=-0.12, x=x, source="beam")
    good = d / "profile_ok.csv"
    rows = [f"{a * 1e3:.9g},{b * 1e3:.9g}" for a, b in zip(x, h, strict=True)]
    _write(good, "x_mm,height_mm\n" + "\n".join(rows) + "\n")
    base = ["contact", "--mass-kg", "60", "--load-position-mm", "-120", "--snow-modulus-mpa",
            "100"]  # fmt: skip
    variants: dict[str, tuple[str | bytes, list[str]]] = {}

    def scaled(fx: float, fh: float, sign: float = 1.0) -> str:
        body = [f"{a * 1e3 * fx:.9g},{sign * b * 1e3 * fh:.9g}" for a, b in zip(x, h, strict=True)]
        return "x_mm,height_mm\n" + "\n".join(body) + "\n"

    lines = ["x_mm,height_mm", *rows]
    variants["heights_in_m"] = (scaled(1, 1e-3), ["height_mm"])
    variants["x_in_m"] = (scaled(1e-3, 1), ["x_mm"])
    variants["negative_heights"] = (scaled(1, 1, -1.0), ["height_mm"])
    variants["ski_20m"] = (scaled(10, 1), ["x_mm"])
    bad = list(lines)
    bad[30] = bad[30].split(",")[0] + ",nan"
    variants["nan_height"] = ("\n".join(bad), ["line 31", "height_mm"])
    bad = ["# measured 2026-01-10", "# operator: test", *lines]
    bad[40] = "abc," + bad[40].split(",")[1]
    variants["text_x_after_comments"] = ("\n".join(bad), ["line 41", "x_mm"])
    variants["one_column"] = ("x_mm\n" + "\n".join(r.split(",")[0] for r in rows), ["height_mm"])
    variants["five_rows"] = ("\n".join(lines[:6]), [])
    variants["x_decreasing"] = ("\n".join([lines[0], *reversed(lines[1:])]), ["x_mm"])
    bad = list(lines)
    bad[51] = bad[50]
    variants["duplicate_x"] = ("\n".join(bad), ["line 52", "x_mm"])
    variants["empty"] = ("", [])
    variants["binary"] = (os.urandom(2000), [])
    variants["tab_separated"] = ("\n".join(ln.replace(",", "\t") for ln in lines), [])
    variants["flat_zero"] = ("x_mm,height_mm\n" + "\n".join(
        f"{a * 1e3:.9g},0" for a in x), ["height_mm"])  # fmt: skip
    cases = []
    for name, (text, detail) in variants.items():
        p = _write(d / f"profile_{name}.csv", text)
        cases.append(Case(f"contact --profile {name}", [*base, "--profile", str(p)],
                          [p.name, *detail], group="profile file"))  # fmt: skip
    missing = d / "profile_missing.csv"
    cases.append(Case("contact --profile missing", [*base, "--profile", str(missing)],
                      [missing.name], group="profile file"))  # fmt: skip
    ski = [*base, "--ski", "skate", "--profile-source", "beam", "--points", "256"]
    for opt, value in (
        ("--mass-kg", "0"),
        ("--mass-kg", "-60"),
        ("--mass-kg", "nan"),
        ("--mass-kg", "inf"),
        ("--mass-kg", "60000"),
        ("--load-position-mm", "5000"),
        ("--load-position-mm", "nan"),
        ("--snow-modulus-mpa", "0"),
        ("--snow-modulus-mpa", "-5"),
        ("--snow-modulus-mpa", "nan"),
        ("--snow-modulus-mpa", "1e8"),
        ("--width-mm", "0"),
        ("--width-mm", "0.044"),
        ("--width-mm", "nan"),
        ("--base-modulus-mpa", "0"),
        ("--base-modulus-mpa", "9e8"),
        ("--points", "0"),
        ("--points", "3"),
        ("--points", "-1"),
        ("--points", "1000000000"),
        ("--n-across", "0"),
        ("--n-across", "-1"),
        ("--model", "fem"),
        ("--profile-source", "laser"),
        ("--ski", "skatte"),
    ):
        cases.append(Case(f"contact {opt} {value}", [*ski, opt, value], [opt], group="option"))
    cases.append(Case("contact no ski no profile", base, ["--ski", "--profile"], group="option"))
    cases.append(Case("contact ski and profile", [*ski, "--profile", str(good)],
                      ["--ski", "--profile"], group="option"))  # fmt: skip
    return cases


def topography_cases(d: Path) -> list[Case]:
    from skisnow import micro

    t = micro.grind_preset("S1", size=64e-6, dx=1e-6)
    good = d / "topo_ok.npy"
    np.save(good, np.asarray(t.heights))
    x3p = micro.write_topography(t, d / "topo_ok.x3p")
    files: dict[str, tuple[Path, list[str], list[str]]] = {}  # path, extra args, detail

    def add(name: str, path: Path, *args: str, detail: tuple[str, ...] = ()) -> None:
        files[name] = (path, list(args), list(detail))

    px = ("--pixel-um", "1")
    counts = (np.asarray(t.heights) / np.nanmax(np.abs(t.heights)) * 30000).astype(np.int32)
    np.save(d / "topo_int.npy", counts)
    add("integer_counts", d / "topo_int.npy", *px)
    np.save(d / "topo_nm.npy", np.asarray(t.heights) * 1e9)
    add("heights_in_nm_as_m", d / "topo_nm.npy", *px)
    sentinel = d / "PICKLE_FIRED"
    np.save(d / "topo_pickle.npy", np.array([_Payload(str(sentinel))], dtype=object),
            allow_pickle=True)  # fmt: skip
    add("pickled_npy", d / "topo_pickle.npy", *px)
    with open(d / "topo_pickle_raw.npy", "wb") as fh:
        pickle.dump(_Payload(str(sentinel)), fh)
    add("raw_pickle_named_npy", d / "topo_pickle_raw.npy", *px)
    np.savez(d / "topo_npz.npz", heights=np.asarray(t.heights))
    shutil.copy(d / "topo_npz.npz", d / "topo_npz_named.npy")
    add("npz_named_npy", d / "topo_npz_named.npy", *px)
    np.save(d / "topo_1d.npy", np.asarray(t.heights).ravel())
    add("one_dimensional", d / "topo_1d.npy", *px)
    np.save(d / "topo_3d.npy", np.asarray(t.heights)[None])
    add("three_dimensional", d / "topo_3d.npy", *px)
    np.save(d / "topo_complex.npy", np.asarray(t.heights) * (1 + 1j))
    add("complex", d / "topo_complex.npy", *px)
    np.save(d / "topo_bool.npy", np.asarray(t.heights) > 0)
    add("boolean", d / "topo_bool.npy", *px)
    np.save(d / "topo_nan.npy", np.full((16, 16), np.nan))
    add("all_nan", d / "topo_nan.npy", *px)
    h = np.array(t.heights)
    h[3, 4] = np.inf
    np.save(d / "topo_inf.npy", h)
    add("inf_pixel", d / "topo_inf.npy", *px)
    np.save(d / "topo_1x1.npy", np.zeros((1, 1)))
    add("one_pixel", d / "topo_1x1.npy", *px)
    raw = good.read_bytes()
    _write(d / "topo_trunc.npy", raw[: len(raw) // 2])
    add("truncated_npy", d / "topo_trunc.npy", *px)
    _write(d / "topo_empty.npy", b"")
    add("empty_npy", d / "topo_empty.npy", *px)
    add("npy_without_pixel", good)
    rows = [" ".join(f"{v:.6g}" for v in r) for r in np.asarray(t.heights)[:8, :8]]
    rows[5] = rows[5].replace(rows[5].split()[2], "xyz", 1)
    _write(d / "topo_bad.txt", "\n".join(rows))
    add("text_bad_cell", d / "topo_bad.txt", *px)
    ragged = "\n".join([*rows[:4], " ".join(rows[4].split()[:3]), *rows[6:]]).replace("xyz", "1")
    _write(d / "topo_ragged.txt", ragged)
    add("text_ragged_row", d / "topo_ragged.txt", *px)
    xb = x3p.read_bytes()
    _write(d / "topo_trunc.x3p", xb[: len(xb) // 2])
    add("truncated_x3p", d / "topo_trunc.x3p")
    _write(d / "topo_garbage.x3p", os.urandom(4000))
    add("garbage_x3p", d / "topo_garbage.x3p")
    for ext in ("opd", "plu", "sur", "al3d"):
        real = sorted(SHARED_TOPOGRAPHIES.glob(f"*.{ext}")) if SHARED_TOPOGRAPHIES.is_dir() else []
        blob = real[0].read_bytes()[:1500] if real else b"\x00" * 1500
        _write(d / f"topo_trunc.{ext}", blob)
        add(f"truncated_{ext}", d / f"topo_trunc.{ext}")
    _write(d / "topo_unknown.xyz123", b"hello")
    add("unknown_format", d / "topo_unknown.xyz123")
    add("missing_file", d / "topo_missing.npy", *px)
    cases = []
    for name, (path, args, detail) in files.items():

        def post(s=sentinel):
            return "a pickle payload was executed" if s.exists() else None

        cases.append(Case(f"topo {name}", ["topo", str(path), *args], [path.name, *detail],
                          post=post, group="topography file"))  # fmt: skip
    for name in (
        "integer_counts",
        "pickled_npy",
        "npz_named_npy",
        "truncated_x3p",
        "truncated_opd",
    ):
        path, args, detail = files[name]
        cases.append(Case(f"bearing {name}", ["bearing", str(path), *args, "--grain-um", "500"],
                          [path.name, *detail], group="topography file"))  # fmt: skip
    topo = ["topo", str(good)]
    for opt, value in (
        ("--pixel-um", "0"),
        ("--pixel-um", "-1"),
        ("--pixel-um", "nan"),
        ("--pixel-um", "inf"),
        ("--pixel-um", "1e-6"),
        ("--pixel-um", "1e5"),
        ("--height-unit", "furlong"),
        ("--cutoff-um", "-5"),
        ("--cutoff-um", "nan"),
        ("--form", "cubic"),
    ):
        args = [*topo, *px, opt, value] if opt != "--pixel-um" else [*topo, opt, value]
        cases.append(Case(f"topo {opt} {value}", args, [opt], group="option"))
    grind = ["grind", "S1", "--out", str(d / "g.npy"), "--size-um", "64"]
    for opt, value in (
        ("--pixel-um", "0"),
        ("--pixel-um", "-1"),
        ("--pixel-um", "nan"),
        ("--pixel-um", "inf"),
        ("--pixel-um", "1e-9"),
        ("--size-um", "0"),
        ("--size-um", "-5"),
        ("--size-um", "nan"),
        ("--size-um", "1e9"),
    ):
        cases.append(Case(f"grind {opt} {value}", [*grind, opt, value], [opt], group="option"))
    cases.append(Case("grind preset S9", ["grind", "S9", "--out", str(d / "g.npy")], ["S9"],
                      group="option"))  # fmt: skip
    cases.append(
        Case(
            "grind --out .png",
            ["grind", "S1", "--out", str(d / "g.png"), "--size-um", "64"],
            ["--out|g.png"],
            group="option",
        )
    )
    bearing = ["bearing", str(good), *px, "--grain-um", "500"]
    for opt, value in (
        ("--temperature-c", "-300"),
        ("--temperature-c", "5"),
        ("--temperature-c", "nan"),
        ("--temperature-c", "268"),
        ("--pressure-kpa", "0"),
        ("--pressure-kpa", "-1"),
        ("--pressure-kpa", "nan"),
        ("--pressure-kpa", "2e7"),
        ("--grain-um", "0"),
        ("--grain-um", "-5"),
        ("--grain-um", "abc"),
        ("--grain-um", "700:500:10"),
        ("--grain-um", "nan"),
        ("--grain-um", "0.5"),
        ("--hardness-model", "vickers"),
        ("--stride", "0"),
        ("--stride", "-1"),
        ("--workers", "0"),
        ("--workers", "-1"),
        ("--cutoff-um", "-1"),
    ):
        cases.append(Case(f"bearing {opt} {value}", [*bearing, opt, value], [opt],
                          group="option"))  # fmt: skip
    return cases  # fmt: skip


def rank_cases(d: Path) -> list[Case]:
    good = ["structure,glide_time_s,A_fr,Sa_um", "S1,10.2,0.011,1.2", "S2,10.5,0.013,1.9",
            "S3,10.1,0.010,0.9", "S4,10.9,0.016,2.4", "S5,10.4,0.012,1.5"]  # fmt: skip
    ok = _write(d / "rank_ok.csv", "\n".join(good) + "\n")
    variants: dict[str, tuple[str | bytes, list[str]]] = {
        "nan_time": ("\n".join([good[0], good[1], "S2,nan,0.013,1.9", *good[3:]]),
                     ["row 3|line 3", "glide_time_s"]),
        "negative_time": ("\n".join([good[0], good[1], "S2,-10.5,0.013,1.9", *good[3:]]),
                          ["row 3|line 3", "glide_time_s"]),
        "two_rows": ("\n".join(good[:3]), []),
        "missing_time_column": ("\n".join(ln.split(",", 2)[0] + "," + ln.split(",", 2)[2]
                                          for ln in good), ["glide_time_s"]),
        "text_descriptor": ("\n".join([*good[:4], "S4,10.9,high,2.4", good[5]]),
                            ["row 5|line 5", "A_fr"]),
        "duplicate_structure": ("\n".join([*good, "S3,10.1,0.010,0.9"]), ["S3"]),
        "constant_descriptor": ("\n".join([good[0].replace(",Sa_um", "")] + [
            ",".join(ln.split(",")[:2]) + ",0.5" for ln in good[1:]]), ["A_fr"]),
        "constant_times": ("\n".join([good[0]] + [ln.split(",")[0] + ",10.0," + ",".join(
            ln.split(",")[2:]) for ln in good[1:]]), ["glide_time_s"]),
        "no_descriptor": ("\n".join(",".join(ln.split(",")[:2]) for ln in good), []),
        "empty": ("", []),
        "binary": (os.urandom(500), []),
    }  # fmt: skip
    cases = []
    for name, (text, detail) in variants.items():
        p = _write(d / f"rank_{name}.csv", text)
        cases.append(Case(f"rank {name}", ["rank", str(p)], [p.name, *detail],
                          group="glide table"))  # fmt: skip
    for value in ("2", "0", "-0.1", "nan", "1", "0.9"):
        cases.append(Case(f"rank --alpha {value}", ["rank", str(ok), "--alpha", value],
                          ["--alpha"], group="option"))  # fmt: skip
    return cases


def model_cases(d: Path) -> list[Case]:
    from importlib import resources

    base = resources.files("skisnow.network") / "models"
    npz = (base / "skate.npz").read_bytes()
    doc = json.loads((base / "skate.json").read_text())
    other = (base / "classic.npz").read_bytes()

    def model(name: str, npz_bytes: bytes | None, document: object, raw: str | None = None) -> Path:
        p = d / f"model_{name}"
        if npz_bytes is not None:
            (d / f"model_{name}.npz").write_bytes(npz_bytes)
        text = raw if raw is not None else json.dumps(document)
        (d / f"model_{name}.json").write_text(text)
        return p

    def edited(path: tuple[str, ...], value: object, *, rehash: bool = False) -> dict:
        new = json.loads(json.dumps(doc))
        node = new
        for k in path[:-1]:
            node = node[k]
        node[path[-1]] = value
        return new

    import hashlib

    def pickled_npz() -> tuple[bytes, dict]:
        buf = io.BytesIO()
        np.savez(buf, **{"member0/load0/weight": np.array([object()], dtype=object)})
        data = buf.getvalue()
        new = dict(doc, weights_sha256=hashlib.sha256(data).hexdigest())
        return data, new

    variants: dict[str, tuple[Path, list[str]]] = {}
    for name, key, value in (
        ("nan_scale", ("scaling", "x_scale"), float("nan")),
        ("zero_scale", ("scaling", "height_scale"), 0.0),
        ("negative_scale", ("scaling", "mass_scale"), -62.5),
        ("inf_center", ("scaling", "mass_center"), float("inf")),
        ("widened_domain", ("domain", "mass_max"), 1000.0),
        ("inverted_domain", ("domain", "position_min"), 0.5),
        ("string_scale", ("scaling", "x_scale"), "big"),
        ("future_version", ("format_version",), 99),
        ("foreign_format", ("format",), "keras"),
        ("zero_members", ("n_members",), 0),
        ("negative_width", ("architecture", "load"), -6),
        ("reference_n_mismatch", ("reference", "n"), 17),
        ("reference_window_moved", ("reference", "x_max"), 9.4),
    ):
        variants[name] = (model(name, npz, edited(key, value)), [])
    variants["truncated_npz"] = (model("truncated_npz", npz[: len(npz) // 2], doc), [".npz"])
    variants["npz_of_other_ski"] = (model("other_npz", other, doc), [".npz"])
    variants["json_invalid"] = (model("json_invalid", npz, None, raw="{not json"), [".json"])
    variants["json_list"] = (model("json_list", npz, [1, 2, 3]), [".json"])
    variants["npz_missing"] = (model("npz_missing", None, doc), [".npz"])
    data, new = pickled_npz()
    variants["pickled_npz"] = (model("pickled", data, new), [])
    variants["no_such_model"] = (d / "model_nothing_here", [])
    cases = []
    for name, (path, detail) in variants.items():
        argv = ["predict", str(path), "--mass-kg", "60", "--load-position-mm", "-120",
                "--dx-mm", "20"]  # fmt: skip
        cases.append(Case(f"predict {name}", argv, [path.name, *detail], group="model file"))
    pred = ["predict", "skate", "--mass-kg", "60", "--load-position-mm", "-120", "--dx-mm", "20"]
    for opt, value in (
        ("--mass-kg", "nan"),
        ("--mass-kg", "0"),
        ("--mass-kg", "-1"),
        ("--dx-mm", "0"),
        ("--dx-mm", "1e-7"),
        ("--dx-mm", "nan"),
        ("--load-position-mm", "nan"),
        ("--load-position-mm", "5000"),
    ):
        cases.append(Case(f"predict {opt} {value}", [*pred, opt, value], [opt], group="option"))
    return cases  # fmt: skip


def sweep_cases(d: Path) -> list[Case]:
    cases = []

    def not_created(p: Path) -> Callable[[], str | None]:
        return lambda: f"{p.name} was created by a rejected sweep" if p.exists() else None

    base = ["--mass-kg", "20,60", "--load-position-mm", "-120", "--snow-modulus-mpa", "100",
            "--points", "256", "--workers", "0", "--profile-source", "beam"]  # fmt: skip
    for i, (opt, value) in enumerate((
        ("--ski", "skatte"), ("--mass-kg", "0"), ("--mass-kg", "nan"),
        ("--snow-modulus-mpa", "nan"), ("--snow-modulus-mpa", "1e8"), ("--points", "3"),
        ("--points", "1000000000"), ("--model", "fem"), ("--profile-source", "laser"),
        ("--workers", "-1"), ("--load-position-mm", "5000"),
    )):  # fmt: skip
        out = d / f"sweep_bad_{i}.zarr"
        args = ["sweep", "--ski", "skate", *base, "--out", str(out), opt, value]
        if opt == "--ski":
            args = ["sweep", "--ski", value, *base, "--out", str(out)]
        cases.append(Case(f"sweep {opt} {value}", args, [opt, "skatte" if opt == "--ski" else ""],
                          post=not_created(out), group="option"))  # fmt: skip
    afile = _write(d / "not_a_store.zarr", "hello")
    cases.append(
        Case(
            "sweep --out regular file",
            ["sweep", "--ski", "skate", *base, "--out", str(afile)],
            [afile.name],
            group="sweep store",
        )
    )
    adir = d / "some_dir.zarr"
    adir.mkdir()
    (adir / "data.txt").write_text("mine")
    cases.append(
        Case(
            "sweep --out foreign dir",
            ["sweep", "--ski", "skate", *base, "--out", str(adir)],
            [adir.name],
            group="sweep store",
        )
    )
    for name, p in (
        ("missing", d / "nothing.zarr"),
        ("regular file", afile),
        ("foreign dir", adir),
    ):
        cases.append(Case(f"plot {name}", ["plot", str(p), "--out", str(d / "figs")], [p.name],
                          group="sweep store"))  # fmt: skip
    return cases  # fmt: skip


def build_corpus(d: Path) -> list[Case]:
    """All cases, with their fixture files written under ``d``."""
    d.mkdir(parents=True, exist_ok=True)
    from corpus_doors import DOOR_GROUPS

    groups = (bench_cases, virtual_bench_cases, profile_cases, topography_cases, rank_cases,
              model_cases, sweep_cases, *DOOR_GROUPS)  # fmt: skip
    cases: list[Case] = []
    for g in groups:
        sub = d / g.__name__
        sub.mkdir()
        made = g(sub)
        for c in made:
            c.builder = g.__name__
        cases += made
    for c in cases:  # the empty placeholder of the option cases above
        c.place = [p for p in c.place if p]
    return cases


# --------------------------------------------------------------------------------------------
# running and classifying


class CaseTimeout(BaseException):
    """A case still computing after the time limit (``main --timeout``): it was accepted."""


def run_case(case: Case, timeout: float | None = None) -> Outcome:
    from skisnow.cli import main

    if timeout:
        import signal

        def _alarm(*_):
            raise CaseTimeout(f"still computing after {timeout:g} s")

        signal.signal(signal.SIGALRM, _alarm)
        signal.setitimer(signal.ITIMER_REAL, timeout)

    out, err = io.StringIO(), io.StringIO()
    t0, c0 = time.perf_counter(), time.process_time()
    escaped = None
    saved = {k: os.environ.get(k) for k in case.env}
    os.environ.update(case.env)
    with (
        warnings.catch_warnings(record=True) as caught,
        contextlib.redirect_stdout(out),
        contextlib.redirect_stderr(err),
    ):
        warnings.simplefilter("always")
        try:
            code = main(list(case.argv))
        except SystemExit as exc:  # pragma: no cover - main never exits
            code = exc.code if isinstance(exc.code, int) else 1
        except BaseException as exc:
            escaped = exc
            code = -1
        finally:
            if timeout:
                signal.setitimer(signal.ITIMER_REAL, 0)
            for k, v in saved.items():
                if v is None:
                    os.environ.pop(k, None)
                else:
                    os.environ[k] = v
    seconds, cpu = time.perf_counter() - t0, time.process_time() - c0
    message = err.getvalue().strip()
    if escaped is not None:
        message = f"{type(escaped).__name__}: {escaped}"
    names = re.findall(r"\[(\w+)\]\s*$", message)
    if isinstance(escaped, CaseTimeout):
        kind = "timeout"
    elif escaped is not None or (code != 0 and names and names[-1] not in CLEAN_ERRORS):
        kind = "traceback"
    elif case.expect == "accept":  # a valid input: computed (0, 3 or 4), never refused
        kind = "clean" if code in (0, 3, 4) else "refused"
    elif code == 0:
        kind = "silent"
    else:
        kind = "clean"
    problem = case.post() if case.post is not None else None
    if not problem and case.post_output is not None:
        problem = case.post_output(out.getvalue() + err.getvalue())
    if problem:
        kind = "side effect"
        message += f" [{problem}]"
    low = message.lower()
    names_place = case.expect == "accept" or all(
        any(alt.lower() in low for alt in p.split("|")) for p in case.place
    )
    return Outcome(
        case=case,
        kind=kind,
        code=code,
        message=message,
        names_place=names_place and kind == "clean",
        says_valid=bool(VALID_WORDS.search(message)) and kind == "clean",
        seconds=seconds,
        warnings=[str(w.message) for w in caught],
        cpu=cpu,
    )


def tally(outcomes: list[Outcome]) -> dict[str, int]:
    counts = Counter(o.kind for o in outcomes)
    clean = [o for o in outcomes if o.kind == "clean"]
    return {
        "cases": len(outcomes),
        "clean": counts["clean"],
        "silent": counts["silent"],
        "traceback": counts["traceback"],
        "side effect": counts["side effect"],
        "refused (valid input)": counts["refused"],
        "timeout": counts["timeout"],
        "names place": sum(o.names_place for o in clean),
        "says what is valid": sum(o.says_valid for o in clean),
    }


def main(argv: list[str] | None = None) -> int:
    import tempfile

    args = sys.argv[1:] if argv is None else argv
    if "--no-limit" not in args:
        # An unguarded allocation of 149 GiB must fail here with MemoryError, not summon the
        # kernel's OOM killer (address space, so JAX and numba fit: 14 GiB).
        import resource

        resource.setrlimit(resource.RLIMIT_AS, (14 << 30, 14 << 30))
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        cases = build_corpus(Path(tmp) / "corpus")
        t1 = time.perf_counter()
        outcomes = []
        timeout = None
        if "--timeout" in args:
            timeout = float(args[args.index("--timeout") + 1])
        only = args[args.index("--only") + 1] if "--only" in args else None
        for c in cases:
            if only and only not in c.group and only not in c.id:
                continue
            outcomes.append(run_case(c, timeout))
            print(f"{outcomes[-1].kind:11s} {c.id}", file=sys.stderr, flush=True)
        t2 = time.perf_counter()
    for o in outcomes:
        flag = "" if o.kind == "clean" and o.names_place else " <--"
        if "--cases" in args or flag:
            print(
                f"{o.kind:11s} {o.code:4d} {o.seconds:6.2f}s {o.case.id}: {o.message[:300]}{flag}"
            )
    print(json.dumps(tally(outcomes), indent=1))
    print(f"fixtures {t1 - t0:.1f} s, cases {t2 - t1:.1f} s, "
          f"CPU {sum(o.cpu for o in outcomes):.1f} s")  # fmt: skip
    if "--slowest" in args:  # the cases that cost most CPU, and the CPU of each group
        for o in sorted(outcomes, key=lambda o: -o.cpu)[: int(args[args.index("--slowest") + 1])]:
            print(f"  {o.cpu:6.2f} s CPU  {o.case.id}")
        per_group = Counter()
        for o in outcomes:
            per_group[o.case.group or o.case.builder] += o.cpu
        for group, cpu in per_group.most_common():
            print(f"  {group:22s} {cpu:6.1f} s CPU")
    by_group = Counter((o.case.group, o.kind) for o in outcomes)
    for (group, kind), n in sorted(by_group.items()):
        print(f"  {group:18s} {kind:11s} {n}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
