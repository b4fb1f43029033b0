"""A CSV saved by a spreadsheet in a locale with decimal commas (``;`` or tab separators) is
refused by every table reader with the separator named, not with a parse error ("Error
tokenizing data", bench tables), a load column said to be missing (load histories) or missing
columns (profiles, rank tables); the same file with commas and decimal points reads."""

from __future__ import annotations

from pathlib import Path

import pytest

from skisnow._errors import FileFormatError
from skisnow.bench import read_bench, run_bench, write_bench
from skisnow.contact import read_profile
from skisnow.micro import read_rank_table
from skisnow.workflows import read_load_history


def _localised(text: str, sep: str) -> str:
    """``text`` as a spreadsheet with decimal commas saves it (comment lines kept)."""
    return "\n".join(
        line if line.startswith("#") else line.replace(",", sep).replace(".", ",")
        for line in text.splitlines()
    )


def _cases(tmp_path: Path) -> list[tuple[str, str, object]]:
    bench = write_bench(
        run_bench("classic", masses=[20.0, 60.0], load_positions=[-0.12], dx=0.01),
        tmp_path / "bench.csv",
    ).read_text(encoding="utf-8")
    history = "t_s,mass_kg,load_position_mm\n0,30.5,-100\n0.5,60,-80.5\n1.0,40,-60\n"
    profile = "x_mm,height_mm\n" + "\n".join(f"{x:.1f},{1e-5 * x * x:.4f}" for x in
                                            range(-500, 501, 25))  # fmt: skip
    rank = "structure,glide_time_s,A_fr\nS1,10.5,0.1\nS2,10.7,0.2\nS3,10.1,0.05\n"
    return [("bench.csv", bench, read_bench), ("h.csv", history, read_load_history),
            ("p.csv", profile, read_profile), ("r.csv", rank, read_rank_table)]  # fmt: skip


@pytest.mark.parametrize("sep", [";", "\t"])
def test_other_separators_are_named(tmp_path: Path, sep: str) -> None:
    for name, text, reader in _cases(tmp_path):
        good = tmp_path / f"good_{name}"
        good.write_text(text, encoding="utf-8")
        reader(good)  # reads
        bad = tmp_path / f"bad_{name}"
        bad.write_text(_localised(text, sep), encoding="utf-8")
        with pytest.raises(FileFormatError, match="not commas") as info:
            reader(bad)
        assert str(bad) in str(info.value), name


def test_a_nan_cell_is_shown_as_read(tmp_path: Path) -> None:
    """The offending value is shown as a number ('nan'), not as NumPy's repr
    ('np.float64(nan)'), with the file line of the row."""
    text = "ski,mass_kg,load_position_mm,x_mm,height_mm\n" + "".join(
        f"a,20,-120,{x},{'nan' if x == 30 else 1.0}\n" for x in range(0, 120, 10)
    )
    path = tmp_path / "b.csv"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(FileFormatError, match="line 5, column 'height_mm'") as info:
        read_bench(path)
    assert "np." not in str(info.value) and "nan" in str(info.value)
