"""Bench files: round trips (CSV, Parquet) and every validation error, named by file/row/column."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from skisnow import FileFormatError, InputError, allow_implausible
from skisnow.bench import (
    MIN_PROFILE_POINTS,
    BenchData,
    read_bench,
    run_bench,
    ski_metrics,
    write_bench,
)

#: Parquet needs the optional pyarrow (the ``parquet`` extra); CI installs every extra.
needs_pyarrow = pytest.mark.skipif(
    importlib.util.find_spec("pyarrow") is None,
    reason="Parquet bench files need the parquet extra: uv sync --extra parquet",
)


@pytest.fixture(scope="module")
def bench() -> BenchData:
    return run_bench("classic", masses=[30, 35, 60, 65], load_positions=[-0.08], noise=1e-5, seed=1)


@pytest.mark.parametrize("suffix", [".csv", pytest.param(".parquet", marks=needs_pyarrow)])
def test_round_trip_is_exact_and_metrics_equal(
    bench: BenchData, tmp_path: Path, suffix: str
) -> None:
    path = write_bench(bench, tmp_path / f"b{suffix}")
    back = read_bench(path)
    assert back.equals(bench)  # values bit for bit (17 significant digits in CSV) and metadata
    assert back.metadata["ski"] == "classic" and back.metadata["units"]["x_mm"] == "mm"
    assert ski_metrics(back) == ski_metrics(bench)


def _small_table(n: int = MIN_PROFILE_POINTS) -> pd.DataFrame:
    x = np.arange(n, dtype=float) * 100.0 - 450.0  # a plausible ski: 900 mm of it
    return pd.DataFrame(
        {
            "ski": ["s"] * (2 * n),
            "mass_kg": [10.0] * n + [20.0] * n,
            "load_position_mm": [-80.0] * (2 * n),
            "x_mm": np.concatenate([x, x]),
            "height_mm": np.linspace(2.0, 0.0, 2 * n),  # the heavier load sits lower
        }
    )


def _write_csv(tmp_path: Path, table: pd.DataFrame) -> Path:
    path = tmp_path / "bad.csv"
    path.write_text("# a comment line\n" + table.to_csv(index=False), encoding="utf-8")
    return path


def _expect(path: Path, *patterns: str) -> None:
    with pytest.raises(FileFormatError) as info:
        read_bench(path)
    msg = str(info.value)
    assert str(path) in msg
    for p in patterns:
        assert p in msg, msg


def test_valid_small_csv_without_metadata(tmp_path: Path) -> None:
    data = read_bench(_write_csv(tmp_path, _small_table()))
    assert data.metadata == {} and len(data.table) == 2 * MIN_PROFILE_POINTS


def test_missing_and_misnamed_columns(tmp_path: Path) -> None:
    t = _small_table()
    _expect(_write_csv(tmp_path, t.drop(columns="height_mm")), "missing column 'height_mm'")
    _expect(_write_csv(tmp_path, t.rename(columns={"x_mm": "x"})), "'x' should be named 'x_mm'")
    _expect(_write_csv(tmp_path, t.assign(extra=1.0)), "unexpected column 'extra'")


def test_nan_inf_and_text(tmp_path: Path) -> None:
    # data row i of this file is on line i + 3 (comment line, header line, 1-based)
    t = _small_table()
    t.loc[4, "height_mm"] = np.nan
    _expect(_write_csv(tmp_path, t), "line 7", "'height_mm'", "NaN")
    t = _small_table()
    t.loc[2, "x_mm"] = np.inf
    _expect(_write_csv(tmp_path, t), "line 5", "'x_mm'")
    t = _small_table().astype({"mass_kg": object})
    t.loc[3, "mass_kg"] = "heavy"
    _expect(_write_csv(tmp_path, t), "line 6", "'mass_kg'", "not a number")


def test_negative_mass(tmp_path: Path) -> None:
    t = _small_table()
    t.loc[MIN_PROFILE_POINTS:, "mass_kg"] = -20.0
    _expect(_write_csv(tmp_path, t), f"line {MIN_PROFILE_POINTS + 3}", "'mass_kg'", "> 0 kg")


def test_duplicated_sample(tmp_path: Path) -> None:
    t = _small_table()
    t = pd.concat([t.iloc[:3], t.iloc[[2]], t.iloc[3:]], ignore_index=True)
    _expect(_write_csv(tmp_path, t), "duplicated sample", "line 5", "line 6", "'x_mm'")


def test_x_not_increasing(tmp_path: Path) -> None:
    t = _small_table()
    t.loc[5, "x_mm"], t.loc[6, "x_mm"] = 6.0, 5.0
    _expect(_write_csv(tmp_path, t), "line 9", "'x_mm'", "does not increase")


def test_too_few_points(tmp_path: Path) -> None:
    t = _small_table().iloc[: 2 * MIN_PROFILE_POINTS - 1]
    _expect(_write_csv(tmp_path, t), "mass_kg=20.0", f"{MIN_PROFILE_POINTS - 1} samples")


@needs_pyarrow
def test_parquet_errors_name_the_row(tmp_path: Path) -> None:
    t = _small_table()
    t.loc[7, "height_mm"] = np.nan
    path = tmp_path / "bad.parquet"
    t.to_parquet(path)
    _expect(path, "row 8", "'height_mm'")


def test_file_level_errors(tmp_path: Path, bench: BenchData) -> None:
    _expect(tmp_path / "absent.csv", "no such file")
    _expect(tmp_path / "x.txt", "unknown bench file type")
    bad_meta = tmp_path / "meta.csv"
    bad_meta.write_text(
        "# skisnow-bench-metadata: {not json\n" + _small_table().to_csv(index=False)
    )
    _expect(bad_meta, "line 1", "not valid JSON")
    if importlib.util.find_spec("pyarrow") is not None:
        garbage = tmp_path / "g.parquet"
        garbage.write_bytes(b"not parquet at all")
        _expect(garbage, "not a readable Parquet file")
    empty = tmp_path / "e.csv"
    empty.write_text(",".join(_small_table().columns) + "\n")
    _expect(empty, "no rows")
    with pytest.raises(FileFormatError, match="unknown bench file type"):
        write_bench(bench, tmp_path / "b.xlsx")


def test_parquet_without_its_extra_says_which_extra(
    bench: BenchData, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Without pyarrow (an optional dependency), a Parquet bench file is refused naming the file
    and the extra to install, as an InputError (exit code 2) that is also an ImportError."""
    from skisnow._optional import MissingDependencyError

    for name in ("pyarrow", "pyarrow.parquet"):
        monkeypatch.setitem(sys.modules, name, None)  # import fails as if it were not installed
    for call in (lambda p: write_bench(bench, p), read_bench):
        path = tmp_path / "b.parquet"
        path.write_bytes(b"PAR1")
        with pytest.raises(MissingDependencyError, match=r"b\.parquet.*uv sync --extra parquet"):
            call(path)
    assert issubclass(MissingDependencyError, InputError)
    assert issubclass(MissingDependencyError, ImportError)
    assert write_bench(bench, tmp_path / "b.csv").is_file()  # CSV needs nothing optional


