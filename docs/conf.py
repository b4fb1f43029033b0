"""Sphinx configuration of skisnow's documentation site.

Build (warnings are errors)::

    uv run --group docs sphinx-build -W --keep-going -b html docs docs/_build/html

``SKISNOW_DOCS_GALLERY=0`` skips running the examples (the gallery pages then show the code
only); ``SKISNOW_DOCS_GALLERY=small`` (the default) runs them on the small grids the tests use;
``full`` runs them as a user would (minutes).

The API reference is generated at build time: one page per public subpackage of ``skisnow``
(every name in its ``__all__`` whose home is that subpackage, through autosummary), written to
``docs/api/generated/`` (not committed). Each section's index collects every ``.md`` page of its
folder (a glob), so a page added to ``docs/user-guide/`` etc. appears without editing an index.
"""

from __future__ import annotations

import atexit
import importlib
import inspect
import os
import pkgutil
import re
import shutil
import sys
import tempfile
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT / "src"))
sys.path.insert(0, str(ROOT / "examples"))  # the examples import their helper `_cases`

import skisnow  # noqa: E402

project = "skisnow"
author = "skisnow developers"
copyright = "skisnow developers, MIT licence"
release = version = skisnow.__version__

extensions = [
    "myst_parser",
    "numpydoc",
    "sphinx.ext.napoleon",  # after numpydoc: the few Google-style "Args:" docstrings
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "figures/*.csv", "**/README.md"]
templates_path = ["_templates"]
html_static_path = ["_static"]
html_theme = "pydata_sphinx_theme"
html_title = "skisnow"
html_theme_options = {
    "navigation_depth": 3,
    "show_toc_level": 2,
    "secondary_sidebar_items": ["page-toc"],
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
}
html_show_sourcelink = False

myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
suppress_warnings = [
    "myst.header",  # moved README sections may start below level 1
    "config.cache",  # sphinx_gallery_conf holds functions: the environment is rebuilt each time
]

autosummary_generate = True
autosummary_imported_members = True
autodoc_typehints = "none"  # numpydoc renders the types from the docstrings
autodoc_default_options = {"members": False}
numpydoc_show_class_members = False
numpydoc_validation_checks: set[str] = set()
numpydoc_xref_param_type = False
napoleon_numpy_docstring = False  # numpydoc renders those
napoleon_google_docstring = True


_LITERAL = re.compile(r"(``.+?``)")


def _escape_bars(app, what, name, obj, options, lines: list[str]) -> None:
    """Docstrings write |x| for an absolute value (physics notation), which reStructuredText
    reads as a substitution reference: escape every bar outside inline literals, except on the
    lines of tables and line blocks (``+---`` or ``| `` at their start)."""
    for i, line in enumerate(lines):
        opening = line.lstrip()[:2]
        if "|" not in line or opening[:1] == "+" or opening in ("|", "| "):
            continue  # a table or a line block
        parts = _LITERAL.split(line)
        lines[i] = "".join(
            part if k % 2 else re.sub(r"(?<!\\)\|", r"\\|", part) for k, part in enumerate(parts)
        )


def _no_type_docstring(app, what, name, obj, options, lines: list[str]) -> None:
    """A constant without a doc-comment shows nothing, not its type's docstring (a ``dict``'s, a
    :class:`~skisnow.materials.Material`'s); runs after numpydoc."""
    if what not in ("data", "attribute") or inspect.isclass(obj) or inspect.isroutine(obj):
        return
    own = getattr(obj, "__doc__", None)
    typedoc = inspect.getdoc(type(obj)) or ""
    first = next((ln.strip() for ln in typedoc.splitlines() if ln.strip()), "")
    if own == type(obj).__doc__ or (first and any(first in ln for ln in lines[:8])):
        lines[:] = []


def setup(app) -> None:
    app.connect("autodoc-process-docstring", _escape_bars, priority=400)  # before numpydoc
    app.connect("autodoc-process-docstring", _no_type_docstring, priority=600)  # after it


# -- the API reference: one page per public subpackage -------------------------------------------

API = DOCS / "api" / "generated"


