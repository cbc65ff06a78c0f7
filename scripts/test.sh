#!/usr/bin/env bash
# Run strata's whole test suite: unit, analytic and agreement tests, on a software Vulkan adapter.
# Installs lavapipe (Debian's mesa-vulkan-drivers) first when it is missing and we are root.
set -euo pipefail
cd "$(dirname "$0")/.."

if ! compgen -G "/usr/share/vulkan/icd.d/lvp_icd*.json" >/dev/null; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        echo "test.sh: installing lavapipe (mesa-vulkan-drivers)" >&2
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq mesa-vulkan-drivers >/dev/null
    else
        echo "test.sh: lavapipe is missing and I cannot install it:" \
             "run 'sudo apt-get install mesa-vulkan-drivers'" >&2
    fi
fi

exec cargo test --workspace "$@"
