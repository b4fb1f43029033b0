"""One definition per concept: the elastic material and the default base (skisnow.materials),
and the grid-axis check (skisnow._values.sorted_unique) of the bench, the sweep and the CLI."""

from __future__ import annotations

import numpy as np
import pytest

from skisnow import InputError, contact, materials, micro
from skisnow._values import sorted_unique


def test_one_material_class_and_one_default_base() -> None:
    assert contact.Material is micro.Material is materials.Material
    assert contact.BASE is materials.BASE
    assert (materials.BASE.modulus, materials.BASE.poisson) == (900e6, 0.3)
    from skisnow.sweep import PAPER_BASE_MODULUS, PAPER_POISSON, SweepSpec

    assert (materials.BASE.modulus, materials.BASE.poisson) == (PAPER_BASE_MODULUS, PAPER_POISSON)
    spec = SweepSpec(skis=("classic",), masses=(60.0,), load_positions=(-0.1,), snow_moduli=(1e8,))
    assert spec.base_modulus == materials.BASE.modulus
    # eq. 2 with the default base equals eq. 2 written out with 900 MPa and ν = 0.3
    e = contact.effective_modulus(contact.snow(100e6))
    assert e == pytest.approx(2 / (0.91 / 900e6 + 0.91 / 100e6), rel=1e-15)


def test_micro_presets_keep_scherge_table2_values() -> None:
    """Changed in the refactor: micro's Material had fields ``youngs_modulus``/``poisson_ratio``;
    the one Material names them ``modulus``/``poisson`` and validates them. The values of
    Scherge et al. (2021, Table 2) are unchanged, and so is E' of ice on UHMWPE."""
    assert (micro.ICE.modulus, micro.ICE.poisson) == (9.5e9, 0.31)
    assert (micro.UHMWPE.modulus, micro.UHMWPE.poisson) == (840e6, 0.46)
    expected = 2 / ((1 - 0.31**2) / 9.5e9 + (1 - 0.46**2) / 840e6)
    assert micro.ice_base_modulus() == pytest.approx(expected, rel=1e-15)
    with pytest.raises(InputError, match="Poisson"):
        materials.Material(name="rubber", modulus=1e6, poisson=0.5)


def test_sorted_unique_sorts_and_names_the_defect() -> None:
    np.testing.assert_array_equal(sorted_unique([3.0, -1.0, 2.0], name="x"), [-1.0, 2.0, 3.0])
    np.testing.assert_array_equal(sorted_unique(5.0, name="x"), [5.0])
    with pytest.raises(InputError, match=r"masses \[kg\]: values must be distinct.*\[30.0\]"):
        sorted_unique([30.0, 60.0, 30.0], name="masses", unit="kg")
    with pytest.raises(InputError, match="must be > 0"):
        sorted_unique([1.0, 0.0], name="m", positive=True)
    with pytest.raises(InputError, match="finite"):
        sorted_unique([1.0, np.nan], name="m")
    with pytest.raises(InputError, match="non-empty"):
        sorted_unique([], name="m")


def test_bench_grid_rejects_a_repeated_mass() -> None:
    """Changed in the refactor: ``run_bench`` silently merged a mass given twice; it now shares
    the sweep's rule (a grid names each point once) and says which value was repeated."""
    from skisnow.bench import run_bench

    with pytest.raises(InputError, match=r"masses \[kg\].*\[30.0\]"):
        run_bench("classic", masses=[30.0, 30.0, 60.0], load_positions=[-0.1])
