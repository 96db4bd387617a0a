#!/usr/bin/env bash
# `railfem study` over MPI (docs/study.md): install the system's Open MPI from Debian's
# packages (with clang/libclang for rsmpi's bindgen), build railfem with `--features mpi`,
# and check under mpirun that
#   - 1 rank gives the same study.csv bytes as the default (non-MPI) build,
#   - 2 ranks give the same bytes as 1 rank, and
#   - a case that panics on a worker rank is a failed row and the study ends (no hang),
#   - a rank that dies outright (abort, as a crash or a kill) ends the job with mpirun's
#     message naming the rank, never a hang; the checkpoint keeps the finished cases and the
#     same command then finishes the study with the serial run's table;
# that `railfem bridge-check` on 2 ranks writes the serial envelope.csv byte for byte (also
# after a stop and a resume), and that `railfem train-bridge` with the partitioned
# solver's blocks shared by 2 ranks
# writes the serial run's recorders (to 1e-12 relative), as does 1 rank, and that a SIGTERM
# to one of its ranks stops both at the same step (exit 130, rank 0's rows whole).
# Usage: scripts/mpi.sh [PLAN.toml]   (default: a 24-case cut of examples/studies)
# Timings of the whole 200-case plan: SCALE_OUT_BENCH=1 scripts/mpi.sh (docs/scale-out.md).
set -euo pipefail
cd "$(dirname "$0")/.."

sudo_if_needed() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }
if ! command -v mpirun >/dev/null || ! dpkg -s libopenmpi-dev >/dev/null 2>&1 \
    || ! dpkg -s libclang-dev >/dev/null 2>&1; then
    sudo_if_needed apt-get update -qq
    sudo_if_needed env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq \
        --no-install-recommends libopenmpi-dev openmpi-bin libclang-dev clang >/dev/null
fi

work=$(mktemp -d /tmp/railfem-mpi.XXXXXX)
trap 'rm -rf "$work"' EXIT
# The default build first (the reference table, copied aside), then the MPI build in the
# same target folder (cargo keeps both variants of the dependencies, so switching back and
# forth recompiles only the railfem crate). target/release/railfem is the MPI one after.
cargo build --release -p railfem -q
cp target/release/railfem "$work/railfem-serial"
serial_bin=$work/railfem-serial
cargo build --release -p railfem --features mpi -q
mpi_bin=target/release/railfem

root_flags=()
if [ "$(id -u)" -eq 0 ]; then root_flags=(--allow-run-as-root); fi
# Two ranks on a 2-core machine shared with others: oversubscribe, and let Open MPI yield.
export OMPI_MCA_mpi_yield_when_idle=1
mpirun_n() { local n=$1; shift; mpirun -n "$n" --oversubscribe "${root_flags[@]}" "$@"; }

plan=${1:-}
if [ -z "$plan" ]; then
    plan=$work/plan.toml
    # 3 seeds × 2 scales × 4 speeds of the 200-case plan: 24 cases.
    sed -e 's/^stop = 10$/stop = 3/' -e 's/^values = \[0.0, 0.5, 1.0, 1.5, 2.0\]$/values = [0.0, 1.0]/' \
        examples/studies/bridge-quake.toml > "$plan"
fi

fail() { echo "mpi.sh: FAILED: $*" >&2; exit 1; }
"$serial_bin" study "$plan" --threads 1 -q --out "$work/serial" >/dev/null
mpirun_n 1 "$mpi_bin" study "$plan" --threads 1 -q --out "$work/mpi1" >/dev/null
cmp "$work/serial/study.csv" "$work/mpi1/study.csv" || fail "1 rank differs from the serial run"
mpirun_n 2 "$mpi_bin" study "$plan" --threads 1 -q --out "$work/mpi2" >/dev/null
cmp "$work/serial/study.csv" "$work/mpi2/study.csv" || fail "2 ranks differ from the serial run"
grep -q '"ranks": 2' "$work/mpi2/study.json" || fail "study.json does not say 2 ranks"
# Resume under MPI: stop after 7 cases, then finish with 2 ranks.
mpirun_n 2 "$mpi_bin" study "$plan" --threads 1 -q --stop-after 7 --out "$work/resume" >/dev/null
mpirun_n 2 "$mpi_bin" study "$plan" --threads 1 -q --out "$work/resume" >/dev/null
cmp "$work/serial/study.csv" "$work/resume/study.csv" || fail "the resumed MPI study differs"
# A panicking case (whichever rank takes it) is a failed row; the job ends by itself.
RAILFEM_STUDY_PANIC_CASE=0001 timeout 600 mpirun -n 2 --oversubscribe "${root_flags[@]}" \
    -x RAILFEM_STUDY_PANIC_CASE "$mpi_bin" study "$plan" --threads 1 -q --out "$work/panic" >/dev/null 2>"$work/panic.err" \
    || fail "the study with a panicking case did not end cleanly"
