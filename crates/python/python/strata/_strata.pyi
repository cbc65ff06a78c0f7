"""Type stubs of strata's extension module (wrapped by the ``strata`` package)."""

import os
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Tuple

import numpy as np
import numpy.typing as npt

class SceneError(ValueError):
    """A scene file strata cannot use: the message names the file, line and column."""

class Scene:
    """A loaded scene: strata's TOML or a pbrt-v4 file, validated, with its BVH built."""

    @property
    def path(self) -> Path: ...
    @property
    def size(self) -> Tuple[int, int]:
        """Film (width, height) in pixels."""
    @property
    def settings(self) -> Dict[str, Any]:
        """spp, max_depth, sampler, strategy, seed, calibrate."""
    @property
    def effects(self) -> str:
        """What the scene calls for, in the words of ``strata info``."""
    @property
    def counts(self) -> Dict[str, int]:
        """primitives, points, materials, lights, textures, texture_bytes."""
    @property
    def warnings(self) -> List[str]:
        """A pbrt-v4 import's warnings, ``file:line:column: message`` each."""

class Film:
    """A render's estimate: per pixel the mean of its samples and the calibrated variance of
    that mean. ``np.asarray(film)`` is ``film.image``."""

    @property
    def image(self) -> npt.NDArray[np.float32]:
        """H x W x 3, linear RGB (the EXR's R, G, B)."""
    @property
    def variance(self) -> npt.NDArray[np.float32]:
        """H x W x 3: the calibrated variance of each pixel's mean (the EXR's var.*)."""
    @property
    def error(self) -> float:
        """The calibrated relative standard error of the image mean."""
    @property
    def error_p95(self) -> float:
        """The 95th-percentile pixel's relative standard error."""
    @property
    def pixel_error(self) -> npt.NDArray[np.float64]:
        """H x W: each pixel's relative standard error."""
    @property
    def mean(self) -> Tuple[float, float, float]: ...
    @property
    def mean_error(self) -> Tuple[float, float, float]: ...
    @property
    def spp(self) -> int: ...
    @property
    def size(self) -> Tuple[int, int]: ...
    @property
    def seconds(self) -> float: ...
    @property
    def device(self) -> str: ...
    @property
    def device_reason(self) -> Optional[str]: ...
    @property
    def stopped(self) -> str:
        """``spp``, ``target-error``, ``time-limit`` or ``merged``."""
    @property
    def settings(self) -> Dict[str, Any]: ...
    @property
    def stats(self) -> Dict[str, Any]:
        """samples, rays, non_finite, dispatches, compile_seconds, first_dispatch_seconds,
        gpu_seconds."""
    def write(self, path: str | os.PathLike[str]) -> None:
        """Write ``.exr`` (linear RGB + variance) or ``.png`` (sRGB), atomically."""
    def __array__(self, dtype: Any = None, copy: Optional[bool] = None) -> npt.NDArray[Any]: ...

def load(path: str, *, strict: bool = False) -> Scene: ...
def render(
    scene: Scene,
    *,
    spp: Optional[int] = None,
    size: Optional[Tuple[int, int]] = None,
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
    progress: Optional[Callable[[int], None]] = None,
) -> Film: ...
def study(words: List[str], command: str) -> Path: ...
def merge(paths: List[str], *, allow_partial: bool = False) -> Film: ...
def adapters() -> List[Dict[str, Any]]: ...
