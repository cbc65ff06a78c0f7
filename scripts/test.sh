#!/usr/bin/env bash
# Run strata's whole test suite: unit, analytic and agreement tests, on a software Vulkan adapter.
# Installs lavapipe (Debian's mesa-vulkan-drivers) first when it is missing and we are root; on
# Debian 12 it takes Mesa 25 from bookworm-backports, whose lavapipe runs strata's kernel about
# 2x faster than the release's Mesa 22.3.
set -euo pipefail
cd "$(dirname "$0")/.."

install_lavapipe() {
    local codename="" target=()
    if [ -r /etc/os-release ]; then
        codename="$(. /etc/os-release && echo "${VERSION_CODENAME:-}")"
    fi
    if [ "$codename" = bookworm ]; then
        # Debian 12: add bookworm-backports (once) and install Mesa from it.
        if ! grep -rqs "bookworm-backports" /etc/apt/sources.list /etc/apt/sources.list.d/; then
            echo "deb http://deb.debian.org/debian bookworm-backports main" \
                >/etc/apt/sources.list.d/strata-bookworm-backports.list
        fi
        target=(-t bookworm-backports)
    fi
    echo "test.sh: installing lavapipe (mesa-vulkan-drivers${target:+ from ${target[1]}})" >&2
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${target[@]}" mesa-vulkan-drivers >/dev/null
}

if ! compgen -G "/usr/share/vulkan/icd.d/lvp_icd*.json" >/dev/null; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        install_lavapipe
    else
        echo "test.sh: lavapipe is missing and I cannot install it:" \
             "run 'sudo apt-get install mesa-vulkan-drivers' (on Debian 12:" \
             "'-t bookworm-backports', after adding that suite, for the 2x faster Mesa 25)" >&2
    fi
fi

exec cargo test --workspace "$@"
