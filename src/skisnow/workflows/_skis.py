"""What a technician names a ski by: a shipped name, a ski file or a bench file."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from skisnow._errors import InputError, SkisnowError
from skisnow.ski import SHIPPED_SKIS, Ski, get_ski

__all__ = ["FleetSki", "resolve_fleet", "resolve_ski"]

_BENCH_SUFFIXES = (".csv", ".parquet")


@dataclass(frozen=True, kw_only=True)
class FleetSki:
    """One ski of a fleet.

    Attributes
    ----------
    label
        How the user named it (a shipped name, or the file name).
    ski
        The beam description (EI(x), z0(x), width, kick zone).
    origin
        ``'shipped'``, ``'ski file'`` or ``'bench file (identified)'``.
    network
        The shipped camber network's name when one exists for this ski (the paper's
        network route), else ``None`` (the beam route is used).
    warnings
        What the identification of a bench file said about its result (not at the noise, the
        cause, stretches the bench does not determine); empty otherwise.
    """

    label: str
    ski: Ski
    origin: str
    network: str | None = None
    warnings: tuple[str, ...] = ()


def resolve_ski(spec: str | Ski | FleetSki) -> FleetSki:
    """Turn a shipped name, a ski file or a bench file into a :class:`FleetSki`.

    A bench file (``.csv``/``.parquet`` camber-bench table of one ski) enters through the
    identification of its EI(x) and z0(x) from the whole bench sequence
    (:func:`skisnow.identify.identify_ski`; about a minute on a 2-core machine).

    Raises
    ------
    InputError
        Unknown name, unreadable or invalid file (the message names the file).
    """
    if isinstance(spec, FleetSki):
        return spec
    if isinstance(spec, Ski):
        from skisnow.pipeline import shipped_twin

        return FleetSki(label=spec.name, ski=spec, origin="ski object", network=shipped_twin(spec))
    if spec in SHIPPED_SKIS:
        return FleetSki(label=spec, ski=get_ski(spec), origin="shipped", network=spec)
    path = Path(spec)
    if not path.exists():
        raise InputError(
            f"{spec}: neither a shipped ski ({', '.join(SHIPPED_SKIS)}) nor an existing file"
        )
    if path.suffix.lower() in _BENCH_SUFFIXES:
        from skisnow.bench import read_bench
        from skisnow.identify import identify_ski

        bench = read_bench(path)
        if len(bench.skis) != 1:
            raise InputError(
                f"{path}: the bench holds {len(bench.skis)} skis ({', '.join(bench.skis)}); give "
                "one bench file per ski of the fleet"
            )
        # EI(x) and z0(x) identified from the whole bench sequence (skisnow.identify.identify_ski)
        result = identify_ski(bench, source=str(path))
        return FleetSki(label=path.name, ski=result.ski, origin="bench file (identified)",
                        warnings=result.warnings)  # fmt: skip
    ski = get_ski(str(path))
    # a file holding a shipped ski's content (whatever its name) may use that ski's network
    from skisnow.pipeline import shipped_twin

    return FleetSki(label=path.name, ski=ski, origin="ski file", network=shipped_twin(ski))


def resolve_fleet(
    specs: list[str | Ski | FleetSki],
) -> tuple[list[FleetSki], list[tuple[str, str]]]:
    """Resolve every ski of a fleet; a broken one is reported, not fatal.

    Returns
    -------
    (skis, failures)
        The skis that could be read, and ``(spec, message)`` for each that could not.
    """
    pairs: list[tuple[str, FleetSki]] = []
    failures: list[tuple[str, str]] = []
    for spec in specs:
        try:
            pairs.append((str(spec), resolve_ski(spec)))
        except (SkisnowError, OSError) as exc:
            failures.append((str(spec), str(exc)))
    labels = [fs.label for _, fs in pairs]
    # two files of the same name in different folders: label them by the path as given
    skis = [
        FleetSki(label=spec, ski=fs.ski, origin=fs.origin, network=fs.network)
        if labels.count(fs.label) > 1
        else fs
        for spec, fs in pairs
    ]
    return skis, failures
