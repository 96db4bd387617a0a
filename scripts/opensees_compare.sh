#!/usr/bin/env bash
# Side-by-side run of railfem and OpenSeesPy on the linear moving-load multi-span beam of
# `railfem bench` (see docs/performance.md, "Against OpenSees").
#
# Creates a venv in target/opensees-venv with openseespy and numpy (pip, PyPI), builds
# railfem (release), exports each size with `railfem bench --export` (railfem's own timing
# and answer, run twice: pinned to one core with taskset, and unpinned), then reruns every
# size in OpenSees and writes out/opensees/<size>/opensees.json and a summary table.
#
# Usage: scripts/opensees_compare.sh [SIZES] [STEPS] [SOLVERS]
#   SIZES   comma-separated DOF counts (default 1e4,1e5)
#   STEPS   steps per run (default 200: the force crosses the first span's midspan)
#   SOLVERS OpenSees systems to try (default UmfPack,BandSPD,BandGeneral,ProfileSPD,SparseSYM)
set -euo pipefail
cd "$(dirname "$0")/.."
SIZES=${1:-1e4,1e5}
STEPS=${2:-200}
SOLVERS=${3:-UmfPack,BandSPD,BandGeneral,ProfileSPD,SparseSYM}
OUT=out/opensees
VENV=target/opensees-venv
if [ ! -x "$VENV/bin/python" ]; then
  python3 -m venv "$VENV"
fi
"$VENV/bin/python" -c "import openseespy, numpy" 2>/dev/null || "$VENV/bin/pip" install -q openseespy numpy
# The openseespylinux wheel ships libblas/liblapack/libgfortran beside opensees.so but its
# extension has no rpath to them; without this the import fails with "libblas.so.3: cannot
# open shared object file" on machines without a system BLAS.
OSLIB=$("$VENV/bin/python" -c "import importlib.util, os; print(os.path.join(os.path.dirname(importlib.util.find_spec('openseespylinux').origin), 'lib'))")
export LD_LIBRARY_PATH="$OSLIB${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
cargo build --release -p railfem
BIN=target/release/railfem
echo "load average at start: $(cat /proc/loadavg)"
IFS=',' read -ra LIST <<< "$SIZES"
for s in "${LIST[@]}"; do
  n=$(python3 -c "print(round(float('$s')))")
  # railfem unpinned (its default), then pinned to one core; the unpinned export is the one
  # OpenSees reruns (both write the same model and loads; only the timing differs).
  $BIN bench --export "$OUT" --sizes "$n" --steps "$STEPS" > /dev/null
  cp "$OUT/dof$n/timing.json" "$OUT/dof$n/timing-default.json"
  taskset -c 0 $BIN bench --export "$OUT" --sizes "$n" --steps "$STEPS"
  mv "$OUT/dof$n/timing.json" "$OUT/dof$n/timing-taskset.json"
  cp "$OUT/dof$n/timing-default.json" "$OUT/dof$n/timing.json"
  echo "railfem default: $(tr -d '\n ' < "$OUT/dof$n/timing-default.json")"
  echo "railfem taskset -c 0: $(tr -d '\n ' < "$OUT/dof$n/timing-taskset.json")"
  taskset -c 0 "$VENV/bin/python" scripts/opensees_compare.py "$OUT/dof$n" \
    --solvers "$SOLVERS" --json "$OUT/dof$n/opensees.json"
done
echo "load average at end: $(cat /proc/loadavg)"
