"""Regions and patches (issue 26): bookkeeping, and continuity over a load sweep in 1 kg steps.

A region is a fixed set of stations (rear glide | kick zone | front glide, or rear | front at the
balance point), so between neighbouring loads a region metric may change only through the cells
that change: its length by no more than the cells whose contact status changed (plus one cell),
its load by no more than the change of the total load plus one cell's load per cell that
changed, its peak pressure by no more than the largest pointwise pressure change. The paper's
whole-patch zones break these bounds where two patches join (on main before issue 26: 314 mm in
one step, classic at -120 mm, 20 MPa; ``benchmarks/zone_continuity.py``).
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from skisnow import InputError
from skisnow.constants import STANDARD_GRAVITY
from skisnow.contact import footprint, region_index, region_marks
from skisnow.pipeline import solve_case


def test_footprint_bookkeeping_on_a_constructed_mask() -> None:
    x = (np.arange(100) + 0.5) * 0.01 - 0.5  # 10 mm cells, -0.5 … 0.5 m
    contact = (x > -0.40) & (x < 0.30)
    force = np.where(contact, 2.0, 0.0)
    fp = footprint(x, contact, kick_zone=(-0.1, 0.1), force=force, area=0.01 * 0.044 * contact,
                   max_pressure=force, penetration=force * 1e-4)  # fmt: skip
    assert fp.names == ("rear_glide", "kick_zone", "front_glide")
    rear, kick, front = fp.regions
    assert rear.cells == 30 and kick.cells == 20 and front.cells == 20
    assert sum(r.force for r in fp.regions) == pytest.approx(force.sum(), rel=1e-15)
    assert sum(r.load_share for r in fp.regions) == pytest.approx(1.0, rel=1e-15)
    assert kick.start == -0.1 and kick.end == 0.1 and rear.start == -np.inf
    assert kick.mean_pressure == pytest.approx(2.0 / (0.01 * 0.044))
    (patch,) = fp.patches
    assert patch.regions == ("rear_glide", "kick_zone", "front_glide")
    assert patch.length == pytest.approx(0.70) and patch.force == pytest.approx(140.0)
    # without a kick zone: rear/front at the balance point, stated
    fp2 = footprint(x, contact)
    assert fp2.names == ("rear_glide", "front_glide") and fp2.rule == "balance point"
    assert fp2.regions[0].length == pytest.approx(0.40) and np.isnan(fp2.regions[0].force)
    # a station on a mark belongs to the kick zone
    assert region_index(np.array([-0.1, 0.1, 0.1000001]), (-0.1, 0.1)).tolist() == [1, 1, 2]
    with pytest.raises(InputError, match="kick_zone"):
        region_marks((0.2, -0.2))


def test_zone_metrics_regions_are_the_footprint_regions() -> None:
    c = solve_case("classic", mass=75.0, load_position=-0.120, snow_modulus=50e6,
                   profile_source="beam", n_points=512)  # fmt: skip
    z = c.zones
    for region in z.footprint.regions:
        zone = z[region.name]
        assert (zone.length, zone.force, zone.area) == (region.length, region.force, region.area)
        assert zone.max_pressure == region.max_pressure
    assert z["kick_zone"].force == z.kick.force  # the kick metric is the kick-zone region
    doc = z.as_dict()
    assert set(doc["regions"]) == {"rear_glide", "kick_zone", "front_glide"}
    assert sum(p["force"] for p in doc["patches"]) == pytest.approx(75.0 * STANDARD_GRAVITY)
    skate = solve_case("skate", mass=60.0, load_position=0.0, snow_modulus=50e6,
                       profile_source="beam", n_points=512).zones  # fmt: skip
    assert skate.footprint.names == ("rear_glide", "front_glide")
    assert skate["kick_zone"].length == 0.0 and skate.footprint.rule == "balance point"


@pytest.mark.parametrize(
    ("ski", "mass", "position", "modulus"),
    [("classic", 75.0, -0.120, 50e6), ("classic", 40.0, -0.120, 300e6),
     ("classic", 110.0, 0.0, 20e6), ("skate", 60.0, -0.120, 100e6)],
)  # fmt: skip
def test_metrics_are_the_sums_over_their_stations_to_the_last_bit(ski, mass, position, modulus):
    # Every zone, region and patch metric is the plain sum (or maximum) of the per-station
    # values over its stations, taken here independently with a boolean mask of the stations
    # its intervals cover: equal to the last bit (the same values summed in the same order), so
    # no shortcut (prefix sums, reordering) may change a stored number.
    c = solve_case(ski, mass=mass, load_position=position, snow_modulus=modulus,
                   profile_source="beam", n_points=1024)  # fmt: skip
    s, z = c.solution, c.zones
    x, dx, p = s.x, s.dx, s.pressure
    force, area = p * dx * s.width, np.full(x.size, dx * s.width)

    def stations(intervals) -> np.ndarray:
        sel = np.zeros(x.size, dtype=bool)
        for a, b in intervals:
            sel |= (x > a) & (x < b)  # interval ends lie half a cell outside the stations
        return sel

    zones = [z[n] for n in ("rear", "middle", "front", "total", "kick", *z.footprint.names)]
    for zone in zones:
        if not zone.intervals:
            continue
        sel = stations(zone.intervals)
        assert zone.force == float(force[sel].sum()) and zone.area == float(area[sel].sum())
        assert zone.max_pressure == float(p[sel].max())
        assert zone.length == float(sel.sum() * dx)
    for patch in z.footprint.patches:
        sel = stations([(patch.start, patch.end)])
        assert patch.force == float(force[sel].sum()) and patch.area == float(area[sel].sum())
        assert patch.max_pressure == float(p[sel].max()) and patch.length == sel.sum() * dx
    for region in z.footprint.regions:
        sel = (p > 0) & stations([(region.start, region.end)])
        assert region.force == float(force[sel].sum()) and region.cells == int(sel.sum())
        assert region.area == float(area[sel].sum())


CASES = [
    ("classic", -0.120, 20e6, "rigid"),
    ("classic", -0.070, 50e6, "rigid"),
    ("classic", 0.0, 300e6, "rigid"),
    ("classic", -0.095, 140e6, "flexible"),
    ("skate", -0.120, 50e6, "rigid"),
]


@pytest.mark.slow
@pytest.mark.parametrize(("ski", "position", "modulus", "ski_model"), CASES)
def test_region_metrics_are_continuous_in_the_load(ski, position, modulus, ski_model) -> None:
    solved = []
    for m in range(20, 131):
        c = solve_case(ski, mass=float(m), load_position=position, snow_modulus=modulus,
                       profile_source="beam", n_points=256, ski_model=ski_model)  # fmt: skip
        s = c.solution
        line_force = s.pressure * s.dx * s.width
        regions = c.zones.footprint.regions
        # region loads add to the total, which is the weight (force balance, eq. 3)
        assert sum(r.force for r in regions) == pytest.approx(m * STANDARD_GRAVITY, rel=1e-6)
        assert sum(r.length for r in regions) == pytest.approx(c.zones.total.length, rel=1e-12)
        if c.zones.merged:  # a merged footprint: the paper's zones are the regions
            for zone, region in zip(("rear", "middle", "front"), regions, strict=False):
                assert c.zones[zone].force == region.force
        solved.append((c, line_force))
    merged = [c.zones.merged for c, _ in solved]
    for (a, fa), (b, fb) in itertools.pairwise(solved):
        pa, pb = a.solution.pressure, b.solution.pressure
        idx = region_index(a.x, a.zones.footprint.marks)
        changed = (pa > 0) != (pb > 0)
        one_cell = max(fa.max(), fb.max())
        dw = abs(b.mass - a.mass) * STANDARD_GRAVITY
        for k, (ra, rb) in enumerate(zip(a.zones.footprint.regions, b.zones.footprint.regions,
                                         strict=True)):  # fmt: skip
            dx = a.solution.dx
            assert abs(rb.length - ra.length) <= (changed[idx == k].sum() + 1) * dx + 1e-12
            assert abs(rb.length - ra.length) <= (changed.sum() + 1) * dx + 1e-12
            # the load may move only with the cells that change: ΔW plus one cell's load per
            # cell that changed anywhere (a kick zone touching down unloads the glide zones)
            cell_loads = (changed.sum() + 1) * one_cell
            assert abs(rb.force - ra.force) <= dw + cell_loads, (ra.name, a.mass)
            assert abs(rb.load_share - ra.load_share) <= (dw + cell_loads) / (a.mass * 9.8)
            dp = np.abs(pb - pa)[idx == k]
            # the pressure field is 0 where a region has no contact (its peak: NaN, no value)
            peak_a, peak_b = np.nan_to_num(ra.max_pressure), np.nan_to_num(rb.max_pressure)
            assert abs(peak_b - peak_a) <= dp.max() + 1e-9
    assert len(merged) == 111


def test_fields_file_names_each_stations_region_and_patch(tmp_path) -> None:
    import pandas as pd

    from skisnow.contact import read_fields, write_fields

    c = solve_case("classic", mass=70.0, load_position=-0.120, snow_modulus=50e6,
                   profile_source="beam", n_points=512)  # fmt: skip
    path = write_fields(c.solution, tmp_path / "f.csv", c.zones)
    table = pd.read_csv(path)
    assert ((table["patch"] > 0) == (c.solution.pressure > 0)).all()
    assert table["patch"].max() == len(c.zones.footprint.patches)
    for region in c.zones.footprint.regions:
        cells = ((table["region"] == region.name) & (table["patch"] > 0)).sum()
        assert cells == region.cells
    back = read_fields(path)  # the extra columns do not disturb the round trip
    np.testing.assert_allclose(back["pressure"], c.solution.pressure, rtol=1e-9, atol=1e-6)
