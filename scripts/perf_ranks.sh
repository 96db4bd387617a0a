#!/usr/bin/env bash
# One train–bridge model shared by 1 and 2 MPI ranks, as docs/scale-out.md reports it, run
# from the repository root:
#
#   scripts/perf_ranks.sh [OUT_DIR] [LIMIT_MIB]
#
# Builds the MPI binary (Open MPI and libclang must be installed: scripts/mpi.sh does it),
# then runs `railfem bench --case train-bridge --sizes 1e5,1043430 --cars 12 --steps 20`
# under `mpirun -n 1` and `-n 2` back to back (time per step, bytes and time in the
# collectives, memory per rank: the bench prints one line per rank), and, with LIMIT_MIB
# (e.g. 2100), the 1M-DOF case once more on 1 and on 2 ranks with each rank's data segment
# limited to LIMIT_MIB (`prlimit --data`): the model that does not fit one rank but runs on
# two. Each log holds the load average before and after. OUT_DIR defaults to out/perf-ranks.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-out/perf-ranks}
LIMIT=${2:-}
mkdir -p "$OUT"
cargo build --release -p railfem --features mpi -q
BIN=target/release/railfem
export OMPI_MCA_mpi_yield_when_idle=1
flags=(--oversubscribe)
if [ "$(id -u)" -eq 0 ]; then flags+=(--allow-run-as-root); fi

for n in 1 2; do
  log=$OUT/ranks-$n.log
  echo "load before: $(cat /proc/loadavg)" > "$log"
  mpirun -n "$n" "${flags[@]}" "$BIN" bench --case train-bridge --sizes 1e5,1043430 --cars 12 \
    --steps 20 --out "$OUT/ranks-$n" >> "$log" 2>&1
  echo "load after: $(cat /proc/loadavg)" >> "$log"
  grep -E "DOF \(|memory of rank|bytes|load (before|after)" "$log" || true
done

if [ -n "$LIMIT" ]; then
  for n in 1 2; do
    log=$OUT/limit-$n.log
    set +e
    mpirun -n "$n" "${flags[@]}" prlimit --data=$((LIMIT * 1024 * 1024)) "$BIN" bench \
      --case train-bridge --sizes 1043430 --cars 12 --steps 20 --out "$OUT/limit-$n" > "$log" 2>&1
    echo "exit code $? with $n rank(s) limited to $LIMIT MiB each" | tee -a "$log"
    set -e
  done
fi
