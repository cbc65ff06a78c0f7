#!/usr/bin/env bash
# Render every bundled scene small, on the CPU reference and on the GPU (specialized and generic
# kernels), and print one SHA-256 per EXR. A refactor that claims to change no image must leave
# this list byte for byte the same: run it before and after and `diff` the two lists.
#
#   scripts/image-hashes.sh [STRATA-BINARY] > hashes.txt
set -euo pipefail
cd "$(dirname "$0")/.."
strata=${1:-target/release/strata}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for scene in scenes/*.toml scenes/hard/*.toml scenes/mitsuba/*.toml; do
    for run in "cpu specialized" "gpu specialized" "gpu generic"; do
        set -- $run
        name=$(echo "$scene-$1-$2" | tr '/' '_')
        "$strata" render "$scene" --device "$1" --kernel "$2" --size 24x16 --spp 16 \
            -o "$out/$name.exr" > "$out/$name.log" 2>&1 || { echo "FAILED $scene $1 $2"; cat "$out/$name.log"; continue; }
        echo "$(sha256sum < "$out/$name.exr" | cut -c1-16)  $scene $1 $2"
    done
done
