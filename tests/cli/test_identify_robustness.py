"""Issue 25's robustness re-checks of ``skisnow identify`` on benches like the issue's (item 3):
a noise given 10× too small, a bench refused as implausible and re-run with
``--allow-implausible``, heights every 20 mm without ``--noise-mm``. Never exit 1: a clear error
(exit 2) or a result (exit 0, or 3 with the cause named). Small benches (three masses at one
load position, classic ski, 5 µm seeded noise) keep them to tens of seconds each."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import pytest

from skisnow.cli import main

pytestmark = pytest.mark.slow

_FAST = ["--n-stiffness", "20", "--max-nfev", "10"]


def _bench(capsys, tmp: Path, name: str, dx_mm: float) -> Path:
    out = tmp / f"{name}.csv"
    code = main(["bench", "classic", "--out", str(out), "--mass-kg", "20,40,60",
                 "--load-position-mm", "-120", "--noise-mm", "0.005", "--seed", "1",
                 "--dx-mm", str(dx_mm)])  # fmt: skip
    assert code == 0
    capsys.readouterr()
    return out


def _identify(capsys, args: list[str]) -> tuple[int, dict | None, str]:
    code = main([*args, "--json"])
    cap = capsys.readouterr()
    doc = json.loads(cap.out) if cap.out.strip() else None
    return code, doc, cap.err


def test_noise_given_ten_times_too_small_is_named(capsys, tmp_path: Path) -> None:
    bench = _bench(capsys, tmp_path, "b10", 10.0)
    code, doc, err = _identify(capsys, ["identify", str(bench), "--out",
                                        str(tmp_path / "a.json"), "--noise-mm", "0.0005",
                                        *_FAST])  # fmt: skip
    assert code in (0, 3), err
    assert "noise" in doc["causes"]
    words = " ".join(doc["warnings"])
    assert "noise misestimate" in words and "0.5 µm" in words


def test_implausible_bench_refused_then_identified_with_the_override(
    capsys, tmp_path: Path
) -> None:
    bench = _bench(capsys, tmp_path, "b10", 10.0)
    lines = bench.read_text().splitlines()
    header = [ln for ln in lines if ln.startswith("#")]
    df = pd.read_csv(bench, comment="#")
    df["height_mm"] += 0.1 * df["mass_kg"]  # heights rise with the mass: swapped data
    rising = tmp_path / "rising.csv"
    rising.write_text("\n".join(header) + "\n" + df.to_csv(index=False))
    out = tmp_path / "r.json"
    assert main(["identify", str(rising), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "higher under the load" in err and "--allow-implausible" in err
    code, doc, err = _identify(
        capsys, ["--allow-implausible", "identify", str(rising), "--out", str(out), *_FAST]
    )
    assert code in (0, 3), err  # never 1 (the LinAlgError crash of the issue)
    assert doc["causes"][0] == "implausible bench"
    assert "higher under the load" in doc["warnings"][0]
    assert out.is_file()


def test_heights_every_20_mm_need_no_noise_option(capsys, tmp_path: Path) -> None:
    bench = _bench(capsys, tmp_path, "b20", 20.0)
    code, doc, err = _identify(capsys, ["identify", str(bench), "--out",
                                        str(tmp_path / "c.json"), *_FAST])  # fmt: skip
    assert code in (0, 3), err
    # the noise is estimated from the data (5 µm true): across the three profiles at the same
    # stations, where the free camber cancels (issue 25's target: within ±15 %; one profile's
    # own fourth differences read 7.2 µm here, they see the camber's waviness)
    assert 0.00425 < doc["noise_mm"] < 0.00575


def test_bootstrap_option_reaches_every_replicate_and_one_is_refused(
    capsys, tmp_path: Path, monkeypatch
) -> None:
    import skisnow.identify._identify as ident

    bench = _bench(capsys, tmp_path, "b10", 10.0)
    out = tmp_path / "boot.json"
    code, doc, err = _identify(capsys, ["identify", str(bench), "--out", str(out),
                                        "--bootstrap", "1", *_FAST])  # fmt: skip
    assert code == 2 and "--bootstrap" in err
    seen: list[dict] = []

    def replicate(_bench, **kw):  # each replicate's identification (the bootstrap's import)
        seen.append(kw)
        raise RuntimeError("replicate not run in this test")

    monkeypatch.setattr(ident, "identify_ski", replicate)
    code, doc, err = _identify(capsys, ["identify", str(bench), "--out", str(out),
                                        "--bootstrap", "3", "--bootstrap-workers", "0",
                                        *_FAST])  # fmt: skip
    assert code in (0, 3), err
    assert len(seen) == 3 and all(k["n_stiffness"] == 20 and k["max_nfev"] == 10 for k in seen)
    # no replicate ended: the Laplace bands, said so, with what they are known to be worth
    assert doc["bootstrap_replicates"] == 0
    assert any("fewer than two replicates" in w for w in doc["warnings"])
    assert doc["bands"].startswith("Laplace posterior") and "under-cover" in doc["bands"]


def test_a_bootstrapped_ski_file_says_so_and_carries_the_replicates(capsys, tmp_path) -> None:
    # two real replicates (in this process): the summary and the ski file name the band method,
    # and the file's posterior gains one mode per replicate used, so the answers' intervals
    # (sample_skis draws from the modes) inherit the widened z0 bands
    from skisnow.ski import read_ski

    bench = _bench(capsys, tmp_path, "b10", 10.0)
    lap, boot = tmp_path / "lap.json", tmp_path / "boot.json"
    _identify(capsys, ["identify", str(bench), "--out", str(lap), *_FAST])
    code, doc, err = _identify(capsys, ["identify", str(bench), "--out", str(boot),
                                        "--bootstrap", "2", "--bootstrap-workers", "0",
                                        *_FAST])  # fmt: skip
    assert code in (0, 3), err
    n = doc["bootstrap_replicates"]
    assert n == 2 and "parametric bootstrap of 2 replicates" in doc["bands"]
    a, b = read_ski(lap), read_ski(boot)
    assert b.provenance.detail("bands") == doc["bands"]
    assert b.provenance.detail("bootstrap_scale") == "trimmed"
    assert len(b.camber_modes) == len(a.camber_modes) + n
    det = [i for i, d in enumerate(b.camber_determined) if d]
    assert all(b.camber_sd[i] >= a.camber_sd[i] for i in det)
