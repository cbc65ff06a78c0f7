"""`strata.study` is `strata study`: its rows and plots, from Python."""

import strata
from conftest import SCENES

COLUMNS = ["sampler", "strategy", "spp", "seed", "seconds", "time_source", "mse", "rmse",
           "relmse", "rel_rmse", "predicted_mse", "predicted_relmse"]


def test_a_study_returns_its_rows_and_plots(tmp_path):
    done = strata.study(
        SCENES / "soft-shadow-area.toml", out=tmp_path / "study", samplers=["independent", "sobol"],
        strategies=["light"], max_spp=4, seeds=2, size=(16, 16), device="cpu",
        reference_spp=64,
    )
    assert len(done.rows) == 2 * 3 * 2  # samplers × spp levels (1, 2, 4) × seeds
    assert list(done.rows[0]) == COLUMNS
    assert {r["sampler"] for r in done.rows} == {"independent", "sobol"}
    assert all(isinstance(r["spp"], int) and isinstance(r["mse"], float) for r in done.rows)
    assert set(done.plots) == {"error-vs-time.svg", "error-vs-time.png", "error-vs-spp.svg",
                               "error-vs-spp.png"}
    assert all(p.stat().st_size > 0 for p in done.plots.values())
    report = done.report.read_text()
    assert "strata.study(" in report and "max_spp=4" in report


def test_a_study_shares_the_process_kernels(tmp_path):
    # No other test renders this scene on the GPU: the study compiles its kernel, and a render
    # after it finds the kernel compiled only if both ran on the process's one device.
    scene = SCENES / "soft-shadow-area.toml"
    done = strata.study(scene, out=tmp_path, samplers=["sobol"], strategies=["light"],
                        max_spp=2, seeds=1, size=(16, 16), device="gpu", reference_spp=16)
    after = strata.render(scene, device="gpu", size=(16, 16), spp=2, sampler="sobol",
                          strategy="light", progress=False)
    assert len(done.rows) == 2
    assert after.stats["compile_seconds"] == 0, "the study's device was not the render's"
