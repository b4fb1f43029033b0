"""Load histories: reading, validation (row and column named), templates and their balance law."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from skisnow import FileFormatError, InputError
from skisnow.constants import STANDARD_GRAVITY
from skisnow.workflows import (
    TEMPLATES,
    LoadHistory,
    check_positions,
    read_load_history,
    template_history,
)

GOOD = """# force-measuring binding, right ski
t_s,force_n,load_position_mm
0.00,0,-150
0.01,300,-140
# a comment inside the data
0.02,600,-120
0.03,650,-100
"""


def write(tmp_path: Path, text: str, name: str = "h.csv") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_reads_force_and_mass_columns_in_si(tmp_path: Path) -> None:
    h = read_load_history(write(tmp_path, GOOD))
    np.testing.assert_allclose(h.time, [0, 0.01, 0.02, 0.03])
    np.testing.assert_allclose(h.force, [0, 300, 600, 650])
    np.testing.assert_allclose(h.load_position, [-0.150, -0.140, -0.120, -0.100])
    assert h.lines == (3, 4, 6, 7)  # the file's own line numbers (comments skipped)
    text = GOOD.replace("force_n", "mass_kg")
    for n in ("300", "600", "650"):  # the same numbers / 10 as kg
        text = text.replace(f",{n},", f",{int(n) // 10},")
    hm = read_load_history(write(tmp_path, text, "m.csv"))
    np.testing.assert_allclose(hm.force, h.force / 10 * STANDARD_GRAVITY)
    np.testing.assert_allclose(hm.mass, h.force / 10)


@pytest.mark.parametrize(
    ("bad_line", "replacement", "line", "column", "what"),
    [
        ("0.02,600,-120", "0.02,nan,-120", 6, "force_n", "NaN"),
        ("0.02,600,-120", "0.02,,-120", 6, "force_n", "empty"),
        ("0.02,600,-120", "0.02,abc,-120", 6, "force_n", "not a number"),
        ("0.02,600,-120", "0.02,-5,-120", 6, "force_n", "negative"),
        ("0.02,600,-120", "0.005,600,-120", 6, "t_s", "does not increase"),
        ("0.03,650,-100", "0.09,650,-100", 7, "t_s", "gap"),
        ("0.01,300,-140", "0.01,300,", 4, "load_position_mm", "empty"),
    ],
)
def test_bad_rows_are_named_by_line_and_column(
    tmp_path: Path, bad_line: str, replacement: str, line: int, column: str, what: str
) -> None:
    path = write(tmp_path, GOOD.replace(bad_line, replacement))
    with pytest.raises(FileFormatError) as err:
        read_load_history(path)
    msg = str(err.value)
    assert str(path) in msg
    assert f"line {line}" in msg
    assert repr(column) in msg
    assert what in msg


def test_columns_are_checked(tmp_path: Path) -> None:
    with pytest.raises(FileFormatError, match="exactly one load column"):
        read_load_history(write(tmp_path, GOOD.replace("force_n", "force_kn")))
    both = GOOD.replace("t_s,force_n,load_position_mm", "t_s,force_n,mass_kg,load_position_mm")
    with pytest.raises(FileFormatError, match="exactly one load column"):
        read_load_history(write(tmp_path, both))
    with pytest.raises(FileFormatError, match="load_position_mm"):
        read_load_history(write(tmp_path, GOOD.replace("load_position_mm", "x_mm")))
    with pytest.raises(FileFormatError, match="no such file"):
        read_load_history(tmp_path / "missing.csv")


def test_position_off_the_ski_names_line(tmp_path: Path) -> None:
    path = write(tmp_path, GOOD.replace("0.03,650,-100", "0.03,650,-1500"))
    with pytest.raises(InputError, match=r"'load_position_mm', line 7: -1500 mm is an implausible"):
        read_load_history(path)
    from skisnow import allow_implausible

    with allow_implausible():  # possible, if implausible: then the ski decides
        h = read_load_history(path)
    with pytest.raises(InputError, match=r"line 7 .*'load_position_mm'.*off the ski"):
        check_positions(h, x_tail=-0.98, x_tip=1.02)


def test_resample_keeps_the_span_and_interpolates_linearly() -> None:
    h = LoadHistory(time=[0.0, 1.0, 2.0], force=[0.0, 100.0, 0.0], load_position=[0, -0.1, 0])
    r = h.resample(5)
    np.testing.assert_allclose(r.time, [0, 0.5, 1, 1.5, 2])
    np.testing.assert_allclose(r.force, [0, 50, 100, 50, 0])
    np.testing.assert_allclose(r.load_position, [0, -0.05, -0.1, -0.05, 0])


@pytest.mark.parametrize("name", list(TEMPLATES))
def test_templates_are_periodic_nonnegative_and_balance_the_vertical_impulse(name: str) -> None:
    """Over a periodic cycle the skier's vertical momentum returns to its start, so the mean
    vertical support equals body weight: 2·mean(F_ski) + pole share·BW = BW (both skis carry
    the same history, half a cycle apart)."""
    tpl = TEMPLATES[name]
    body = 70.0
    h = template_history(name, body_mass=body, n_frames=4001)
    bw = body * STANDARD_GRAVITY
    assert h.force.min() >= 0.0
    assert h.force[0] == pytest.approx(h.force[-1], abs=1e-9 * bw)
    assert h.load_position[0] == pytest.approx(h.load_position[-1])
    mean_ski = h.force[:-1].mean() / bw  # one period, endpoint counted once
    assert 2 * mean_ski + tpl.pole_share == pytest.approx(1.0, abs=0.01)
    # on the foot: heel −240 mm to ball −40 mm
    assert h.load_position.min() >= -0.240 - 1e-12
    assert h.load_position.max() <= -0.040 + 1e-12
    assert tpl.citation and "not digitised" in tpl.citation


def test_template_scales_with_body_mass_and_duration() -> None:
    a = template_history("diagonal", body_mass=60, n_frames=50)
    b = template_history("diagonal", body_mass=90, n_frames=50, duration=2.6)
    np.testing.assert_allclose(b.force, a.force * 1.5)
    np.testing.assert_allclose(b.time, a.time * 2.0)
    np.testing.assert_allclose(b.load_position, a.load_position)
    with pytest.raises(InputError, match="unknown cycle template"):
        template_history("marathon", body_mass=70)