def _home(package: str, name: str, obj: object) -> bool:
    """Whether ``package.name`` is where ``obj`` is documented: a class or function whose defining
    module lies inside ``package`` (compatibility re-exports are listed on their home's page)."""
    if not (inspect.isclass(obj) or inspect.isroutine(obj) or inspect.ismodule(obj)):
        # constants and instances of skisnow's or Python's types are documented where they are
        # exported; an instance of another library's type (the CLI's Typer app) is not API
        kind = type(obj).__module__
        return kind == "builtins" or kind.split(".")[0] in ("skisnow", "numpy")
    module = getattr(obj, "__module__", None)
    if module is None:
        return True
    return module == package or module.startswith(package + ".")


def write_api_pages() -> list[str]:
    """Write ``api/generated/<subpackage>.rst`` for every public subpackage; return their names."""
    shutil.rmtree(API, ignore_errors=True)  # stale stubs of names no longer exported
    API.mkdir(parents=True)
    pages = []
    for info in sorted(pkgutil.iter_modules(skisnow.__path__), key=lambda i: i.name):
        if info.name.startswith("_") or not info.ispkg:
            continue
        package = f"skisnow.{info.name}"
        mod = importlib.import_module(package)
        names = [n for n in getattr(mod, "__all__", []) if _home(package, n, getattr(mod, n))]
        title = f"``{package}``"
        body = [title, "=" * len(title), "", f".. automodule:: {package}", "   :no-members:", ""]
        if names:
            body += [".. currentmodule:: " + package, "", ".. autosummary::",
                     "   :toctree: stubs", "   :nosignatures:", ""]  # fmt: skip
            body += [f"   {n}" for n in names]
        else:
            body += ["(no public names beyond the module's own documentation)"]
        (API / f"{package}.rst").write_text("\n".join(body) + "\n", encoding="utf-8")
        pages.append(package)
    return pages


write_api_pages()

# -- the gallery of examples/ --------------------------------------------------------------------

GALLERY = os.environ.get("SKISNOW_DOCS_GALLERY", "small").strip().lower()
if GALLERY not in {"0", "off", "small", "full"}:
    raise ValueError(f"SKISNOW_DOCS_GALLERY must be 0, small or full, got {GALLERY!r}")
_GALLERY_OUT = Path(tempfile.mkdtemp(prefix="skisnow-gallery-"))
# the examples' own output files are not part of the site: removed when the build's process ends
atexit.register(shutil.rmtree, _GALLERY_OUT, ignore_errors=True)


def _example_argv(gallery_conf: dict, script_vars: dict) -> list[str]:
    """The command line of each example in the gallery: small grids and beam profiles when
    ``SKISNOW_DOCS_GALLERY=small`` (as ``tests/examples`` runs them), sweeps in process."""
    name = Path(script_vars["src_file"]).name
    small = GALLERY == "small"
    if name == "micro_s1_s5.py":  # prints its table, writes no file
        return ["--workers", "1", *(["--small"] if small else [])]
    args = ["--out", str(_GALLERY_OUT / Path(name).stem), *(["--small"] if small else [])]
    if name.startswith("fig"):
        args += ["--formats", "png", *(["--profile-source", "beam"] if small else [])]
    if name == "flexible_vs_rigid.py":
        args += ["--formats", "png"]
    if name == "fig8_9_maps.py":
        args += ["--workers", "0"]
    return args


class _WrittenPNGs:
    """Image scraper: the PNG files an example wrote (they save their figures and close them)."""

    def __repr__(self) -> str:  # sphinx-gallery caches on the repr
        return "skisnow-written-pngs"

    def __call__(self, block, block_vars, gallery_conf):
        from sphinx_gallery.scrapers import figure_rst

        out = _GALLERY_OUT / Path(block_vars["src_file"]).stem
        pngs = sorted(out.glob("*.png")) if out.is_dir() else []
        paths = []
        for png, target in zip(pngs, block_vars["image_path_iterator"], strict=False):
            shutil.copyfile(png, target)
            paths.append(target)
        return figure_rst(paths, gallery_conf["src_dir"])


sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/(fig|flexible|micro|paper)[^/]*\.py$",
    "ignore_pattern": r"(^|/)_[^/]*\.py$",
    "plot_gallery": GALLERY != "0" and GALLERY != "off",
    "reset_argv": _example_argv,
    "image_scrapers": (_WrittenPNGs(),),
    "download_all_examples": False,
    "remove_config_comments": True,
    "abort_on_example_error": True,
    "only_warn_on_example_error": False,
    "within_subsection_order": "FileNameSortKey",
    "min_reported_time": 1,
}
