"""The Figure 8-9 findings of Kalliorinne et al. (2023) as criteria, on constructed maps."""

from __future__ import annotations

import numpy as np
import pytest

from skisnow import InputError
from skisnow.paper import ZoneMaps, figure89_findings, zone_maps

M = np.arange(5.0, 81.0, 5.0)
E = np.arange(20.0, 401.0, 20.0)


def maps(*, split_at: float, rear_bump: bool) -> ZoneMaps:
    """Rear area growing with the load (optionally with a bump at 35-40 kg on stiff snow), front
    area rising to 30 kg then flat, the front splitting at ``split_at`` kg on every snow."""
    mm, ee = np.meshgrid(M, E, indexing="ij")
    rear = 2.0 + 0.5 * mm * (1.0 + 100.0 / ee)
    if rear_bump:
        bump = np.where((mm == 40.0) & (ee > 260), 3.0, 0.0)
        rear = rear + bump - np.where((mm == 45.0) & (ee > 260), 1.0, 0.0)
    front = np.where(mm <= 30, 10.0 + mm, 40.0 - 0.05 * (mm - 30)) * (1 + 0.25 * ee / 400)
    front[(mm == 30)] *= 1.1  # a local maximum at 30 kg
    g = 9.80665 * 0.33
    return ZoneMaps(
        masses_kg=M,
        moduli_mpa=E,
        area_cm2={"rear": rear, "front": front},
        pressure_kpa={"rear": 0.67 * mm * 9.80665 / rear * 10, "front": mm * g / front * 10},
        patches={"rear": np.ones_like(mm, dtype=int), "front": np.where(mm >= split_at, 2, 1)},
        breitschaedel_cm2={"rear": rear[:, 3] * 0.9, "front": front[:, 0]},
    )


def by_key(found):  # type: ignore[no-untyped-def]
    return {f.key: f for f in found}


def test_findings_read_constructed_maps() -> None:
    f = by_key(figure89_findings(maps(split_at=35.0, rear_bump=True)))
    assert len(f) == 12
    assert f["rear-area-increases"].shown
    assert f["rear-local-max-35-40kg"].shown
    assert f["front-splits-35kg"].shown and "35-35" in f["front-splits-35kg"].measured
    assert f["front-area-increases-to-30kg"].shown
    # a maximum at 30 kg of 40·1.1·1.25 = 55 cm² at 400 MPa: within the paper's "about 50"
    assert f["front-local-max-30kg"].shown and "55.0 cm²" in f["front-local-max-30kg"].measured
    assert f["breitschaedel-front-soft-snow"].shown  # identical to the 20 MPa line
    assert f["breitschaedel-rear-trend"].shown  # proportional to the rear area


def test_findings_fail_where_the_maps_differ() -> None:
    f = by_key(figure89_findings(maps(split_at=60.0, rear_bump=False)))
    assert not f["front-splits-35kg"].shown and "60-60" in f["front-splits-35kg"].measured
    assert not f["rear-local-max-35-40kg"].shown
    assert f["rear-area-increases"].shown


def test_zone_maps_checks_its_grid() -> None:
    from skisnow.ski import get_ski

    with pytest.raises(InputError, match="masses"):
        zone_maps(get_ski("skate"), [30.0], [100.0])
