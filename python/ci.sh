#!/usr/bin/env bash
# The Python bindings' check (docs/python.md), called at the end of .ci/run: a fresh
# virtual environment, maturin, pytest and numpy from the package index, the package built
# from the repository with `pip install ./python` (as a user would), then pytest.
# The build shares the workspace's target directory, so the railfem library compiled by
# `cargo test --release --workspace` is reused and only PyO3 and the bindings compile.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(dirname "$here")"
python="${PYTHON:-python3}"
venv="$repo/target/python-venv"
start=$(date +%s)

export CARGO_TARGET_DIR="$repo/target"
# What the tests compare against: the command line, and the example plugin.
cargo build --release --bin railfem
cargo build --release -p railfem-plugin-hysteretic

rm -rf "$venv"
"$python" -m venv "$venv"
"$venv/bin/python" -m pip install --quiet --upgrade pip
"$venv/bin/python" -m pip install --quiet "maturin>=1.5,<2" pytest numpy mypy
"$venv/bin/python" -m pip install --quiet "$here"
echo "python/ci.sh: venv and build $(($(date +%s) - start)) s"
cd "$here/tests"
"$venv/bin/python" -m pytest -q "$here/tests"
echo "python/ci.sh: total $(($(date +%s) - start)) s"
