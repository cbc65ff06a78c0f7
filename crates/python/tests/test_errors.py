"""Bad input raises the exception a Python user expects, with the message the `strata` command
prints (file, line, column); never a crash of the interpreter."""

import re

import pytest

import strata
from conftest import SCENES, run_cli

SCENE = SCENES / "cornell-box.toml"


def command_error(*args: str) -> str:
    """The `error: …` the command prints for ARGS, without the prefix."""
    done = run_cli(*args, check=False)
    assert done.returncode != 0
    return done.stderr.strip().splitlines()[-1].removeprefix("error: ")


def test_a_missing_scene_file(tmp_path):
    missing = tmp_path / "nowhere.toml"
    with pytest.raises(FileNotFoundError) as raised:
        strata.load(missing)
    assert str(raised.value) == command_error("info", str(missing))
    with pytest.raises(FileNotFoundError):
        strata.render(missing, progress=False)


def test_a_wrong_scene_names_file_line_and_column(tmp_path):
    bad = tmp_path / "bad.toml"
    text = SCENE.read_text().replace('type = "diffuse"', 'type = "difuse"', 1)
    assert text != SCENE.read_text()
    bad.write_text(text)
    with pytest.raises(strata.SceneError) as raised:
        strata.load(bad)
    message = str(raised.value)
    assert isinstance(raised.value, ValueError)
    assert message == command_error("info", str(bad))
    line = next(i for i, l in enumerate(text.splitlines(), 1) if '"difuse"' in l)
    assert f"bad.toml:{line}:" in message, message


def test_a_pbrt_scene_loads_with_its_warnings(tmp_path):
    scene_file = tmp_path / "lamp.pbrt"
    scene_file.write_text(
        """LookAt 0 0 0  0 0 1  0 1 0
Camera "perspective" "float fov" 60
Film "rgb" "integer xresolution" 24 "integer yresolution" 12
Option "bool disablepixeljitter" true
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [1 0.5 0.25]
  Translate 0 0 4
  Shape "sphere" "float radius" 0.5
AttributeEnd
"""
    )
    with pytest.warns(strata.SceneWarning):
        scene = strata.load(scene_file)
    option = [w for w in scene.warnings if "Option" in w]
    assert len(option) == 1, scene.warnings
    assert re.match(rf"{re.escape(str(scene_file))}:4:\d+: ", option[0]), option
    assert scene.size == (24, 12)
    with pytest.raises(strata.SceneError, match="strict"):
        strata.load(scene_file, strict=True)
    film = strata.render(scene, device="cpu", spp=4, progress=False)
    assert film.mean[0] > film.mean[1] > film.mean[2] > 0


@pytest.mark.parametrize(
    "option, value, words",
    [
        ("spp", 0, "spp: 0 is not in 1"),
        ("max_depth", 5000, "max_depth"),
        ("sampler", "halton", "expected one of independent, stratified, sobol"),
        ("strategy", "path", "expected one of"),
        ("size", (0, 10), "expected WIDTHxHEIGHT"),
        ("size", "big", "expected WIDTHxHEIGHT"),
        ("device", "tpu", "expected auto, gpu, cpu or cpu8"),
        ("target_error", 2.0, "between 0 and 1"),
        ("time_limit", -1.0, "positive"),
    ],
)
def test_a_wrong_option_is_a_value_error(option, value, words):
    with pytest.raises(ValueError, match=words):
        strata.render(SCENE, progress=False, **{option: value})


def test_writing_where_it_cannot(tmp_path):
    film = strata.render(SCENE, device="cpu", spp=1, size=(8, 8), progress=False)
    with pytest.raises(ValueError, match="must end in .exr or .png"):
        film.write(tmp_path / "image.jpg")
    with pytest.raises(FileNotFoundError, match="does not exist"):
        film.write(tmp_path / "no" / "such" / "folder.exr")
    assert list(tmp_path.iterdir()) == []


def test_a_study_with_a_wrong_option():
    with pytest.raises(ValueError, match="max-spp"):
        strata.study(SCENE, max_spp=0)
    with pytest.raises(FileNotFoundError):
        strata.study(SCENES / "nowhere.toml")
