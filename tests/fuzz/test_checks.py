"""Plausibility checks (skisnow._checks) and atomic writes (skisnow._atomic)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from skisnow import ImplausibleValueError, InputError, allow_implausible
from skisnow._atomic import atomic_path, atomic_write
from skisnow._checks import check_array, check_memory, check_value


def test_impossible_values_are_refused_even_with_the_override() -> None:
    with allow_implausible():
        for key, value in (("mass", 0.0), ("pixel", 0.0), ("temperature", -300.0)):
            with pytest.raises(InputError, match="not a possible"):
                check_value(value, key, where="--opt")
        with pytest.raises(InputError, match="not a number"):
            check_value("abc", "mass", where="--mass-kg")
        with pytest.raises(InputError, match="not a possible"):
            check_value(float("nan"), "mass", where="--mass-kg")


def test_implausible_values_name_the_probable_unit_and_the_override() -> None:
    with pytest.raises(ImplausibleValueError, match=r"--snow-modulus-mpa.*given in Pa.*allow"):
        check_value(1e8, "snow_modulus", where="--snow-modulus-mpa")
    with pytest.raises(ImplausibleValueError, match="given in K"):
        check_value(270.0, "temperature", where="--temperature-c")
    with pytest.raises(ImplausibleValueError, match="20000 mm is an implausible ski length"):
        check_value(20.0e3, "ski_length", where="length_mm")  # a 20 m ski
    with pytest.raises(ImplausibleValueError, match="given in m"):
        check_value(1.9, "ski_length", where="length_mm")
    with allow_implausible():
        assert check_value(1e8, "snow_modulus", where="x") == 1e8
    assert check_value(-2.0, "temperature", where="x") == -2.0


def test_heights_in_metres_in_a_millimetre_column() -> None:
    x = np.linspace(-900.0, 900.0, 50)
    h_m = 0.03 * (x / 900.0) ** 2  # a camber in metres
    with pytest.raises(ImplausibleValueError, match="look like m, not mm"):
        check_array(h_m, "camber_height", where="f.csv, column 'height_mm'")
    assert check_array(h_m * 1e3, "camber_height", where="f.csv").shape == x.shape
    with pytest.raises(ImplausibleValueError, match="line 1: -30 mm is an implausible"):
        check_array(-h_m * 1e3, "camber_height", where="f", row_label=lambda i: f"line {i + 1}")


def test_memory_guard_refuses_before_allocating() -> None:
    with pytest.raises(InputError, match=r"--dx-mm.*GiB"):
        check_memory(149 * 2.0**30 * 1e3, where="--dx-mm 1e-07", what="the profile")
    check_memory(1e6, where="--dx-mm", what="the profile")


def test_atomic_write_keeps_the_old_file_when_the_writer_fails(tmp_path) -> None:
    target = tmp_path / "sub" / "a.txt"
    atomic_write(target, "old")
    with pytest.raises(RuntimeError), atomic_path(target) as tmp:
        tmp.write_text("half")
        raise RuntimeError("killed")
    assert target.read_text() == "old"
    assert sorted(p.name for p in target.parent.iterdir()) == ["a.txt"]
    with atomic_path(tmp_path / "b.npy") as tmp:
        assert tmp.suffix == ".npy"
        np.save(tmp, np.arange(3))
    assert np.load(tmp_path / "b.npy").tolist() == [0, 1, 2]


def test_messages_read_as_sentences() -> None:
    """Every quantity's refusals read "VALUE [UNIT] is an implausible NAME (plausible: ...)" and
    "VALUE is not a possible NAME": a count's name says what is counted ("number of frames",
    never "a frames"), and a count or factor shows no bracketed pseudo-unit after its value."""
    from skisnow._quantities import QUANTITIES

    for key, q in QUANTITIES.items():
        hi = q.plausible[1]
        if hi < q.high and math.isfinite(hi):
            v = hi * 2.0 + 1.0 if q.high == math.inf else 0.5 * (hi + q.high)
            v = float(math.floor(hi) + 1) if q.integer else v
            with pytest.raises(ImplausibleValueError) as exc:
                check_value(v, key, where="--x")
            text = str(exc.value)
            shown = f"{v:.6g}" if q.unit.startswith("(") else f"{v:.6g} {q.unit}"
            assert text.startswith(f"--x: {shown} is an implausible {q.name} (plausible: ")
        if q.integer:
            countable = ("number of", "random seed", "evaluation limit", "stride",
                         "population size", "layer width")  # fmt: skip
            assert q.name.startswith(countable), q.name