def test_benchdata_validates_in_memory() -> None:
    with pytest.raises(FileFormatError, match="<table>"):
        BenchData(table=_small_table().drop(columns="ski"))
    with pytest.raises(InputError, match="JSON"):
        BenchData(table=_small_table(), metadata={"bad": object()})


def _bilinear_bench() -> BenchData:
    """Two skis, h = 0.5 + 0.01·x − 0.004·m [mm] at two positions: bilinear, so linear
    interpolation in x and in mass must reproduce it exactly."""
    x = np.linspace(-100.0, 100.0, 11)
    rows = [
        {
            "ski": s,
            "mass_kg": m,
            "load_position_mm": p,
            "x_mm": xi,
            "height_mm": 0.5 + 0.01 * xi - 0.004 * m,
        }
        for s in ("a", "b")
        for m in (20.0, 40.0, 80.0)
        for p in (-80.0, 0.0)
        for xi in x
    ]
    # a mathematical bench (negative heights, 200 mm long): accepted as implausible on purpose
    with allow_implausible():
        return BenchData(pd.DataFrame(rows), {"ski": "a", "kick_zone_mm": [-200.0, 300.0]})


def test_bench_queries_interpolate_exactly_on_a_bilinear_bench() -> None:
    b = _bilinear_bench()
    masses, h = b.heights_at(load_position_mm=-80.0, x_mm=25.0, ski="b")
    np.testing.assert_array_equal(masses, [20.0, 40.0, 80.0])
    np.testing.assert_allclose(h, 0.5 + 0.25 - 0.004 * masses, rtol=0, atol=1e-12)
    x, h = b.profile_at_mass(mass_kg=50.0, load_position_mm=0.0, ski="a")
    np.testing.assert_allclose(h, 0.5 + 0.01 * x - 0.2, rtol=0, atol=1e-12)
    assert b.kick_zone_mm("a") == (-200.0, 300.0) and b.describes_kick_zone("a")
    assert b.kick_zone_mm("b") is None and not b.describes_kick_zone("b")


def test_bench_queries_name_what_exists() -> None:
    b = _bilinear_bench()
    with pytest.raises(InputError, match="several skis"):
        b.heights_at(load_position_mm=0.0)
    with pytest.raises(InputError, match="not in the bench"):
        b.ski_name("c")
    with pytest.raises(
        InputError, match=r"no profiles at load_position_mm = -120; it has \[-80.0, 0.0\]"
    ):
        b.heights_at(load_position_mm=-120.0, ski="a")
    with pytest.raises(InputError, match="outside the bench's masses"):
        b.profile_at_mass(mass_kg=100.0, load_position_mm=0.0, ski="a")
