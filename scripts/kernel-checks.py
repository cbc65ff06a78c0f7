#!/usr/bin/env python3
"""What each of wgpu's runtime checks costs the GPU kernel, in alternating runs.

Renders each scene with each set of `--kernel-checks` in turn, ROUNDS times over (so that a
slow spell of a shared machine falls on every variant alike), reads the "N s of GPU time" of
each render, and prints per scene the median seconds and the median over rounds of each
variant's speed relative to the fully checked kernel (`all`) of the same round.

    python3 scripts/kernel-checks.py [--rounds 5] [SCENE:SPP ...]

Default scenes: the Cornell box at 64 spp, Veach's scene and the mesh scene at 256 spp, at
their own sizes. Needs a release build (`cargo build --release`).
"""
import argparse
import re
import statistics
import subprocess
import sys
import tempfile

VARIANTS = [
    ("all", "all"),
    ("audited (bounds)", "audited"),
    ("loops off", "bounds,int-division"),
    ("int-division off (default)", "bounds,loops"),
    ("bounds off", "loops,int-division"),
    ("none", "none"),
]
DEFAULT_SCENES = ["scenes/cornell-box.toml:64", "scenes/veach-mis.toml:256", "scenes/mesh.toml:256"]
GPU_TIME = re.compile(r"([0-9.]+) s of GPU time")


def gpu_seconds(scene, spp, checks, output):
    """One render's GPU time, and its image mean line (every variant must give the same)."""
    run = subprocess.run(
        ["target/release/strata", "render", scene, "--device", "gpu", "--spp", str(spp),
         "--kernel-checks", checks, "-o", output],
        capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"{scene} --kernel-checks {checks} failed:\n{run.stderr}")
    seconds = GPU_TIME.search(run.stderr)
    if seconds is None:
        sys.exit(f"{scene}: no GPU time in the render's output (an adapter without timestamp "
                 f"queries?):\n{run.stderr}")
    mean = next(l for l in run.stderr.splitlines() if l.startswith("mean:"))
    return float(seconds.group(1)), mean


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("scenes", nargs="*", default=DEFAULT_SCENES, help="SCENE:SPP")
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        for item in args.scenes:
            scene, spp = item.rsplit(":", 1)
            seconds = {name: [] for name, _ in VARIANTS}
            means = set()
            for _ in range(args.rounds):
                for name, checks in VARIANTS:
                    t, mean = gpu_seconds(scene, int(spp), checks, f"{tmp}/out.exr")
                    seconds[name].append(t)
                    means.add(mean)
            print(f"{scene}, {spp} spp, {args.rounds} alternating rounds "
                  f"({'one image mean' if len(means) == 1 else 'IMAGE MEANS DIFFER: ' + str(means)})")
            print(f"  {'kernel checks':<18} {'median s':>9} {'min–max s':>13} {'speed vs all':>13}")
            for name, _ in VARIANTS:
                ratios = [a / b for a, b in zip(seconds["all"], seconds[name])]
                ts = seconds[name]
                print(f"  {name:<18} {statistics.median(ts):9.2f} "
                      f"{min(ts):6.2f}–{max(ts):<6.2f} {statistics.median(ratios):12.3f}×")
            sys.stdout.flush()


if __name__ == "__main__":
    main()
