#!/bin/bash
# Interleaved timing of two railfem binaries (e.g. the commit before a change and after it),
# run from the repository root:
#   scripts/compare_timing.sh OLD_BINARY NEW_BINARY [ROUNDS] [OUT_DIR]
# Each round runs, for OLD then NEW, the 1e5-DOF lumped linear `bench` (400 steps) and
# `curve --quick`, and appends one line per binary to OUT_DIR/results.txt: the bench's own
# time per step (wall), and the process CPU time (perf's task-clock) of the bench and of
# the curve case. Needs `perf` and `bc`. Medians per column are printed at the end.
set -eu
OLD=$1; NEW=$2; ROUNDS=${3:-7}; OUT=${4:-out/compare-timing}
mkdir -p "$OUT"; : > "$OUT/results.txt"
for i in $(seq 1 "$ROUNDS"); do
  for tag in old new; do
    if [ "$tag" = old ]; then BIN=$OLD; else BIN=$NEW; fi
    bcpu=$(perf stat -e task-clock -x, "$BIN" bench --sizes 1e5 --mass lumped --steps 400 \
      --out "$OUT/b-$tag-$i" 2>&1 >/dev/null | grep task-clock | cut -d, -f1)
    step=$(tail -1 "$OUT/b-$tag-$i/bench.csv" | cut -d, -f10)
    s=$(date +%s.%N)
    ccpu=$(perf stat -e task-clock -x, "$BIN" curve --quick --out "$OUT/c-$tag-$i" 2>&1 >/dev/null \
      | grep task-clock | cut -d, -f1)
    e=$(date +%s.%N)
    echo "$tag $i bench_step_s=$step bench_cpu_ms=$bcpu curve_cpu_ms=$ccpu curve_wall_s=$(echo "$e - $s" | bc)" \
      >> "$OUT/results.txt"
  done
done
python3 - "$OUT/results.txt" <<'PY'
import sys, statistics as st
d = {}
for line in open(sys.argv[1]):
    tag, _, *kv = line.split()
    for x in kv:
        k, v = x.split("=")
        d.setdefault((tag, k), []).append(float(v))
for k in ["bench_step_s", "bench_cpu_ms", "curve_cpu_ms", "curve_wall_s"]:
    o, n = st.median(d[("old", k)]), st.median(d[("new", k)])
    print(f"{k}: old median {o:.4g}, new median {n:.4g}, new/old {n / o:.3f}")
PY
