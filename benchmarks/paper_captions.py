"""The caption tables of docs/validation/paper-reproduction.md (issue 30), as markdown.

    uv run python benchmarks/paper_captions.py

Every shipped ski, both profile routes (network, beam), through ``skisnow.paper.caption_table``
(the numbers ``skisnow captions`` prints); each cell paper / network / beam, (share) = implied by
length × pressure; then each ski's departures from a plausible ski (reproduction skis) and the
count of zones within its tolerances per route.
"""

from __future__ import annotations

import json
import os
import time


def numbers_within(rows, tol) -> tuple[int, int]:  # type: ignore[no-untyped-def]
    """(within, checked) over the caption numbers of some rows: each length and mean pressure,
    each load share the tolerances hold (stated; implied too for the reproduction skis), each
    stated patch count; a zone the paper does not have counts as one number missed."""
    ok = n = 0
    for x in rows:
        if x.paper is None:
            n += 1
            continue
        checks = [abs(x.length_error) <= tol.length, abs(x.pressure_error) <= tol.pressure]
        if not x.share_implied or tol.implied_shares:
            checks.append(abs(x.share_error) <= tol.share)
        if x.paper.patches is not None:
            checks.append(x.patches == x.paper.patches)
        ok, n = ok + sum(checks), n + len(checks)
    return ok, n


def main() -> None:
    from skisnow.paper import ROUTES, caption_table, tolerances_of
    from skisnow.ski import REPRODUCTION_SKIS, SHIPPED_SKIS, get_ski

    t0 = time.process_time()
    print(f"load average {os.getloadavg()[0]:.2f}\n")
    by_route = {r: caption_table(route=r) for r in ROUTES}
    for name in SHIPPED_SKIS:
        tol = tolerances_of(get_ski(name))
        rows = {
            r: {(x.case.label, x.zone): x for x in by_route[r] if x.ski == name} for r in ROUTES
        }
        keys = list(dict.fromkeys(k for r in ROUTES for k in rows[r]))
        counts = {r: (sum(x.ok for x in rows[r].values()), len(rows[r])) for r in ROUTES}
        numbers = {r: numbers_within(rows[r].values(), tol) for r in ROUTES}
        print(f"**{name}** (±{tol.length:.0%} length, ±{tol.pressure:.0%} pressure, "
              f"±{tol.share * 100:.0f} points share"
              + (", implied shares held" if tol.implied_shares else "") + "): zones within "
              + ", ".join(f"{r} {a}/{b}" for r, (a, b) in counts.items()) + "; caption numbers "
              "within " + ", ".join(f"{r} {a}/{b}" for r, (a, b) in numbers.items())
              + "\n")  # fmt: skip
        print("| case | zone | length mm | mean p kPa | share % | patches | within (net, beam) |")
        print("| --- | --- | --- | --- | --- | --- | --- |")
        for key in keys:
            per = [rows[r].get(key) for r in ROUTES]
            x = next(p for p in per if p is not None)
            pz = x.paper

            def cell(paper, vals, fmt):  # type: ignore[no-untyped-def]
                f = lambda v: "—" if v is None else format(v, fmt)  # noqa: E731
                return " / ".join([f(paper), *(f(v) for v in vals)])

            share = None if x.paper_share is None else 100 * x.paper_share
            share_txt = "—" if share is None else (f"({share:.0f})" if x.share_implied
                                                   else f"{share:.0f}")  # fmt: skip
            print(
                f"| {key[0].replace(' ' + x.case.ski + ' ', ' ')} | {x.zone} | "
                + cell(None if pz is None else pz.length * 1e3,
                       [p.length * 1e3 if p else None for p in per], ".1f") + " | "
                + cell(None if pz is None else pz.mean_pressure * 1e-3,
                       [p.mean_pressure * 1e-3 if p else None for p in per], ".1f") + " | "
                + " / ".join([share_txt, *("—" if p is None else f"{p.load_share * 100:.0f}"
                                          for p in per)]) + " | "
                + " / ".join(["—" if pz is None or pz.patches is None else str(pz.patches),
                              *("0" if p is None else str(p.patches) for p in per)]) + " | "
                + " / ".join("—" if p is None else ("yes" if p.ok else "**no**") for p in per)
                + " |"
            )  # fmt: skip
        print()
        if name in REPRODUCTION_SKIS:
            deps = json.loads(get_ski(name).provenance.detail("departures"))
            print("Departures: " + "; ".join(deps) + ".\n")
    print(f"CPU {time.process_time() - t0:.0f} s, load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
