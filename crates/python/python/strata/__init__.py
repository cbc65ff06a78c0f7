"""strata from Python: a Monte Carlo path tracer with a calibrated error estimate.

Render a scene file into numpy arrays, on the fastest renderer the machine has (a GPU through
wgpu, Mesa's lavapipe or the CPU reference), and measure what accuracy costs in time::

    import strata
    film = strata.render("scenes/cornell-box.toml", spp=64, size=(256, 256))
    film.image          # H x W x 3 float32, linear RGB
    film.error          # calibrated relative standard error of the image mean
    film.write("cornell-box.exr")

The functions do what the ``strata`` command's subcommands do, with the same options, checks
and messages: ``load`` (``strata info``), ``render``, ``study``, ``merge``, ``adapters``.
Renders run without the GIL; Ctrl-C raises ``KeyboardInterrupt`` once the batch in flight has
finished. The devices a process opens, and the kernels compiled on them, are kept for the
process, so a loop of renders of one scene compiles once.
"""

from __future__ import annotations

import csv
import os
import sys
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

from . import _strata
from ._strata import Film, Scene, SceneError

__all__ = [
    "Film",
    "Scene",
    "SceneError",
    "SceneWarning",
    "Study",
    "adapters",
    "load",
    "merge",
    "render",
    "study",
]

try:
    from importlib.metadata import version as _version

    __version__ = _version("stratapt")
except Exception:  # pragma: no cover - running from a source tree without metadata
    __version__ = "0+unknown"

PathLike = Union[str, "os.PathLike[str]"]
Size = Union[Tuple[int, int], str]


class SceneWarning(UserWarning):
    """A pbrt-v4 scene asks for something strata draws differently (``Scene.warnings`` lists
    each, at its file, line and column)."""


def load(path: PathLike, *, strict: bool = False) -> Scene:
    """Load a scene file: strata's TOML, or pbrt-v4 (``.pbrt``, ``.pbrt.gz``).

    A pbrt-v4 import that draws something differently from what the file asks issues one
    ``SceneWarning``; ``scene.warnings`` lists them all. ``strict=True`` refuses such a scene
    (``SceneError``), as ``strata render --strict`` does.

    Raises ``FileNotFoundError`` when there is no file at ``path`` and ``SceneError`` (a
    ``ValueError``) when the scene is wrong, with the command's message (file, line, column).
    """
    scene = _strata.load(os.fspath(path), strict=strict)
    found = scene.warnings
    if found:
        more = f" (and {len(found) - 1} more: Scene.warnings)" if len(found) > 1 else ""
        warnings.warn(f"{found[0]}{more}", SceneWarning, stacklevel=2)
    return scene


def render(
    scene: Union[Scene, PathLike],
    *,
    spp: Optional[int] = None,
    size: Optional[Size] = None,
    sampler: Optional[str] = None,
    strategy: Optional[str] = None,
    max_depth: Optional[int] = None,
    seed: Optional[int] = None,
    device: str = "auto",
    adapter: Optional[str] = None,
    target_error: Optional[float] = None,
    target_error_metric: str = "image-mean",
    time_limit: Optional[float] = None,
    calibrate: bool = True,
    progress: bool = True,
) -> Film:
    """Render a scene (a ``Scene``, or a path to load) and return its ``Film``.

    Every option overrides the scene's own, as ``strata render``'s do:

    - ``spp``: samples per pixel (with ``target_error`` or ``time_limit``: the cap, default
      65536);
    - ``size``: ``(width, height)`` or ``"WxH"``; the vertical field of view is kept;
    - ``sampler``: ``independent``, ``stratified`` or ``sobol``;
    - ``strategy``: ``uniform``, ``cosine``, ``bsdf``, ``light`` or ``mis``;
    - ``max_depth``: most path vertices after the camera; ``seed``: of the sample sequences;
    - ``device``: ``auto`` (a hardware GPU, else lavapipe where it is measured faster than the
      CPU on this scene, else the CPU: the eight-lane renderer on scenes it covers, the
      reference on others; ``film.device_reason`` says why), ``gpu``, ``cpu`` (the reference)
      or ``cpu8`` (the eight-lane prototype); ``adapter``: a GPU adapter by (part of) its name;
    - ``target_error``: render until the calibrated relative standard error reaches this (e.g.
      0.01), of the ``target_error_metric`` (``image-mean`` or ``pixel-p95``);
    - ``time_limit``: seconds; stop before a batch would end past it;
    - ``calibrate=False`` skips the twin pixels that calibrate the error estimate of the
      stratified and Sobol samplers;
    - ``progress``: a progress bar on ``sys.stderr`` (a terminal or a notebook).

    The render runs without the GIL. Ctrl-C stops it once the batch in flight has finished and
    raises ``KeyboardInterrupt``.
    """
    if not isinstance(scene, Scene):
        scene = load(scene)
    if isinstance(size, str):
        size = _parse_size(size)
    meter = None
    if progress:
        (w, h) = size if size is not None else scene.size
        open_ended = target_error is not None or time_limit is not None
        cap = spp if spp is not None else (None if open_ended else scene.settings["spp"])
        total = None if open_ended or cap is None else w * h * cap
        meter = _Meter(f"{Path(str(scene.path)).name}", total)
    try:
        film = _strata.render(
            scene,
            spp=spp,
            size=size,
            sampler=sampler,
            strategy=strategy,
            max_depth=max_depth,
            seed=seed,
            device=device,
            adapter=adapter,
            target_error=target_error,
            target_error_metric=target_error_metric,
            time_limit=time_limit,
            calibrate=calibrate,
            progress=meter,
        )
    finally:
        if meter is not None:
            meter.close()
    if progress:
        _announce(film)
    return film


