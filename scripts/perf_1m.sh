#!/usr/bin/env bash
# The paper-sized train–bridge case timed as docs/performance.md reports it, run from the
# repository root:
#
#   scripts/perf_1m.sh [OUT_DIR] [PART...]
#
# OUT_DIR defaults to out/perf-1m; PART is any of
#   step     20 steps of the 12-carriage train on 11 spans (112 542 equations) and on the
#            paper's 113 spans (1 043 052 equations): time per Newton iteration and per step
#            by phase, peak memory (~3 min, 2.5 GiB)
#   sizes    one carriage on 1, 11 and 108 spans (1e4, 1e5, 1e6 DOF): how an iteration
#            grows with the bridge; writes phases.svg (~2 min)
#   build    the model build alone at 3e5 and 1M DOF (`train-bridge --build-only`; below
#            ~1.2e5 DOF the mesh is already one element per fastener bay, so smaller
#            targets give the same 122 694-equation model)
#   crossing the whole crossing projected from a 5000-step entry segment and a 600-step
#            middle segment (scripts/crossing_projection.py; ~10 min + ~1 min)
# (default: step sizes build). Every command runs under /usr/bin/time -v; the load average
# before and after each is written beside it, because on a shared machine the wall times
# follow the load. BIN=path overrides the binary (default target/release/railfem, built
# here when missing).
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-out/perf-1m}
shift || true
PARTS=${*:-step sizes build}
BIN=${BIN:-target/release/railfem}
[ -x "$BIN" ] || cargo build --release -p railfem
mkdir -p "$OUT"

run() { # run NAME COMMAND...: log the load, the command, its output and /usr/bin/time -v
  local name=$1; shift
  { echo "load before: $(cat /proc/loadavg)"; echo "command: $*"; } > "$OUT/$name.log"
  /usr/bin/time -v "$@" >> "$OUT/$name.log" 2>&1
  echo "load after: $(cat /proc/loadavg)" >> "$OUT/$name.log"
  grep -E "DOF .*ms/iteration|per iteration \(ms\)|Maximum resident|load (before|after)" "$OUT/$name.log" || true
}

for part in $PARTS; do
  case $part in
    step)
      run step "$BIN" bench --case train-bridge --sizes 1e5,1043430 --cars 12 --steps 20 --out "$OUT/step" ;;
    sizes)
      run sizes "$BIN" bench --case train-bridge --sizes 1e4,1e5,1e6 --steps 20 --out "$OUT/sizes" ;;
    build)
      for n in 300000 1043430; do
        run "build-$n" "$BIN" train-bridge --dof "$n" --build-only --out "$OUT/build-$n"
      done ;;
    crossing)
      run entry "$BIN" bench --case train-bridge --sizes 1043430 --cars 12 --steps 5000 --out "$OUT/entry"
      run middle "$BIN" bench --case train-bridge --sizes 1043430 --cars 12 --steps 600 \
        --train-start 1000 --out "$OUT/middle"
      python3 scripts/crossing_projection.py "$OUT/entry/steps-1043052.csv" \
        "$OUT/middle/steps-1043052.csv" | tee "$OUT/crossing.md" ;;
    *) echo "perf_1m.sh: unknown part '$part' (step, sizes, build, crossing)" >&2; exit 2 ;;
  esac
done
