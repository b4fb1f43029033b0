"""skisnow.pipeline.solve_case: one case end to end (profile -> contact -> zones).

Balance laws and complementarity on the case, the ski's own width and kick zone, the grid
convention, warm starts that do not change the answer, a precomputed profile
that gives the identical case (the doors of the CLI, the sweep and the report: test_doors.py).
"""

from __future__ import annotations

import numpy as np
import pytest

from skisnow import DomainWarning, InputError, UnsupportedLoadError
from skisnow.constants import STANDARD_GRAVITY
from skisnow.pipeline import Case, loaded_profiles, solve_case, stations
from skisnow.ski import get_ski

N = 512  # small grid: the physics checks do not need the paper's 4096 stations
KW = dict(mass=45.0, load_position=-0.12, snow_modulus=100e6, n_points=N, profile_source="beam")


@pytest.fixture(scope="module")
def skate() -> Case:
    return solve_case("skate", **KW)


def test_balance_and_complementarity(skate: Case) -> None:
    sol = skate.solution
    assert skate.converged and skate.warnings == ()
    force = sol.pressure.sum() * sol.cell_area
    # force and moment balance of eq. 3 to the solver's tolerance (1e-8 -> 1e-6 margin)
    assert force == pytest.approx(45.0 * STANDARD_GRAVITY, rel=1e-6)
    moment = np.sum((sol.x - sol.load_position) * sol.pressure) * sol.cell_area
    assert abs(moment) < 1e-6 * force * (sol.x[-1] - sol.x[0])
    # p >= 0, gap >= 0 and p * gap = 0 (contact closed to 1 nm where loaded)
    assert np.all(sol.pressure >= 0)
    assert np.all(sol.gap >= -1e-9)
    assert np.all(np.abs(sol.gap[sol.pressure > 0]) < 1e-9)
    # the zones carry the whole load; a skate ski has no middle zone
    shares = sum(skate.zones[z].load_share for z in ("rear", "middle", "front"))
    assert shares == pytest.approx(1.0, rel=1e-12)
    assert skate.zones["middle"].patches == 0
    assert skate.breitschaedel is skate.zones.breitschaedel


def test_grid_convention_width_and_kick_zone() -> None:
    ski = get_ski("classic")
    x = stations(ski, N)
    assert x.size == N and x[0] == ski.x_tail and x[-1] == ski.x_tip
    np.testing.assert_allclose(np.diff(x), (ski.x_tip - ski.x_tail) / (N - 1), rtol=1e-12)
    case = solve_case(ski, **KW)
    np.testing.assert_array_equal(case.x, x)
    assert case.width == ski.width and case.solution.width == ski.width
    assert case.kick_zone == ski.kick_zone and case.zones.kick_zone == ski.kick_zone
    # the cell area of the strip model is dx times the ski's own width
    assert case.solution.cell_area == pytest.approx((x[1] - x[0]) * ski.width, rel=1e-12)


def test_width_only_for_a_bare_profile(skate: Case) -> None:
    with pytest.raises(InputError, match="own width"):
        solve_case("skate", width=0.05, **KW)
    with pytest.raises(InputError, match="profile"):
        solve_case(None, **KW)


def test_bare_profile_is_the_same_case(skate: Case) -> None:
    # the same profile given as a bare (x, h) of a ski of the same width: identical contact
    bare = solve_case(
        None, profile=(skate.x, skate.height), width=skate.width, label="mine",
        **{k: v for k, v in KW.items() if k != "profile_source"},
    )  # fmt: skip
    assert bare.label == "mine" and bare.ski is None and bare.profile_source == "given"
    np.testing.assert_array_equal(bare.solution.pressure, skate.solution.pressure)
    np.testing.assert_equal(bare.zones.as_dict(), skate.zones.as_dict())  # the same grouping


def test_precomputed_profile_gives_the_identical_case(skate: Case) -> None:
    x, heights = loaded_profiles("skate", [30.0, 45.0], -0.12, profile_source="beam", n_points=N)
    case = solve_case("skate", profile=(x, heights[1]), **KW)
    np.testing.assert_array_equal(case.height, skate.height)
    np.testing.assert_array_equal(case.solution.pressure, skate.solution.pressure)
    np.testing.assert_equal(case.zones.as_dict(), skate.zones.as_dict())  # NaN == NaN here


def test_warm_start_does_not_change_the_answer(skate: Case) -> None:
    lighter = solve_case("skate", **{**KW, "mass": 42.0})
    warm = solve_case("skate", start=lighter.solution.pressure, **KW)
    assert warm.converged
    # the same contact set and pressures to the solver tolerance (1e-8 -> 1e-6 margin)
    np.testing.assert_array_equal(warm.solution.pressure > 0, skate.solution.pressure > 0)
    np.testing.assert_allclose(
        warm.solution.pressure, skate.solution.pressure, atol=1e-6 * skate.solution.pressure.max()
    )


def test_unsupported_load_and_nan_profiles() -> None:
    x = stations("skate", N)
    with pytest.raises(UnsupportedLoadError, match="skate"):
        solve_case("skate", profile=(x, np.full(N, np.nan)), **KW)
    # the beam cannot carry a load whose boot plate reaches beyond the tail: the batched
    # profiles mark it by a row of NaN, a single case raises
    _, h = loaded_profiles("skate", [45.0], -0.91, profile_source="beam", n_points=N)
    assert np.all(np.isnan(h))
    with pytest.raises(UnsupportedLoadError, match="tail"):
        solve_case("skate", **{**KW, "load_position": -0.91})


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"mass": -1.0}, "mass"),
        ({"snow_modulus": float("nan")}, "snow_modulus"),
        ({"load_position": float("inf")}, "load_position"),
        ({"model": "line2"}, "model"),
        ({"profile_source": "oracle"}, "profile_source"),
        ({"n_points": 8}, "n_points"),
    ],
)
def test_bad_input_names_the_argument(change: dict, message: str) -> None:
    with pytest.raises(InputError, match=message):
        solve_case("skate", **{**KW, **change})


def test_network_outside_its_domain_is_a_warning_on_the_case() -> None:
    pytest.importorskip("jax")
    # 200 kg lies outside the network's trained 5-130 kg: the case says so, nothing is raised
    case = solve_case("skate", **{**KW, "profile_source": "network", "mass": 200.0})
    assert any("outside its trained domain" in w for w in case.warnings)
    with pytest.warns(DomainWarning):  # the lower-level batched call warns as before
        loaded_profiles("skate", [200.0], -0.12, n_points=N, profile_source="network")
