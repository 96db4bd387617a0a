#!/usr/bin/env python3
"""Rerun a `railfem bench --export` model in OpenSeesPy and compare time and answer.

What lives here: reading one exported size (model.json, nodes.csv, elements.csv,
loads.csv, railfem.csv, timing.json), building the same continuous beam in OpenSees
(elasticBeamColumn with consistent mass, the same pins, the same local axes), applying the
identical nodal load vectors as Path time series (one series per loaded DOF, valued at every
step time), integrating with Newmark (gamma 1/2, beta 1/4) at the same dt with the Linear
algorithm factoring once, and reporting the time per step and the largest difference of the
monitored midspan displacement histories relative to their peak.

Usage: opensees_compare.py EXPORT_DIR [--solvers UmfPack,BandSPD,...] [--json OUT.json]
Each solver is run in a fresh OpenSees domain; the answer of every solver is compared.
"""

import argparse
import csv
import json
import math
import os
import sys
import time

DOF_INDEX = {"ux": 1, "uy": 2, "uz": 3, "rx": 4, "ry": 5, "rz": 6}


def fail(msg):
    print(f"opensees_compare: {msg}", file=sys.stderr)
    sys.exit(2)


def rows_of(f):
    """The rows of a railfem CSV as dicts keyed by the column names without their units
    (`x [m]` -> `x`)."""
    return [{k.split(" [")[0]: v for k, v in r.items()} for r in csv.DictReader(f)]


def read_export(d):
    try:
        with open(os.path.join(d, "model.json")) as f:
            spec = json.load(f)
        with open(os.path.join(d, "nodes.csv")) as f:
            nodes = [(int(r["id"]), float(r["x"]), float(r["y"]), float(r["z"]),
                      r["fixed"].split()) for r in rows_of(f)]
        with open(os.path.join(d, "elements.csv")) as f:
            elems = [(int(r["id"]), int(r["node_i"]), int(r["node_j"])) for r in rows_of(f)]
        loads = {}
        with open(os.path.join(d, "loads.csv")) as f:
            for r in rows_of(f):
                key = (int(r["node"]), r["dof"])
                loads.setdefault(key, {})[int(r["step"])] = float(r["value"])
        with open(os.path.join(d, "railfem.csv")) as f:
            rows = rows_of(f)
        with open(os.path.join(d, "timing.json")) as f:
            timing = json.load(f)
    except (OSError, ValueError, KeyError) as e:
        fail(f"{d}: cannot read the export ({e}); run `railfem bench --export {d} ...` first")
    mon = spec["monitor_nodes"]
    hist = {n: [float(r[f"uz_{n}"]) for r in rows] for n in mon}
    return spec, nodes, elems, loads, hist, timing


def build(ops, spec, nodes, elems, loads):
    """The exported model in a fresh OpenSees domain."""
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    for nid, x, y, z, fixed in nodes:
        ops.node(nid, x, y, z)
        if fixed:
            flags = [1 if name in fixed else 0 for name in DOF_INDEX]
            ops.fix(nid, *flags)
    # Local y = vecxz x local x = Z x X = Y (horizontal), local z = global Z: Iy is the
    # vertical-bending inertia, as in railfem's beam3d default orientation.
    ops.geomTransf("Linear", 1, 0.0, 0.0, 1.0)
    mass_per_length = spec["rho"] * spec["A"]
    for eid, i, j in elems:
        ops.element("elasticBeamColumn", eid, i, j, spec["A"], spec["E"], spec["G"],
                    spec["J"], spec["Iy"], spec["Iz"], 1, "-mass", mass_per_length, "-cMass")
    dt, steps = spec["dt"], spec["steps"]
    # One Path series per loaded DOF, valued at t = 0, dt, ..., steps*dt (0 at t = 0:
    # the force enters just after t = 0), and a unit nodal load on that DOF. `-useLast`:
    # OpenSees accumulates time, so the last step lands a hair after steps*dt, where a
    # Path series would otherwise return 0 (seen as a 2e-6 jump at the last step).
    for k, ((nid, dof), by_step) in enumerate(sorted(loads.items()), start=1):
        values = [0.0] + [by_step.get(s, 0.0) for s in range(1, steps + 1)]
        ops.timeSeries("Path", k, "-dt", dt, "-values", *values, "-useLast")
        ops.pattern("Plain", k, k)
        unit = [0.0] * 6
        unit[DOF_INDEX[dof] - 1] = 1.0
        ops.load(nid, *unit)


