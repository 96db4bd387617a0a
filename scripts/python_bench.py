"""Benchmark (not a test): the same model run by the `railfem` command and from Python.

    python scripts/python_bench.py [--repeats 7] [MODEL ...]

For each model, `repeats` rounds, each running in turn: the command (`railfem run MODEL
--out DIR`, a process), a Python process doing `Model.from_file(MODEL).run(out=DIR)`
(interpreter start and `import railfem` included), and the same call inside this process
(`run(out=DIR)` and `run()`, no files). Wall and CPU seconds (user + system, all threads)
per variant, the median over the rounds, and the overhead against the command. Prints a
Markdown table (docs/performance.md has one).
"""

import argparse
import os
import pathlib
import resource
import statistics
import subprocess
import sys
import tempfile
import time

import railfem

REPO = pathlib.Path(__file__).resolve().parents[1]
BIN = pathlib.Path(
    os.environ.get("RAILFEM_BIN", pathlib.Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target")) / "release" / "railfem")
)


def child_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def timed_process(argv):
    c0, t0 = child_cpu(), time.perf_counter()
    subprocess.run(argv, check=True, capture_output=True)
    return time.perf_counter() - t0, child_cpu() - c0


def timed_call(f):
    c0, t0 = time.process_time(), time.perf_counter()
    f()
    return time.perf_counter() - t0, time.process_time() - c0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument(
        "models",
        nargs="*",
        default=[str(REPO / "examples/models/curve_quick.toml"), str(REPO / "examples/models/moving_sprung_mass.toml")],
    )
    a = ap.parse_args()
    print("| model | variant | wall (s) | CPU (s) | wall vs CLI | CPU vs CLI |")
    print("|---|---|---|---|---|---|")
    for model in a.models:
        out = tempfile.mkdtemp(prefix="railfem-bench-")
        m = railfem.Model.from_file(model)
        script = f"import railfem; railfem.Model.from_file({model!r}).run(out={out!r})"
        variants = {
            "CLI process: `railfem run --out`": lambda: timed_process([str(BIN), "run", model, "--out", out]),
            "Python process: `run(out=)`": lambda: timed_process([sys.executable, "-c", script]),
            "in Python: `run(out=)`": lambda: timed_call(lambda: m.run(out=out)),
            "in Python: `run()`": lambda: timed_call(m.run),
        }
        samples = {k: [] for k in variants}
        for _ in range(a.repeats):
            for k, f in variants.items():
                samples[k].append(f())
        base_w = statistics.median(w for w, _ in samples[next(iter(variants))])
        base_c = statistics.median(c for _, c in samples[next(iter(variants))])
        for k, s in samples.items():
            w = statistics.median(x for x, _ in s)
            c = statistics.median(x for _, x in s)
            print(
                f"| {pathlib.Path(model).name} | {k} | {w:.3f} | {c:.3f} | "
                f"{100 * (w / base_w - 1):+.1f} % | {100 * (c / base_c - 1):+.1f} % |"
            )


if __name__ == "__main__":
    main()
