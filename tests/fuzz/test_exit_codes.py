"""Exit codes that mean something: 0 done and converged, 2 bad input, 3 not converged, 4 outside
a model's trained domain; ``--json`` always carries ``converged``, ``warnings`` and the version."""

from __future__ import annotations

import json

import pytest

from _extras import needs_network
from skisnow import __version__
from skisnow.cli import main
from skisnow.cli._app import EXIT_CODES

CONTACT = ["contact", "--ski", "skate", "--mass-kg", "60", "--load-position-mm", "-120",
           "--snow-modulus-mpa", "100", "--points", "256", "--json"]  # fmt: skip


def test_help_lists_every_exit_code(capsys) -> None:
    assert main(["--help"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    for code in EXIT_CODES:
        assert f"{code} " in out
    assert "Exit codes" in out


def test_converged_and_in_domain_is_0_with_annotations(capsys) -> None:
    assert main(CONTACT) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["converged"] is True and doc["warnings"] == []
    assert doc["skisnow_version"] == __version__


def test_bad_input_is_2(capsys) -> None:
    assert main([*CONTACT, "--mass-kg", "-60"]) == 2
    err = capsys.readouterr().err
    assert "--mass-kg" in err and len(err.strip().splitlines()) == 1
    assert main(["contact", "--no-such-option"]) == 2  # a usage error is bad input too


def test_unconverged_contact_is_3_and_says_so(capsys, monkeypatch) -> None:
    import skisnow.contact

    original = skisnow.contact.solve_contact

    def starved(*args, **kwargs):  # the same solve with 2 iterations: it cannot converge
        return original(*args, **{**kwargs, "max_iter": 2})

    monkeypatch.setattr(skisnow.contact, "solve_contact", starved)
    assert main(CONTACT) == 3
    captured = capsys.readouterr()
    doc = json.loads(captured.out)
    assert doc["converged"] is False
    assert "did not converge" in captured.err


@needs_network
def test_outside_the_trained_domain_is_4_and_listed(capsys) -> None:
    # 200 kg on the skate's network, trained on 5..130 kg: computed, flagged, exit 4
    code = main([*CONTACT[:-1], "--mass-kg", "200", "--profile-source", "network", "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert code == 4
    assert any("outside the trained" in w for w in doc["warnings"])
    assert doc["skisnow_version"] == __version__ and "converged" in doc


@pytest.mark.parametrize("args", [["skis", "--json"], ["rank", "--paper-tables", "--json"]])
def test_every_json_document_is_annotated(capsys, args) -> None:
    assert main(args) == 0
    doc = json.loads(capsys.readouterr().out)
    assert {"skisnow_version", "converged", "warnings"} <= set(doc)


def test_ctrl_c_in_a_sweep_is_130_and_says_what_was_kept(tmp_path, capsys, monkeypatch) -> None:
    import skisnow.sweep

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(skisnow.sweep, "run_sweep", interrupted)
    out = tmp_path / "s.zarr"
    args = ["sweep", "--ski", "skate", "--mass-kg", "30", "--snow-modulus-mpa", "100",
            "--workers", "0", "--out", str(out)]  # fmt: skip
    assert main(args) == 130
    assert "run the same command again" in capsys.readouterr().err


_SMALL = ["--points", "256"]
_STARVED_COMMANDS = {
    "sweep": ["sweep", "--ski", "skate", "--mass-kg", "60", "--snow-modulus-mpa", "100",
              "--workers", "0", *_SMALL, "--out", "{tmp}/s.zarr"],
    "report": ["report", "skate", "--mass-kg", "60", "--snow-modulus-mpa", "100", "--workers",
               "0", "--stride", "none", *_SMALL, "--out", "{tmp}/r"],
    "explore": ["explore", "skate", "--mass-kg", "60", "--load-position-mm", "-120",
                "--snow-modulus-mpa", "100", "--workers", "0", "--stations", "16",
                "--out", "{tmp}/e.html"],
    "compare": ["compare", "skate", "classic", "--body-mass-kg", "60", "--snow-modulus-mpa",
                "100", "--snow-range-mpa", "100,200", *_SMALL],
    "pairs": ["pairs", "skate", "classic", "--body-mass-kg", "60", "--snow-modulus-mpa", "100",
              *_SMALL],
    "cycle": ["cycle", "skate", "--template", "diagonal", "--body-mass-kg", "60", "--frames",
              "3", "--snow-modulus-mpa", "100", *_SMALL],
}  # fmt: skip


@pytest.mark.slow
@pytest.mark.parametrize("command", list(_STARVED_COMMANDS))
def test_every_command_exits_3_naming_the_unconverged_solves(
    command, tmp_path, capsys, monkeypatch
) -> None:
    """Every solve starved of iterations: the command still writes its result, and exits 3
    with the count of unconverged solves and the first named."""
    import skisnow.contact

    original = skisnow.contact.solve_contact

    def starved(*args, **kwargs):
        return original(*args, **{**kwargs, "max_iter": 2})

    monkeypatch.setattr(skisnow.contact, "solve_contact", starved)
    argv = [a.replace("{tmp}", str(tmp_path)) for a in _STARVED_COMMANDS[command]]
    assert main(argv) == 3
    err = " ".join(capsys.readouterr().err.split())
    assert "did not converge (first: skate" in err and "kg at" in err, err
