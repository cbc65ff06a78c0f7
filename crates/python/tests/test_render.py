"""A render from Python is the render the `strata` command makes: the same pixels, bit for
bit, on the CPU reference and on lavapipe, the same error figure, the same merge."""

import re

import numpy as np
import pytest

import strata
from conftest import SCENES, read_exr, run_cli

SCENE = SCENES / "cornell-box.toml"
SETTINGS = dict(spp=8, size=(40, 30), sampler="sobol", strategy="mis", seed=3)
FLAGS = ["--spp", "8", "--size", "40x30", "--sampler", "sobol", "--strategy", "mis", "--seed", "3"]


@pytest.mark.parametrize("device", ["cpu", "gpu"])
def test_the_image_is_the_exr_the_command_writes(tmp_path, device):
    exr = tmp_path / "cli.exr"
    said = run_cli("render", str(SCENE), *FLAGS, "--device", device, "-o", str(exr)).stderr
    film = strata.render(SCENE, device=device, progress=False, **SETTINGS)
    rgb, var = read_exr(exr)
    assert film.image.shape == (30, 40, 3) and film.image.dtype == np.float32
    assert np.array_equal(film.image, rgb), "image differs from the EXR's R, G, B"
    assert np.array_equal(film.variance, var), "variance differs from the EXR's var.*"
    assert np.array_equal(np.asarray(film), rgb)
    assert np.asarray(film, dtype=np.float64).dtype == np.float64
    # The closing line's figures: "error: 0.123 % relative standard error of the image mean,
    # 4.56 % at the 95th-percentile pixel" and "mean: r g b (± …)".
    error = re.search(r"error: ([0-9.]+) % relative .*?, ([0-9.]+) % at the 95th", said)
    assert error, said
    assert f"{100 * film.error:.3f}" == error.group(1)
    assert f"{100 * film.error_p95:.2f}" == error.group(2)
    mean = re.search(r"mean: ([0-9.]+) ([0-9.]+) ([0-9.]+)", said)
    assert [f"{m:.5f}" for m in film.mean] == list(mean.groups())
    assert film.spp == 8 and film.stopped == "spp"
    assert film.settings["sampler"] == "sobol" and film.settings["seed"] == 3
    assert ("CPU" in film.device) == (device == "cpu")
    assert film.pixel_error.shape == (30, 40)
    assert np.percentile(film.pixel_error, 95) == pytest.approx(film.error_p95, rel=0.05)


def test_written_files_are_the_commands(tmp_path):
    film = strata.render(SCENE, device="cpu", progress=False, **SETTINGS)
    film.write(tmp_path / "py.exr")
    film.write(str(tmp_path / "py.png"))
    run_cli("render", str(SCENE), *FLAGS, "--device", "cpu",
            "-o", str(tmp_path / "cli.exr"), "-o", str(tmp_path / "cli.png"))
    for name in ("exr", "png"):
        assert (tmp_path / f"py.{name}").read_bytes() == (tmp_path / f"cli.{name}").read_bytes()
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "cli.exr", "cli.png", "py.exr", "py.png"
    ], "a temporary file was left behind"


def test_a_merge_of_parts_is_the_whole_render(tmp_path):
    parts = [tmp_path / f"part{k}.exr" for k in range(3)]
    for k, part in enumerate(parts):
        run_cli("render", str(SCENE), *FLAGS, "--device", "cpu", "--part", f"{k}/3",
                "-o", str(part))
    merged = strata.merge(parts)
    whole = strata.render(SCENE, device="cpu", progress=False, **SETTINGS)
    assert merged.stopped == "merged" and merged.spp == 8
    assert np.array_equal(merged.image, whole.image)
    with pytest.raises(ValueError, match="are in no part"):
        strata.merge(parts[:2])
    assert strata.merge(parts[:2], allow_partial=True).spp < 8


def test_a_scene_loaded_once_renders_with_any_settings():
    scene = strata.load(SCENE)
    assert scene.size == (512, 512) or scene.size[0] > 0
    assert scene.counts["primitives"] > 0 and scene.counts["lights"] >= 1
    assert "NEE" in scene.effects or "lights" in scene.effects
    a = strata.render(scene, device="cpu", progress=False, **SETTINGS)
    b = strata.render(SCENE, device="cpu", progress=False, **SETTINGS)
    assert np.array_equal(a.image, b.image)
    c = strata.render(scene, device="cpu", progress=False, size="20x15", spp=4)
    assert c.image.shape == (15, 20, 3) and c.spp == 4


def test_a_render_to_an_error_stops_there():
    film = strata.render(SCENE, device="cpu", progress=False, size=(24, 24),
                         target_error=0.02)
    assert film.stopped == "target-error" and film.error <= 0.02
    assert film.spp >= 64


def test_adapters_are_listed_best_first():
    found = strata.adapters()
    assert found, "no adapter: scripts/test.sh installs lavapipe"
    assert {"name", "backend", "type", "description"} <= set(found[0])
    assert any(a["type"] == "Cpu" for a in found)
