#!/usr/bin/env bash
# The linear and small-model tables of docs/performance.md, run from the repository root:
#
#   scripts/perf_small.sh [OUT_DIR] [PART...]
#
# OUT_DIR defaults to out/perf-small; PART is any of
#   beam       the linear multi-span beam (`railfem bench`) at 1e4, 1e5, 1e6 DOF with the
#              consistent and the lumped mass: build, set-up, factorization, time per step
#   floor      the same beam against its memory-bandwidth floor (`bench --case floor`)
#   curve      the paper's curve case (Fig. 6, 20 205 steps) with each tangential law
#   sprung     a sprung mass on the beam with the direct, low-rank and partitioned solvers
#   threshold  dense against sparse factorization by size (`railfem-measure threshold`)
# (default: all). Every command runs under /usr/bin/time -v with the load average before
# and after written beside it. BIN=path overrides the binary (default
# target/release/railfem, built here when missing), MEASURE=path the project's measurement
# binary (default target/release/railfem-measure, likewise).
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-out/perf-small}
shift || true
PARTS=${*:-beam floor curve sprung threshold}
BIN=${BIN:-target/release/railfem}
[ -x "$BIN" ] || cargo build --release -p railfem
MEASURE=${MEASURE:-target/release/railfem-measure}
case " $PARTS " in *" threshold "*) [ -x "$MEASURE" ] || cargo build --release -p railfem-measure ;; esac
mkdir -p "$OUT"

run() { # run NAME COMMAND...: log the load, the command, its output and /usr/bin/time -v
  local name=$1; shift
  { echo "load before: $(cat /proc/loadavg)"; echo "command: $*"; } > "$OUT/$name.log"
  /usr/bin/time -v "$@" >> "$OUT/$name.log" 2>&1
  echo "load after: $(cat /proc/loadavg)" >> "$OUT/$name.log"
  grep -E "Elapsed|User time|Maximum resident|load (before|after)" "$OUT/$name.log" || true
}

for part in $PARTS; do
  case $part in
    beam)
      for mass in consistent lumped; do
        run "beam-$mass" "$BIN" bench --mass "$mass" --sizes 1e4,1e5,1e6 --steps 20 --out "$OUT/beam-$mass"
        cat "$OUT/beam-$mass/bench.md"
      done ;;
    floor)
      for mass in consistent lumped; do
        run "floor-$mass" "$BIN" bench --case floor --mass "$mass" --sizes 1e5,1e6 --steps 20 --out "$OUT/floor-$mass"
      done ;;
    curve)
      for law in coulomb kalker_linear polach; do
        run "curve-$law" "$BIN" curve --quiet --tangential "$law" --out "$OUT/curve-$law"
      done ;;
    sprung)
      run sprung "$BIN" bench --case sprung --sizes 1e3,1e4,1e5 --steps 40 --out "$OUT/sprung" ;;
    threshold)
      run threshold "$MEASURE" threshold --out "$OUT/threshold" ;;
    *) echo "perf_small.sh: unknown part '$part' (beam, floor, curve, sprung, threshold)" >&2; exit 2 ;;
  esac
done
