#!/usr/bin/env python3
"""A loop of renders of one scene from Python against the same renders by the `strata` command:
how many times each compiles the GPU kernel, and the seconds per render (the film's, and the
whole call's or process's). Prints a Markdown table row per device.

    python scripts/python-loop.py [SCENE] [--renders N] [--cli-runs M] [--size WxH] [--spp N]

Run it with the virtual environment the package is installed in (scripts/test.sh makes
target/python-venv); the command is target/release/strata, else target/debug/strata.
"""

import argparse
import re
import statistics
import subprocess
import time
from pathlib import Path

import strata

REPO = Path(__file__).resolve().parents[1]


def command() -> Path:
    for profile in ("release", "debug"):
        path = REPO / "target" / profile / "strata"
        if path.is_file():
            return path
    raise SystemExit("build the strata command first (cargo build --release)")


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("scene", nargs="?", default=str(REPO / "scenes" / "cornell-box.toml"))
    parser.add_argument("--renders", type=int, default=100)
    parser.add_argument("--cli-runs", type=int, default=5)
    parser.add_argument("--size", default="64x64")
    parser.add_argument("--spp", type=int, default=4)
    parser.add_argument("--devices", default="gpu,cpu")
    args = parser.parse_args()
    w, h = (int(v) for v in args.size.split("x"))
    scene = strata.load(args.scene)
    print("| device | renders | kernel compiles | median film s | median call s | "
          "CLI: compiles | CLI median film s | CLI median process s |")
    print("|---|---|---|---|---|---|---|---|")
    for device in args.devices.split(","):
        films, calls = [], []
        for seed in range(args.renders):
            start = time.perf_counter()
            films.append(strata.render(scene, device=device, spp=args.spp, size=(w, h),
                                       seed=seed, progress=False))
            calls.append(time.perf_counter() - start)
        compiles = sum(f.stats.get("compile_seconds", 0) > 0 for f in films)
        cli_films, cli_calls, cli_compiles = [], [], 0
        for seed in range(args.cli_runs):
            start = time.perf_counter()
            said = subprocess.run(
                [str(command()), "render", args.scene, "--device", device, "--spp",
                 str(args.spp), "--size", args.size, "--seed", str(seed), "-o", "/tmp/loop.exr"],
                capture_output=True, text=True, check=True).stderr
            cli_calls.append(time.perf_counter() - start)
            cli_films.append(float(re.search(r" in ([0-9.]+) s:", said).group(1)))
            cli_compiles += "compiled in" in said
        print(f"| {films[0].device} | {args.renders} | {compiles} | "
              f"{statistics.median(f.seconds for f in films):.4f} | "
              f"{statistics.median(calls):.4f} | {cli_compiles} of {args.cli_runs} | "
              f"{statistics.median(cli_films):.4f} | {statistics.median(cli_calls):.3f} |")


if __name__ == "__main__":
    main()
