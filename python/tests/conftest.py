"""Shared helpers of the Python tests: where the repository and the `railfem` command are,
running the command, and reading its CSV files as text (to compare number by number)."""

import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
MODELS = REPO / "examples" / "models"


def _target_dir():
    return pathlib.Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))


def railfem_bin():
    """The `railfem` binary the comparisons run: $RAILFEM_BIN, else target/release/railfem."""
    p = pathlib.Path(os.environ.get("RAILFEM_BIN", _target_dir() / "release" / "railfem"))
    if not p.is_file():
        pytest.fail(f"{p}: build it first (cargo build --release), or set RAILFEM_BIN")
    return p


def plugin_lib():
    """The example plugin built by `cargo build --release -p railfem-plugin-hysteretic`."""
    return _target_dir() / "release" / "librailfem_plugin_hysteretic.so"


def cli(*args, cwd=None):
    """Runs `railfem ARGS`; returns the CompletedProcess (text)."""
    return subprocess.run(
        [str(railfem_bin()), *map(str, args)],
        capture_output=True,
        text=True,
        cwd=cwd,
    )


def read_csv_text(path):
    """(header, rows) of a CSV file, every field kept as its text."""
    lines = pathlib.Path(path).read_text().splitlines()
    header = lines[0].split(",")
    rows = [line.split(",") for line in lines[1:]]
    return header, rows


def cli_error_lines(proc):
    """The messages `railfem` printed after `error: ` on stderr, in order."""
    return [
        line[len("error: "):]
        for line in proc.stderr.splitlines()
        if line.startswith("error: ")
    ]


def bare(name):
    """A CSV column name without a unit suffix (`Q_fe [N]` -> `Q_fe`)."""
    return name.split(" [")[0]
