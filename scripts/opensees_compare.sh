#!/usr/bin/env bash
# Side-by-side runs of railfem and OpenSeesPy (see docs/performance.md, "Honest peers").
#
# Creates a venv in target/opensees-venv with openseespy and numpy (pip, PyPI) and builds
# railfem (release). Then either
#
#   scripts/opensees_compare.sh [SIZES] [STEPS] [SOLVERS] [MASSES] [LOADS]
#     the linear moving-load multi-span beam of `railfem bench`: per mass matrix and size,
#     exports the model with `railfem-measure export --mass M` (railfem's own timing and
#     answer, run twice: unpinned and pinned to one core with taskset), reruns it in
#     OpenSees (pinned to one core) with every solver and both ways of applying the moving
#     load, and writes out/opensees/<mass>/dof<N>/opensees.json;
#       SIZES   comma-separated DOF counts (default 1e4,1e5)
#       STEPS   steps per run (default 200: the force crosses the first span's midspan)
#       SOLVERS OpenSees systems (default UmfPack,BandSPD,BandGeneral,ProfileSPD,SparseSYM)
#       MASSES  consistent, lumped or both (default consistent,lumped)
#       LOADS   pattern (one pattern rebuilt per step), path (one Path series per loaded
#               DOF) or both (default pattern,path)
# or
#   scripts/opensees_compare.sh pareto [SOLVERS] [LOADS]
#     the moving-force case of `railfem pareto` in OpenSees over the same grid
#     (out/opensees/pareto.csv), then `railfem-measure peer` on it
#     (out/pareto-peer: pareto-force.svg with both codes, pareto-peers.md).
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=out/opensees
VENV=target/opensees-venv
if [ ! -x "$VENV/bin/python" ]; then
  python3 -m venv "$VENV"
fi
"$VENV/bin/python" -c "import openseespylinux, numpy" 2>/dev/null || "$VENV/bin/pip" install -q openseespy numpy
# The openseespylinux wheel ships libblas/liblapack/libgfortran beside opensees.so but its
# extension has no rpath to them; without this the import fails with "libblas.so.3: cannot
# open shared object file" on machines without a system BLAS.
OSLIB=$("$VENV/bin/python" -c "import importlib.util, os; print(os.path.join(os.path.dirname(importlib.util.find_spec('openseespylinux').origin), 'lib'))")
export LD_LIBRARY_PATH="$OSLIB${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
cargo build --release -p railfem-measure
BIN=target/release/railfem-measure
echo "load average at start: $(cat /proc/loadavg)"

if [ "${1:-}" = pareto ]; then
  SOLVERS=${2:-BandSPD}
  LOADS=${3:-pattern,path}
  mkdir -p "$OUT"
  taskset -c 0 "$VENV/bin/python" scripts/opensees_compare.py --pareto "$OUT/pareto.csv" \
    --solvers "$SOLVERS" --loads "$LOADS"
  $BIN peer "$OUT/pareto.csv" --cases force --out out/pareto-peer
  echo "load average at end: $(cat /proc/loadavg)"
  exit 0
fi

SIZES=${1:-1e4,1e5}
STEPS=${2:-200}
SOLVERS=${3:-UmfPack,BandSPD,BandGeneral,ProfileSPD,SparseSYM}
MASSES=${4:-consistent,lumped}
LOADS=${5:-pattern,path}
IFS=',' read -ra MLIST <<< "$MASSES"
IFS=',' read -ra LIST <<< "$SIZES"
for m in "${MLIST[@]}"; do
  for s in "${LIST[@]}"; do
    n=$(python3 -c "print(round(float('$s')))")
    d="$OUT/$m/dof$n"
    # railfem unpinned (its default), then pinned to one core; the unpinned export is the
    # one OpenSees reruns (both write the same model and loads; only the timing differs).
    $BIN export "$OUT/$m" --mass "$m" --sizes "$n" --steps "$STEPS" > /dev/null
    cp "$d/timing.json" "$d/timing-default.json"
    taskset -c 0 $BIN export "$OUT/$m" --mass "$m" --sizes "$n" --steps "$STEPS"
    mv "$d/timing.json" "$d/timing-taskset.json"
    cp "$d/timing-default.json" "$d/timing.json"
    echo "railfem $m default: $(tr -d '\n ' < "$d/timing-default.json")"
    echo "railfem $m taskset -c 0: $(tr -d '\n ' < "$d/timing-taskset.json")"
    taskset -c 0 "$VENV/bin/python" scripts/opensees_compare.py "$d" \
      --solvers "$SOLVERS" --loads "$LOADS" --json "$d/opensees.json"
  done
done
echo "load average at end: $(cat /proc/loadavg)"
