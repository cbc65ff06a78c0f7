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

# The workspace's tests (the Python bindings' crate has none in Rust: its tests are below).
cargo test --workspace "$@"

# The Python package, as a user installs it (`pip install .`), into a virtual environment under
# target/, then its tests (crates/python/tests), which compare it with the `strata` command
# that cargo test built. maturin builds it in the dev profile, which reuses cargo test's build.
venv=target/python-venv
if ! python3 -c 'import ensurepip, venv' 2>/dev/null; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        echo "test.sh: installing python3-venv" >&2
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3-venv >/dev/null
    else
        echo "test.sh: Python's venv module is missing: run 'sudo apt-get install python3-venv'" >&2
        exit 1
    fi
fi
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -m pip install -q --disable-pip-version-check \
    "maturin>=1.7,<2" numpy pytest OpenEXR matplotlib
PATH="$PWD/$venv/bin:$PATH" MATURIN_PEP517_ARGS="--profile dev" "$venv/bin/python" -m pip install -q \
    --disable-pip-version-check --no-build-isolation --force-reinstall --no-deps .
STRATA_BIN=target/debug/strata exec "$venv/bin/python" -m pytest -q -p no:cacheprovider \
    crates/python/tests
