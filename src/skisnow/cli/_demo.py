"""Commands for the end-to-end demo (first version: the ski; later issues extend it)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from skisnow.cli._app import app
from skisnow.cli._render import console, emit_json

__all__ = ["run_ski_demo"]


def run_ski_demo(out: Path, *, progress: bool = True) -> dict[str, Any]:
    """Bench both shipped skis, compute their metrics and draw their camber profiles into ``out``.

    Returns a document with the metrics and the files written.
    """
    from skisnow.cli._ski import _progress_bar, metrics_documents
    from skisnow.io import write_bench
    from skisnow.plot import plot_camber_profiles
    from skisnow.plot._style import save_figure
    from skisnow.ski import SHIPPED_SKIS, run_bench

    out.mkdir(parents=True, exist_ok=True)
    files: list[str] = []
    docs = []
    for name in SHIPPED_SKIS:
        with _progress_bar(f"bench {name}") as bar:
            task = bar.add_task("bench", total=None)

            def tick(done: int, total: int, bar: Any = bar, task: Any = task) -> None:
                bar.update(task, completed=done, total=total)

            data = run_bench(name, progress=tick if progress else None)
        path = write_bench(data, out / f"bench_{name}.parquet")
        files.append(str(path))
        docs.extend(metrics_documents(str(path), body_mass_kg=65.0, load_position_mm=-80.0))
    fig = plot_camber_profiles(SHIPPED_SKIS)
    files.extend(str(p) for p in save_figure(fig, out / "camber_profiles", formats=("png",)))
    return {"output_dir": str(out), "files": files, "metrics": docs}


@app.command()
def demo(
    out: Annotated[Path, typer.Option("--out", help="Output directory.")] = Path("skisnow-output"),
    json_out: bool = typer.Option(False, "--json", help="Print one JSON document, nothing else."),
) -> None:
    """Run the end-to-end demo on the shipped skis and say where the files went."""
    from skisnow.cli._ski import print_metrics_table

    doc = run_ski_demo(out)
    if json_out:
        emit_json(doc)
        return
    print_metrics_table(doc["metrics"], "Shipped skis on the virtual bench (65 kg skier)")
    console.print(f"Files written to {doc['output_dir']}/:")
    for f in doc["files"]:
        console.print(f"  {f}")
