"""camber_profile over an array of masses: the rows are the profiles of the single masses."""

from __future__ import annotations

import numpy as np
import pytest

from skisnow import InputError
from skisnow.network import camber_profile
from skisnow.ski import get_ski


@pytest.mark.parametrize("source", ["beam", "network"])
def test_array_of_masses_gives_the_rows_of_single_masses(source: str) -> None:
    ski = get_ski("skate")
    x = np.linspace(ski.x_tail, ski.x_tip, 301)
    masses = np.array([20.0, 55.5, 90.0])
    xs, h = camber_profile("skate", mass=masses, load_position=-0.12, x=x, source=source)
    assert h.shape == (3, x.size)
    np.testing.assert_array_equal(xs, x)
    for row, m in zip(h, masses, strict=True):
        _, single = camber_profile("skate", mass=m, load_position=-0.12, x=x, source=source)
        np.testing.assert_allclose(row, single, rtol=0, atol=1e-12)
    # heavier loads press the camber down (checks the rows are not swapped)
    mid = np.argmin(np.abs(x))
    assert h[0, mid] > h[1, mid] > h[2, mid]


def test_mass_of_wrong_rank_is_rejected() -> None:
    with pytest.raises(InputError, match="1-D"):
        camber_profile("skate", mass=np.ones((2, 2)), load_position=-0.12)
