"""The fuzz corpus (tests/fuzz/corpus.py, and corpus_doors.py for the doors of ski files, load
histories, fleets, the explorer and report options, side-cars, re-signed models, archive bombs,
nested JSON and name injection): >= 200 + 150 malformed or hostile inputs, run in-process.
Fails on any silent acceptance, traceback or side effect (a store created by a rejected sweep,
a pickle payload executed, a file written outside --out, a name that ends a script block or
reaches the terminal raw), and on a rejection that does not name its place (option, file, and
the line or column where the case knows it)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))
from corpus import build_corpus, run_case, tally

from _extras import HAS_NETWORK


@pytest.mark.slow
def test_every_malformed_input_is_rejected_cleanly_and_names_its_place(tmp_path, capsys) -> None:
    from corpus_doors import DOOR_GROUPS

    cases = build_corpus(tmp_path / "corpus")
    doors = {g.__name__ for g in DOOR_GROUPS}
    n_new = sum(c.builder in doors for c in cases)
    assert len(cases) - n_new >= 200 and n_new >= 150
    outcomes = [run_case(c) for c in cases]
    counts = tally(outcomes)
    with capsys.disabled():
        print(f"\nfuzz corpus ({len(cases) - n_new} + {n_new} new cases):", counts)
    bad = [o for o in outcomes if o.kind != "clean"]
    assert not bad, "\n".join(f"{o.kind}: {o.case.id}: {o.message[:300]}" for o in bad)
    # without the optional network extra, `train` and `predict` are refused naming the extra
    unnamed = [
        o
        for o in outcomes
        if not o.names_place
        and not (
            not HAS_NETWORK
            and o.case.argv[0] in ("train", "predict")
            and "--extra network" in o.message
        )
    ]
    assert not unnamed, "\n".join(
        f"{o.case.id} (needs {o.case.place}): {o.message[:300]}" for o in unnamed
    )
