"""Trust audit finding 19: a profile table whose ``x_mm`` and ``height_mm`` header names are
swapped is still refused (exit 2), and the refusal names the possible swap (the data fit it:
the "height" column increases along each profile over a ski's length, the "x" column holds
camber heights), not only a unit. Data that do not fit a swap get no such hint."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from skisnow._checks import column_swap_hint
from skisnow.cli import main


def _bench(capsys, tmp: Path) -> Path:
    out = tmp / "b.csv"
    code = main(["bench", "classic", "--out", str(out), "--mass-kg", "20,60",
                 "--load-position-mm", "-120", "--noise-mm", "0.005", "--seed", "1",
                 "--dx-mm", "10"])  # fmt: skip
    assert code == 0
    capsys.readouterr()
    return out


def _rewrite(src: Path, dst: Path, df: pd.DataFrame) -> Path:
    header = [ln for ln in src.read_text().splitlines() if ln.startswith("#")]
    dst.write_text("\n".join(header) + "\n" + df.to_csv(index=False))
    return dst


def test_swapped_bench_columns_are_refused_naming_the_swap(capsys, tmp_path: Path) -> None:
    bench = _bench(capsys, tmp_path)
    df = pd.read_csv(bench, comment="#").rename(columns={"x_mm": "height_mm", "height_mm": "x_mm"})
    swapped = _rewrite(bench, tmp_path / "swapped.csv", df)
    assert main(["identify", str(swapped), "--out", str(tmp_path / "a.json")]) == 2
    err = capsys.readouterr().err
    assert "swapped" in err and "'height_mm' increases along every profile" in err
    assert "--allow-implausible" in err


def test_a_unit_slip_is_not_called_a_swap(capsys, tmp_path: Path) -> None:
    bench = _bench(capsys, tmp_path)
    df = pd.read_csv(bench, comment="#")
    df["x_mm"] *= 1e-3  # x in metres: a unit slip, the columns are in place
    slip = _rewrite(bench, tmp_path / "metres.csv", df)
    assert main(["identify", str(slip), "--out", str(tmp_path / "a.json")]) == 2
    err = capsys.readouterr().err
    assert "look like m" in err and "swapped" not in err


def test_swapped_profile_file_names_the_swap(capsys, tmp_path: Path) -> None:
    x = np.linspace(-200.0, 200.0, 64)
    h = 0.5 * (x / 200.0) ** 2  # a rigid profile, heights within 0.5 mm
    p = tmp_path / "p.csv"
    pd.DataFrame({"x_mm": h, "height_mm": x}).to_csv(p, index=False)  # names swapped
    assert main(["contact", "--profile", str(p), "--width-mm", "44", "--mass-kg", "60",
                 "--load-position-mm", "0", "--snow-modulus-mpa", "100"]) == 2  # fmt: skip
    assert "the columns may be swapped" in capsys.readouterr().err


def test_swap_hint_needs_data_that_fit_a_swap() -> None:
    x = np.linspace(-980.0, 1020.0, 201)
    h = 10.0 + 0.01 * np.abs(x)
    assert "swapped" in column_swap_hint(h, x)  # names exchanged
    assert column_swap_hint(x, h) == ""  # in place
    assert column_swap_hint(h, x[::-1].copy()) == ""  # the "height" column not increasing
    assert column_swap_hint(h, 0.1 * h) == ""  # "height" spans < 100 mm: not positions