def run(ops, spec, nodes, elems, loads, solver, workdir):
    """Builds, analyzes and returns the timings and the monitored uz histories.

    The first step (which factors once) is timed alone; the other steps run in ONE
    `analyze` call, so Python's per-call overhead is not charged to OpenSees. The history
    comes from a Node recorder written with 17 significant digits.
    """
    t0 = time.perf_counter()
    build(ops, spec, nodes, elems, loads)
    t_build = time.perf_counter() - t0
    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system(solver)
    ops.algorithm("Linear", "-factorOnce")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    dt, steps = spec["dt"], spec["steps"]
    mon = spec["monitor_nodes"]
    path = os.path.join(workdir, f"opensees-{solver}.out")
    ops.recorder("Node", "-file", path, "-precision", 17, "-node", *mon, "-dof", 3, "disp")
    t0 = time.perf_counter()
    ok = ops.analyze(1, dt)
    first = time.perf_counter() - t0
    t0 = time.perf_counter()
    if ok == 0 and steps > 1:
        ok = ops.analyze(steps - 1, dt)
    t_rest = time.perf_counter() - t0
    if ok != 0:
        raise RuntimeError(f"analyze failed with {solver}")
    ops.wipe()  # closes (flushes) the recorder
    with open(path) as f:
        rows = [[float(x) for x in line.split()] for line in f if line.strip()]
    if len(rows) != steps:
        raise RuntimeError(f"{path}: {len(rows)} rows, expected {steps}")
    hist = {n: [r[c] for r in rows] for c, n in enumerate(mon)}
    return {"solver": solver, "build_s": t_build, "first_step_s": first,
            "per_step_s": t_rest / max(steps - 1, 1), "hist": hist}


def max_rel_diff(a, b):
    """Largest |a - b| over a history, relative to the peak |b|."""
    peak = max(abs(x) for x in b)
    return max(abs(x - y) for x, y in zip(a, b)) / peak if peak > 0 else math.nan


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("export_dir")
    ap.add_argument("--solvers", default="UmfPack,BandSPD,BandGeneral,ProfileSPD,SparseSYM")
    ap.add_argument("--json", default=None)
    args = ap.parse_args()
    try:
        import openseespy.opensees as ops
    except ImportError as e:
        fail(f"openseespy is not importable ({e}); run scripts/opensees_compare.sh, "
             "which installs it in target/opensees-venv")
    spec, nodes, elems, loads, ref, timing = read_export(args.export_dir)
    results = []
    for solver in [s.strip() for s in args.solvers.split(",") if s.strip()]:
        try:
            r = run(ops, spec, nodes, elems, loads, solver, args.export_dir)
        except Exception as e:  # an unavailable solver: say so and go on
            print(f"{args.export_dir}: {solver}: skipped ({e})", file=sys.stderr)
            continue
        r["max_rel_diff"] = max(max_rel_diff(r["hist"][n], ref[n]) for n in spec["monitor_nodes"])
        r["peak_m"] = {str(n): max(abs(x) for x in ref[n]) for n in spec["monitor_nodes"]}
        r["ratio_vs_railfem"] = r["per_step_s"] / timing["per_step_s"]
        del r["hist"]
        results.append(r)
        print(f"{spec['equations']} eq, {solver}: build {r['build_s']:.2f} s, first step "
              f"{r['first_step_s']*1e3:.2f} ms, {r['per_step_s']*1e3:.3f} ms/step "
              f"(railfem {timing['per_step_s']*1e3:.3f} ms/step, ratio "
              f"{r['ratio_vs_railfem']:.2f}); max rel. diff of midspan uz {r['max_rel_diff']:.3e}",
              flush=True)
    ops.wipe()
    out = {"equations": spec["equations"], "steps": spec["steps"], "dt": spec["dt"],
           "railfem": timing, "opensees": results}
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=2)
    if not results:
        fail("no OpenSees solver ran")


if __name__ == "__main__":
    main()
