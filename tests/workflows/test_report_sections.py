"""The report's workflow sections render the workflow results (numbers as computed)."""

from __future__ import annotations

from skisnow.report._html import render_page
from skisnow.report._workflows import cycle_section, fleet_section
from skisnow.workflows import compare_fleet, kick_contact_summary, run_cycle, template_history


def test_stride_and_fleet_sections_show_the_computed_numbers() -> None:
    ds = run_cycle(
        "classic",
        template_history("diagonal", body_mass=75, n_frames=12),
        snow_modulus=100e6,
        n_points=512,
    )
    cmp = compare_fleet(["classic", "skate"], body_mass=75, snow_modulus=100e6, n_points=512)
    page = render_page("t", "s", [cycle_section(ds), fleet_section(cmp, criterion="peak-pressure")])
    s = kick_contact_summary(ds)
    assert f"{s['contact_time']:.3g}" in page
    assert "grip wax touches" in page and "Contact over a cycle" in page
    assert page.count("<figure") == 2  # each drawn wide and, where it fits, for a phone
    ranking = cmp.ranking("peak-pressure")
    assert f"{ranking[0]['full_total_peak_pressure_kpa']:.4g}" in page
    assert "lower is better" in page


def test_fleet_section_shows_the_intervals_of_an_identified_ski() -> None:
    import dataclasses

    from _posterior import with_posterior
    from skisnow.ski import get_ski

    ident = dataclasses.replace(with_posterior(get_ski("classic")), name="identified")
    cmp = compare_fleet([ident, "skate"], body_mass=75, snow_modulus=100e6, n_points=512,
                        samples=12)  # fmt: skip
    page = render_page("t", "s", [fleet_section(cmp, criterion="peak-pressure")])
    row = next(r for r in cmp.ranking("peak-pressure") if r["ski"] == "identified")
    assert f"{row['interval'][0]:.4g} – {row['interval'][1]:.4g}" in page
    assert "no uncertainty recorded" in page  # the shipped skate


def test_a_skate_cycle_has_no_grip_wax_rows() -> None:
    """A ski without a kick zone has no grip wax: the report and the CLI record say nothing
    of it (no 'grip wax touches 0 s'), the classic's section keeps those rows (above)."""
    from skisnow.cli._workflows_cycle import summary_record

    ds = run_cycle(
        "skate",
        template_history("skate_g3", body_mass=70, n_frames=8),
        snow_modulus=100e6,
        n_points=512,
    )
    assert not ds.attrs["kick_zone"]
    page = render_page("t", "s", [cycle_section(ds)])
    assert "grip wax" not in page and "kick marks" not in page and "touch-downs" not in page
    assert f"{float(ds['load'].max()):.3g}" in page  # the rest is shown
    rec = summary_record(ds)
    kick = ["kick_contact_time_s", "kick_fraction_of_loaded", "first_touch_s", "last_touch_s",
            "touch_downs", "max_kick_share", "max_kick_length_mm"]  # fmt: skip
    assert all(rec[k] is None for k in kick)
    assert rec["loaded_time_s"] > 0 and rec["peak_force_n"] > 0