@dataclass
class Study:
    """What ``study`` measured: ``rows`` (one per render: sampler, strategy, spp, seed,
    seconds, time_source, mse, rmse, relmse, rel_rmse, predicted_mse, predicted_relmse;
    ``pandas.DataFrame(study.rows)`` takes them as they are) and the files it wrote in
    ``folder``: ``csv``, ``report`` (ranked, Markdown) and ``plots`` (error against time and
    against spp, SVG and PNG)."""

    folder: Path
    rows: List[Dict[str, Any]] = field(default_factory=list)
    csv: Path = Path()
    report: Path = Path()
    plots: Dict[str, Path] = field(default_factory=dict)


def study(
    scene: PathLike,
    *,
    out: Optional[PathLike] = None,
    samplers: Optional[Sequence[str]] = None,
    strategies: Optional[Sequence[str]] = None,
    max_spp: int = 64,
    budget: Optional[float] = None,
    seeds: int = 4,
    reference: Optional[PathLike] = None,
    reference_spp: Optional[int] = None,
    threshold: float = 1e-3,
    size: Optional[Size] = None,
    max_depth: Optional[int] = None,
    device: str = "auto",
    adapter: Optional[str] = None,
    strict: bool = False,
) -> Study:
    """Measure error against time for every sampler x strategy, as ``strata study`` does:
    renders at 1, 2, 4, ... up to ``max_spp`` spp with ``seeds`` seeds each, against
    ``reference`` (an RGB EXR of the film's size), else the scene's exact value, else a
    high-spp render cached in ``out`` (default ``study-SCENE-NAME``). ``budget``: seconds;
    stop adding spp levels past it. ``threshold``: the relMSE the report's "time to reach it"
    is measured at.

    Ctrl-C stops it; the files then hold what was measured, and ``KeyboardInterrupt`` is
    raised.
    """
    words = [os.fspath(scene), "--max-spp", str(max_spp), "--seeds", str(seeds)]
    words += ["--threshold", repr(float(threshold)), "--device", device]
    options = {
        "--out": out,
        "--samplers": ",".join(samplers) if samplers else None,
        "--strategies": ",".join(strategies) if strategies else None,
        "--budget": f"{budget}s" if budget is not None else None,
        "--reference": reference,
        "--reference-spp": reference_spp,
        "--size": _size_word(size) if size is not None else None,
        "--max-depth": max_depth,
        "--adapter": adapter,
    }
    for flag, value in options.items():
        if value is not None:
            words += [flag, os.fspath(value) if isinstance(value, os.PathLike) else str(value)]
    if strict:
        words.append("--strict")
    call = ", ".join([repr(os.fspath(scene))] + [f"{k}={v!r}" for k, v in _given(locals())])
    folder = Path(_strata.study(words, f"strata.study({call})"))
    table = folder / "study.csv"
    with open(table, newline="") as f:
        rows = [{k: _number(v) for k, v in row.items()} for row in csv.DictReader(f)]
    plots = {
        p.stem + p.suffix: p
        for p in sorted(folder.iterdir())
        if p.stem in ("error-vs-time", "error-vs-spp") and p.suffix in (".svg", ".png")
    }
    return Study(folder, rows, table, folder / "report.md", plots)


