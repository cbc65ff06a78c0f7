#!/usr/bin/env bash
# What the sample split and the kernel checks do on the GPU this machine has, in alternating
# runs: one short script to run as is on a machine with a hardware GPU (issue 28).
#
#   bash scripts/gpu-speed.sh [ROUNDS [SCENE:WxH:SPP ...]]   (default 5 rounds, the items below)
#
# For each scene it renders, ROUNDS times over and in turn, with the sample split off
# (--sample-split 1) and `auto`, and with the fully checked kernel (--kernel-checks all), the
# default and the audited one, and prints each render's "s of GPU time" and its `gpu:` line
# once. It also prints the adapter, and the GPU's name and driver if nvidia-smi is there.
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-5}
shift || true
items=("$@")
[ ${#items[@]} -gt 0 ] || items=(cornell-box:256x256:256 veach-mis:256x192:256 mesh:256x256:256 cornell-box:1024x1024:64)
strata=target/release/strata
[ -x "$strata" ] || cargo build --release
"$strata" adapters || true
command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version --format=csv || true
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for item in "${items[@]}"; do
    IFS=: read -r scene size spp <<<"$item"
    echo "== $scene $size $spp spp"
    for variant in "--sample-split 1" "--sample-split auto" "--kernel-checks all" "--kernel-checks default" "--kernel-checks audited"; do
        # shellcheck disable=SC2086
        "$strata" render "scenes/$scene.toml" --device gpu --size "$size" --spp "$spp" $variant \
            -o "$out/warm.exr" 2>&1 | { grep '^gpu:' || echo 'gpu: (no line)'; } | sed "s/^/   [$variant] /"
    done
    for r in $(seq "$rounds"); do
        line="round $r:"
        for variant in "--sample-split 1" "--sample-split auto" "--kernel-checks all" "--kernel-checks default" "--kernel-checks audited"; do
            # shellcheck disable=SC2086
            t=$("$strata" render "scenes/$scene.toml" --device gpu --size "$size" --spp "$spp" \
                $variant -o "$out/r.exr" 2>&1 | { grep -o '[0-9.]* s of GPU time' || echo '? s'; } | cut -d' ' -f1)
            line="$line  [$variant] $t"
        done
        echo "   $line"
    done
done