grep -q '^0001,.*,failed,.*panic' "$work/panic/study.csv" || fail "the panicking case is not a failed row"
# A rank that dies (case 0012 aborts its process, whichever rank runs it): the job ends
# within the timeout (124 would be a hang), non-zero, with mpirun's line naming the rank.
status=0
RAILFEM_STUDY_ABORT_CASE=0012 timeout 300 mpirun -n 2 --oversubscribe "${root_flags[@]}" \
    -x RAILFEM_STUDY_ABORT_CASE "$mpi_bin" study "$plan" --threads 1 -q --out "$work/died" >/dev/null 2>"$work/died.err" \
    || status=$?
[ "$status" -ne 0 ] && [ "$status" -ne 124 ] || fail "a dying rank: exit status $status (0: not noticed, 124: hung)"
grep -qi 'rank' "$work/died.err" || fail "a dying rank: no message naming the rank ($(head -c 300 "$work/died.err"))"
kept=$(grep -c . "$work/died/study.checkpoint" || true)
mpirun_n 2 "$mpi_bin" study "$plan" --threads 1 -q --out "$work/died" >/dev/null
cmp "$work/serial/study.csv" "$work/died/study.csv" || fail "the study resumed after a dying rank differs"
rows=$(($(wc -l < "$work/serial/study.csv") - 1))
echo "mpi.sh: ok — $rows cases: serial, 1 rank, 2 ranks and a resumed 2-rank run give the same study.csv bytes; a panicking case is a failed row; a dying rank ended the job (exit $status, $kept checkpoint lines kept) and the resumed study is the same"

# `railfem bridge-check` across ranks (docs/bridge-check.md): HSLM-A1 and A4 over the 20 m
# span of examples/bridge-check/span20.toml; 2 ranks write the serial run's envelope.csv
# byte for byte (rank 1 computing some of the runs), and a 2-rank check stopped after 30
# runs (--stop-after) and run again resumes from its journal to the same bytes.
bc_plan=$work/bridge-check.toml
{ echo 'trains = ["HSLM-A1", "HSLM-A4"]'; cat examples/bridge-check/span20.toml; } > "$bc_plan"
"$serial_bin" bridge-check "$bc_plan" --threads 1 -q --out "$work/bc-serial" >/dev/null
mpirun_n 2 "$mpi_bin" bridge-check "$bc_plan" --threads 1 -q --out "$work/bc-mpi2" >"$work/bc-mpi2.out"
cmp "$work/bc-serial/envelope.csv" "$work/bc-mpi2/envelope.csv" || fail "bridge-check: 2 ranks differ from the serial run"
bc_other=$(grep -o 'which computed [0-9]* runs' "$work/bc-mpi2.out" | grep -o '[0-9]*' || true)
[ "${bc_other:-0}" -gt 0 ] || fail "bridge-check: rank 1 computed no run ($(head -c 300 "$work/bc-mpi2.out"))"
status=0
mpirun_n 2 "$mpi_bin" bridge-check "$bc_plan" --threads 1 -q --stop-after 30 --out "$work/bc-resume" >/dev/null 2>&1 || status=$?
bc_kept=$(($(wc -l < "$work/bc-resume/bridge-check.checkpoint") - 1))
[ "$status" -ne 0 ] && [ "$bc_kept" -eq 30 ] && [ ! -e "$work/bc-resume/envelope.csv" ] \
    || fail "bridge-check --stop-after 30 on 2 ranks: exit $status, $bc_kept runs in the journal"
mpirun_n 2 "$mpi_bin" bridge-check "$bc_plan" --threads 1 -q --out "$work/bc-resume" >/dev/null
cmp "$work/bc-serial/envelope.csv" "$work/bc-resume/envelope.csv" || fail "bridge-check resumed on 2 ranks differs from the serial run"
bc_rows=$(($(wc -l < "$work/bc-serial/envelope.csv") - 1))
echo "mpi.sh: ok — bridge-check: $bc_rows runs on 2 ranks (rank 1 computed $bc_other) give the serial envelope.csv bytes; stopped after 30 runs and resumed on 2 ranks, likewise"

# One model across ranks (issue 15 item 2, docs/scale-out.md): the partitioned solver's
# blocks shared by 2 ranks give the serial run's recorders to 1e-12 relative (each column
# against its largest value); 1 rank is the serial run; only rank 0 writes.
tb0=(train-bridge --cars 1 --spans 3 --span 10 --element-length 0.5 --speed 80 --dt 0.002
    --steps 40 --block-size 300 -q)