def merge(paths: Sequence[PathLike], *, allow_partial: bool = False) -> Film:
    """Sum render parts (EXRs written by ``strata render --part K/N`` anywhere, in any order)
    into the whole render, exactly, as ``strata merge`` does. Missing samples are an error
    unless ``allow_partial``."""
    return _strata.merge([os.fspath(p) for p in paths], allow_partial=allow_partial)


def adapters() -> List[Dict[str, Any]]:
    """The GPU adapters wgpu finds, best first (the one ``device="gpu"`` takes): name,
    backend, type, driver, description, storage_buffers, max_storage_buffer_mib, timestamps."""
    return _strata.adapters()


# ---------------------------------------------------------------------------------------------
# Helpers
# ---------------------------------------------------------------------------------------------


def _parse_size(word: str) -> Tuple[int, int]:
    """``"512x256"`` as ``(512, 256)``; anything else is left for the renderer to refuse."""
    for sep in ("x", "X", "\u00d7"):
        if sep in word:
            w, h = word.split(sep, 1)
            try:
                return (int(w), int(h))
            except ValueError:
                break
    raise ValueError(f"size: expected WIDTHxHEIGHT, e.g. 512x512, got {word!r}")


def _size_word(size: Size) -> str:
    if isinstance(size, str):
        return size
    return f"{size[0]}x{size[1]}"


def _given(arguments: Dict[str, Any]) -> List[Tuple[str, Any]]:
    """A study's keyword arguments that differ from their defaults, for its report."""
    defaults = study.__kwdefaults__ or {}
    return [(k, v) for k, v in arguments.items() if k in defaults and v != defaults[k]]


def _number(text: str) -> Any:
    """A CSV cell as an int, else a float, else the text."""
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


_announced = set()


def _announce(film: Film) -> None:
    """``device: WHAT (WHY)`` on stderr, the first time a device is used in this process."""
    line = f"device: {film.device}"
    if film.device_reason:
        line += f" ({film.device_reason})"
    if line not in _announced:
        _announced.add(line)
        print(line, file=sys.stderr)


class _Meter:
    """A text progress bar on ``sys.stderr``, redrawn in place with a carriage return (which
    terminals and notebooks both honour); called with the samples done so far."""

    WIDTH = 30

    def __init__(self, label: str, total: Optional[int]) -> None:
        self.label = label
        self.total = total
        self.start = time.monotonic()
        self.drawn = False

    def __call__(self, done: int) -> None:
        elapsed = max(time.monotonic() - self.start, 1e-9)
        rate = done / elapsed
        if self.total:
            part = min(done / self.total, 1.0)
            filled = int(part * self.WIDTH)
            bar = "#" * filled + "." * (self.WIDTH - filled)
            eta = (self.total - done) / rate if rate > 0 else float("inf")
            text = (
                f"\r{self.label} [{bar}] {100 * part:3.0f}% {_count(done)}/{_count(self.total)} "
                f"samples, {_count(rate)}/s, eta {_seconds(eta)}"
            )
        else:
            text = f"\r{self.label} {_count(done)} samples, {_count(rate)}/s, {_seconds(elapsed)}"
        sys.stderr.write(text)
        sys.stderr.flush()
        self.drawn = True

    def close(self) -> None:
        if self.drawn:
            sys.stderr.write("\n")
            sys.stderr.flush()


def _count(n: float) -> str:
    for scale, unit in ((1e9, "G"), (1e6, "M"), (1e3, "k")):
        if n >= scale:
            return f"{n / scale:.1f}{unit}"
    return f"{n:.0f}"


def _seconds(t: float) -> str:
    if t == float("inf"):
        return "?"
    if t < 60:
        return f"{t:.0f} s"
    return f"{t // 60:.0f} min {t % 60:02.0f} s"
