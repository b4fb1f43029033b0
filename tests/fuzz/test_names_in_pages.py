"""Hostile names in the pages skisnow writes, read back as a browser reads them.

A ski's name (the report shows it) and a ski file's name (the explorer's label) hold
``</script>``, ``<!--<script>``, both quotes, ``&``, markup, terminal and bidirectional control
characters, ``NUL`` and letters beyond ASCII. The written pages are parsed with html5lib, the
WHATWG tokenizer and tree builder (the script-data states in which ``<!--<script>`` merges
script blocks included; Python's ``html.parser`` has none of them), which must report no parse
error and find exactly the elements the page was built with; the explorer's JSON data block must
parse back to the same names; and, where Debian's Chromium and chromedriver are installed, the
explorer runs with a clean console and shows the name as it is.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from _browser import wait_ready
from skisnow._names import printable
from skisnow.cli import main

html5lib = pytest.importorskip("html5lib")

#: A ski's name: everything that could end a script block, open a comment, add markup or
#: escape an attribute, with control characters and letters beyond ASCII.
NAME = "</script><!--<script>alert(1)</script>\"'&amp;<b>x</b>\x1b[31m\x07\x00\u202eÅsa Ølstad Δ"
#: A file name holds the same except ``/`` (no file name can).
FILE = "ski <!--<script>\"'&amp;<b>\x1b[2J\u202e Åsa 雪.json"


@pytest.fixture(scope="module")
def pages(tmp_path_factory) -> dict[str, Path]:
    from skisnow.ski import shipped_ski_path

    d = tmp_path_factory.mktemp("names")
    doc = json.loads(shipped_ski_path("skate").read_text())
    doc["name"] = NAME
    ski = d / FILE
    ski.write_text(json.dumps(doc), encoding="utf-8")
    small = ["--snow-modulus-mpa", "100", "--workers", "0"]
    assert main(["report", str(ski), "--mass-kg", "60", "--stride", "none", "--points", "256",
                 *small, "--out", str(d / "report")]) == 0  # fmt: skip
    assert main(["explore", str(ski), "skate", "--mass-kg", "60", "--load-position-mm", "-120",
                 "--stations", "16", *small, "--out", str(d / "explore.html")]) == 0  # fmt: skip
    (report,) = (d / "report").glob("*.html")
    assert report.parent == d / "report"  # the page stays inside --out
    return {"report": report, "explorer": d / "explore.html"}


def _parse(page: Path):
    parser = html5lib.HTMLParser(namespaceHTMLElements=False)
    tree = parser.parse(page.read_text(encoding="utf-8"))
    return tree, [(pos, code) for pos, code, _ in parser.errors]


def _text(element) -> str:
    return "".join(element.itertext())


def test_the_report_shows_the_name_and_nothing_else(pages) -> None:
    tree, errors = _parse(pages["report"])
    assert errors == []  # no raw NUL or control character, no stray markup
    assert tree.findall(".//script") == [] and tree.findall(".//b") == []
    shown = printable(NAME)  # what a reader sees: the characters, controls as escapes
    assert shown in _text(tree.find(".//h1")) and shown in _text(tree.find(".//title"))
    assert "\x1b" not in _text(tree) and "\u202e" not in _text(tree)


def test_the_explorer_keeps_its_three_script_blocks_and_its_data_the_names(pages) -> None:
    tree, errors = _parse(pages["explorer"])
    assert errors == []
    scripts = tree.findall(".//script")
    assert [(s.get("type"), s.get("id")) for s in scripts] == [
        ("application/json", "skisnow-meta"),
        ("application/octet-stream", "skisnow-blob"),
        (None, None),
    ]
    meta = json.loads(scripts[0].text)  # the data block, as the page's JSON.parse reads it
    assert meta["grid"]["ski"] == [FILE, "skate"]
    assert "function" in scripts[2].text and FILE not in scripts[2].text  # the code, untouched
    assert printable(FILE) in _text(tree.find(".//body"))


@pytest.mark.slow
def test_the_explorer_runs_and_shows_the_name(pages, make_browser) -> None:
    driver = make_browser()
    try:
        driver.get(pages["explorer"].as_uri())
        wait_ready(driver)
        assert driver.execute_script("return document.getElementById('ski').options[0].text")\
            == FILE  # fmt: skip
        assert driver.execute_script(
            "return document.getElementById('status').textContent"
        ).startswith(FILE)
        doc = json.loads(driver.execute_script("return window.skisnowExplorer.exportText('json')"))
        assert doc["ski"] == FILE
        assert driver.execute_script("return document.scripts.length") == 3  # none added
        errors = [e for e in driver.get_log("browser") if e["level"] in ("SEVERE", "WARNING")]
        assert errors == []
    finally:
        driver.quit()