tb=("${tb0[@]}" --solver partitioned)
"$serial_bin" "${tb[@]}" --out "$work/tb-serial" >/dev/null
mpirun_n 1 "$mpi_bin" "${tb[@]}" --out "$work/tb-mpi1" >/dev/null
mpirun_n 2 "$mpi_bin" "${tb[@]}" --out "$work/tb-mpi2" >"$work/tb-mpi2.out"
grep -q 'partitioned solver across 2 ranks: rank 0 owns' "$work/tb-mpi2.out" \
    || fail "the 2-rank train-bridge did not share the partitioned solver ($(head -c 300 "$work/tb-mpi2.out"))"
[ "$(grep -c '^train-bridge:' "$work/tb-mpi2.out")" -eq 1 ] || fail "more than rank 0 printed the report"
same_numbers() { # FILE_A FILE_B: every column within 1e-12 of its largest |value|
    python3 - "$1" "$2" <<'PY'
import sys
rows = [[l.rstrip("\n").split(",") for l in open(f) if l.strip()] for f in sys.argv[1:3]]
a, b = rows
if len(a) != len(b) or a[0] != b[0]:
    sys.exit(f"{sys.argv[2]}: {len(b)} lines/header differ from {sys.argv[1]} ({len(a)} lines)")
worst = 0.0
for j in range(len(a[0])):
    try:
        x = [float(r[j]) for r in a[1:]]
        y = [float(r[j]) for r in b[1:]]
    except ValueError:
        continue
    scale = max(abs(v) for v in x) or 1.0
    worst = max(worst, max(abs(u - v) for u, v in zip(x, y)) / scale)
if worst > 1e-12:
    sys.exit(f"{sys.argv[2]}: differs from {sys.argv[1]} by {worst:.3e} of a column's largest value")
print(f"{worst:.1e}")
PY
}
for f in wheels.csv midspan.csv; do
    d1=$(same_numbers "$work/tb-serial/$f" "$work/tb-mpi1/$f") || fail "1 rank: $f"
    d2=$(same_numbers "$work/tb-serial/$f" "$work/tb-mpi2/$f") || fail "2 ranks: $f"
    echo "mpi.sh: train-bridge $f: 1 rank differs from serial by $d1, 2 ranks by $d2 (relative, limit 1e-12)"
done
# A stop request (SIGTERM) sent to rank 1 alone: every rank stops at the same step (they
# agree on the flag each step), so the job ends — exit 130, not a hang (124 from timeout) —
# and rank 0's rows are whole: the serial run of as many steps gives them to 1e-12.
stop_case=(train-bridge --cars 1 --spans 3 --span 10 --element-length 0.5 --speed 5 --dt 0.002
    --block-size 300 -q --solver partitioned --record-every 1)
status=0
timeout 300 mpirun -n 2 --oversubscribe "${root_flags[@]}" "$mpi_bin" "${stop_case[@]}" \
    --steps 100000 --out "$work/tb-stop" >/dev/null 2>"$work/stop.err" &
job=$!
rank1=""
for _ in $(seq 1 600); do
    sleep 0.1
    for p in $(pgrep -f "$mpi_bin train-bridge" || true); do
        if tr '\0' '\n' < "/proc/$p/environ" 2>/dev/null | grep -qx 'OMPI_COMM_WORLD_RANK=1'; then
            rank1=$p
        fi
    done
    if [ -n "$rank1" ] && [ -f "$work/tb-stop/wheels.csv" ] \
        && [ "$(wc -l < "$work/tb-stop/wheels.csv")" -gt 20 ]; then
        break
    fi
done
[ -n "$rank1" ] || fail "no rank 1 of the long train-bridge run found"
kill -TERM "$rank1"
wait "$job" || status=$?
[ "$status" -eq 130 ] || fail "SIGTERM to rank 1: the job ended with $status (124: it hung), $(head -c 300 "$work/stop.err")"
rows=$(($(wc -l < "$work/tb-stop/wheels.csv") - 1))
"$serial_bin" "${stop_case[@]}" --steps "$rows" --out "$work/tb-stop-serial" >/dev/null
for f in wheels.csv midspan.csv; do
    d=$(same_numbers "$work/tb-stop-serial/$f" "$work/tb-stop/$f") || fail "after a stop on rank 1: $f"
done
echo "mpi.sh: ok — SIGTERM to rank 1 alone stopped both ranks after $rows steps (exit 130); rank 0's rows equal the serial run's ($d)"
# Bad input under a launcher, one line and exit 2 from each rank: the default build (no MPI)
# and a model that does not use the partitioned solver.
status=0
mpirun_n 2 "$serial_bin" "${tb[@]}" --out "$work/tb-nompi" >/dev/null 2>"$work/nompi.err" || status=$?
[ "$status" -ne 0 ] && grep -q 'this build has no MPI; build with' "$work/nompi.err" \
    || fail "the default build under mpirun -n 2: exit $status, $(head -c 300 "$work/nompi.err")"
