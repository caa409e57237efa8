#!/usr/bin/env bash
# The Python package's tests, as CI runs them: a virtual environment in
# target/python-venv (made once, kept), the tools the tests use installed
# into it where missing, the package built from python/ with maturin and
# installed, then pytest over python/tests with the Khronos validation
# layer on. The CLI binary the tests compare with is target/release/shadelab
# (`cargo test --release` or `cargo build --release` leaves it there).
#
# Usage: ci/python-tests.sh [PYTEST ARGS...]
set -euo pipefail
cd "$(dirname "$0")/.."
venv=target/python-venv
if ! [ -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
py="$venv/bin/python"
# maturin's build backend runs the `maturin` of the PATH.
export PATH="$PWD/$venv/bin:$PATH"
# The tools of the tests: maturin builds the package; numpy is its one
# dependency; pytest-xdist, mypy, nbclient/ipykernel and tqdm are what the
# tests run it under.
tools=(maturin numpy pytest pytest-xdist mypy nbclient nbformat ipykernel tqdm)
if ! "$py" -c 'import maturin, numpy, pytest, xdist, mypy, nbclient, nbformat, ipykernel, tqdm' 2>/dev/null; then
    "$py" -m pip install --quiet --disable-pip-version-check "${tools[@]}"
fi
# Built in the workspace's target/, beside the library it links: what
# `cargo test --release` compiled is not compiled again.
"$py" -m pip install --quiet --disable-pip-version-check --no-build-isolation --force-reinstall --no-deps ./python
export SHADELAB_VALIDATION=1
export SHADELAB_BIN="$PWD/target/release/shadelab"
# From python/ (its pyproject holds the pytest settings); the package's
# sources are in python/package/, so the installed one is what is tested.
cd python
exec "../$venv/bin/pytest" -p no:cacheprovider "$@"