status=0
mpirun_n 2 "$mpi_bin" "${tb0[@]}" --solver direct --out "$work/tb-direct" >/dev/null 2>"$work/direct.err" || status=$?
[ "$status" -ne 0 ] && grep -q "give \`--solver partitioned\`" "$work/direct.err" \
    || fail "a direct-solver model under mpirun -n 2: exit $status, $(head -c 300 "$work/direct.err")"
echo "mpi.sh: ok — train-bridge across 2 ranks equals the serial run; the default build and a direct-solver model under mpirun are refused"
# A model file shared among ranks (`railfem run`): the sprung-mass example on the partitioned
# solver in blocks of 20 equations; 2 ranks write the serial run's recorders to 1e-12, and
# the same file on its default (low-rank) solver is refused with the fix.
sed 's/^gravity = .*/&\nsolver = "partitioned"\nblock_size = 20/' \
    examples/models/moving_sprung_mass.toml > "$work/model-partitioned.toml"
"$serial_bin" run "$work/model-partitioned.toml" -q --out "$work/mf-serial" >/dev/null
mpirun_n 2 "$mpi_bin" run "$work/model-partitioned.toml" -q --out "$work/mf-mpi2" >"$work/mf-mpi2.out"
grep -q 'partitioned solver across 2 ranks: rank 0 owns' "$work/mf-mpi2.out" \
    || fail "the 2-rank model-file run did not share the partitioned solver ($(head -c 300 "$work/mf-mpi2.out"))"
for f in midspan.csv sprung_mass.csv; do
    d2=$(same_numbers "$work/mf-serial/$f" "$work/mf-mpi2/$f") || fail "model file, 2 ranks: $f"
    echo "mpi.sh: model file $f: 2 ranks differ from serial by $d2 (relative, limit 1e-12)"
done
# The energy balance, summed over the ranks' own rows in block order: every energy within
# 1e-12 of the largest energy of the run (another order of the same sums), the times equal.
de=$(python3 - "$work/mf-serial/energy.csv" "$work/mf-mpi2/energy.csv" <<'PY'
import sys
a, b = ([[float(x) for x in l.split(",")] for l in list(open(f))[1:] if l.strip()] for f in sys.argv[1:3])
if len(a) != len(b) or len(a) < 2 or any(x[0] != y[0] for x, y in zip(a, b)):
    sys.exit(f"{sys.argv[2]}: rows or times differ from {sys.argv[1]}")
scale = max(abs(v) for r in a for v in r[1:6])
worst = max(abs(u - v) for x, y in zip(a, b) for u, v in zip(x[1:], y[1:])) / scale
if worst > 1e-12:
    sys.exit(f"{sys.argv[2]}: differs from {sys.argv[1]} by {worst:.3e} of the largest energy")
print(f"{worst:.1e}")
PY
) || fail "model file, 2 ranks: energy.csv"
echo "mpi.sh: model file energy.csv: 2 ranks differ from serial by $de of the largest energy (limit 1e-12)"
status=0
mpirun_n 2 "$mpi_bin" run examples/models/moving_sprung_mass.toml -q --out "$work/mf-lowrank" >/dev/null 2>"$work/mf-lowrank.err" || status=$?
[ "$status" -ne 0 ] && grep -q 'set `solver = "partitioned"`' "$work/mf-lowrank.err" \
    || fail "a model file on another solver under mpirun -n 2: exit $status, $(head -c 300 "$work/mf-lowrank.err")"
echo "mpi.sh: ok — a model file across 2 ranks equals the serial run; one on another solver is refused"

if [ "${SCALE_OUT_BENCH:-0}" = 1 ]; then
    # Back-to-back timings of the 200-case plan (A B A B), with the load average.
    full=examples/studies/bridge-quake.toml
    for rep in 1 2; do
        for mode in t1 t2 m1 m2; do
            rm -rf "$work/b"
            start=$(date +%s.%N)
            case $mode in
                t1) "$serial_bin" study $full --threads 1 -q --out "$work/b" >/dev/null ;;
                t2) "$serial_bin" study $full --threads 2 -q --out "$work/b" >/dev/null ;;
                m1) mpirun_n 1 "$mpi_bin" study $full --threads 1 -q --out "$work/b" >/dev/null ;;
                m2) mpirun_n 2 "$mpi_bin" study $full --threads 1 -q --out "$work/b" >/dev/null ;;
            esac
            end=$(date +%s.%N)
            sum=$(sha256sum < "$work/b/study.csv" | cut -c1-16)
            echo "bench rep=$rep mode=$mode wall=$(echo "$end - $start" | bc) s table=$sum load=$(cut -d' ' -f1-3 /proc/loadavg)"
        done
    done
fi
