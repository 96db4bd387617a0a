#!/usr/bin/env python3
"""Rerun railfem's benchmarks in OpenSeesPy: the same model, the same loads, time and answer.

What lives here, two comparisons:

1. `opensees_compare.py EXPORT_DIR`: one size of `railfem-measure export` (model.json,
   nodes.csv, elements.csv, loads.csv, railfem.csv, timing.json). The same continuous beam
   in OpenSees (elasticBeamColumn, consistent mass with `-cMass` or OpenSees' default
   lumped mass, as `mass_kind` in model.json says; the same pins and local axes), the
   identical nodal load vector of every step, Newmark (gamma 1/2, beta 1/4) at the same dt
   with the Linear algorithm factoring once; time per step and the largest difference of
   the monitored midspan histories relative to their peak, per solver and per way of
   applying the moving load:
   - `pattern`: ONE Plain pattern with a Constant series holding only this step's nodal
     loads, removed and rebuilt before every `analyze(1)` (OpenSees evaluates one pattern
     per step; Python's calls are charged to OpenSees, they are what the approach costs);
   - `path`: one Path time series and pattern per loaded DOF, all steps in one `analyze`
     call (OpenSees evaluates every pattern at every step).
2. `opensees_compare.py --pareto OUT.csv`: the moving-force case of `railfem pareto`
   (simply supported 25 m span, EI = 2.943e10 N m2, m = 2303 kg/m, 100 kN at 27.78 m/s,
   consistent mass, Newmark) over the same grid (elements x dt = T1/n), with the same error
   measure (largest |w - w_Fryba| at midspan over the steps, relative to the series' peak
   at those steps; Fryba's modal series with 200 terms, written here independently), and
   the wall time of each run (model build + every step; the analysis alone in its own
   column). OUT.csv is what `railfem-measure peer OUT.csv` reads.

Usage:
  opensees_compare.py EXPORT_DIR [--solvers UmfPack,BandSPD,...] [--loads pattern,path]
                      [--json OUT.json]
  opensees_compare.py --pareto OUT.csv [--solvers BandSPD] [--loads pattern,path]
                      [--elements 2,4,8,16,32] [--per-period 10,20,40,80,160,320]
                      [--repeat 3]
Each run uses a fresh OpenSees domain. An unavailable solver is reported and skipped.
"""

import argparse
import csv
import json
import math
import os
import statistics
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


# ---------------------------------------------------------------- 1. the bench export


def read_export(d):
    try:
        with open(os.path.join(d, "model.json")) as f:
            spec = json.load(f)
        with open(os.path.join(d, "nodes.csv")) as f:
            nodes = [(int(r["id"]), float(r["x"]), float(r["y"]), float(r["z"]),
                      r["fixed"].split()) for r in rows_of(f)]
        with open(os.path.join(d, "elements.csv")) as f:
            elems = [(int(r["id"]), int(r["node_i"]), int(r["node_j"])) for r in rows_of(f)]
        by_step = {}
        with open(os.path.join(d, "loads.csv")) as f:
            for r in rows_of(f):
                by_step.setdefault(int(r["step"]), []).append(
                    (int(r["node"]), r["dof"], float(r["value"])))
        with open(os.path.join(d, "railfem.csv")) as f:
            rows = rows_of(f)
        with open(os.path.join(d, "timing.json")) as f:
            timing = json.load(f)
    except (OSError, ValueError, KeyError) as e:
        fail(f"{d}: cannot read the export ({e}); run `railfem-measure export {d} ...` first")
    spec.setdefault("mass_kind", "consistent")  # exports before `--mass` existed
    if spec["mass_kind"] not in ("consistent", "lumped"):
        fail(f"{d}/model.json: mass_kind = {spec['mass_kind']!r}; expected consistent or lumped")
    mon = spec["monitor_nodes"]
    hist = {n: [float(r[f"uz_{n}"]) for r in rows] for n in mon}
    return spec, nodes, elems, by_step, hist, timing


def build_beam(ops, spec, nodes, elems):
    """The exported beam (no loads) in a fresh OpenSees domain."""
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    for nid, x, y, z, fixed in nodes:
        ops.node(nid, x, y, z)
        if fixed:
            ops.fix(nid, *[1 if name in fixed else 0 for name in DOF_INDEX])
    # Local y = vecxz x local x = Z x X = Y (horizontal), local z = global Z: Iy is the
    # vertical-bending inertia, as in railfem's beam3d default orientation.
    ops.geomTransf("Linear", 1, 0.0, 0.0, 1.0)
    # Without -cMass, elasticBeamColumn lumps rho*A*L/2 on each node's translations and
    # puts no mass on the rotations: railfem's beam3d mass = "lumped_translational".
    cmass = ["-cMass"] if spec["mass_kind"] == "consistent" else []
    mass_per_length = spec["rho"] * spec["A"]
    for eid, i, j in elems:
        ops.element("elasticBeamColumn", eid, i, j, spec["A"], spec["E"], spec["G"],
                    spec["J"], spec["Iy"], spec["Iz"], 1, "-mass", mass_per_length, *cmass)


def add_path_loads(ops, by_step, dt, steps):
    """One Path series per loaded DOF, valued at t = 0, dt, ..., steps*dt (0 at t = 0: the
    force enters just after t = 0), and a unit nodal load on that DOF. `-useLast`: OpenSees
    accumulates time, so the last step lands a hair after steps*dt, where a Path series
    would otherwise return 0 (seen as a 2e-6 jump at the last step)."""
    per_dof = {}
    for s, entries in by_step.items():
        for nid, dof, v in entries:
            per_dof.setdefault((nid, dof), {})[s] = v
    for k, ((nid, dof), vals) in enumerate(sorted(per_dof.items()), start=1):
        values = [0.0] + [vals.get(s, 0.0) for s in range(1, steps + 1)]
        ops.timeSeries("Path", k, "-dt", dt, "-values", *values, "-useLast")
        ops.pattern("Plain", k, k)
        unit = [0.0] * 6
        unit[DOF_INDEX[dof] - 1] = 1.0
        ops.load(nid, *unit)
    return len(per_dof)


def set_step_pattern(ops, entries, first):
    """Replaces the one load pattern (tag 1, Constant series 1) by this step's loads."""
    if not first:
        ops.remove("loadPattern", 1)
    ops.pattern("Plain", 1, 1)
    for nid, dof, v in entries:
        f = [0.0] * 6
        f[DOF_INDEX[dof] - 1] = v
        ops.load(nid, *f)


def analysis(ops, solver):
    """The transient analysis both comparisons use: Newmark (1/2, 1/4), factor once."""
    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system(solver)
    ops.algorithm("Linear", "-factorOnce")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")


def run_bench(ops, spec, nodes, elems, by_step, solver, loads, workdir):
    """Builds, analyzes and returns the timings and the monitored uz histories.

    The first step (which factors once) is timed alone; `per_step_s` is the mean of the
    others. `path`: the other steps run in ONE `analyze` call. `pattern`: each step is one
    loop turn (rebuild the pattern, `analyze(1)`), Python's calls included. The history
    comes from a Node recorder written with 17 significant digits, in both.
    """
    dt, steps = spec["dt"], spec["steps"]
    t0 = time.perf_counter()
    build_beam(ops, spec, nodes, elems)
    n_series = add_path_loads(ops, by_step, dt, steps) if loads == "path" else 1
    if loads == "pattern":
        ops.timeSeries("Constant", 1)
    t_build = time.perf_counter() - t0
    analysis(ops, solver)
    mon = spec["monitor_nodes"]
    path = os.path.join(workdir, f"opensees-{solver}-{loads}.out")
    ops.recorder("Node", "-file", path, "-precision", 17, "-node", *mon, "-dof", 3, "disp")
    if loads == "path":
        t0 = time.perf_counter()
        ok = ops.analyze(1, dt)
        first = time.perf_counter() - t0
        t0 = time.perf_counter()
        if ok == 0 and steps > 1:
            ok = ops.analyze(steps - 1, dt)
        t_rest = time.perf_counter() - t0
    else:
        first, t_rest, ok = 0.0, 0.0, 0
        for k in range(1, steps + 1):
            t0 = time.perf_counter()
            set_step_pattern(ops, by_step.get(k, []), k == 1)
            ok = ops.analyze(1, dt)
            el = time.perf_counter() - t0
            if k == 1:
                first = el
            else:
                t_rest += el
            if ok != 0:
                break
    if ok != 0:
        raise RuntimeError(f"analyze failed with {solver}")
    ops.wipe()  # closes (flushes) the recorder
    with open(path) as f:
        rows = [[float(x) for x in line.split()] for line in f if line.strip()]
    os.remove(path)
    if len(rows) != steps:
        raise RuntimeError(f"{path}: {len(rows)} rows, expected {steps}")
    hist = {n: [r[c] for r in rows] for c, n in enumerate(mon)}
    return {"solver": solver, "loads": loads, "mass": spec["mass_kind"], "series": n_series,
            "build_s": t_build, "first_step_s": first,
            "per_step_s": t_rest / max(steps - 1, 1), "hist": hist}


def max_rel_diff(a, b):
    """Largest |a - b| over a history, relative to the peak |b|."""
    peak = max(abs(x) for x in b)
    return max(abs(x - y) for x, y in zip(a, b)) / peak if peak > 0 else math.nan


def bench_main(args, ops):
    spec, nodes, elems, by_step, ref, timing = read_export(args.export_dir)
    results = []
    for loads in split(args.loads):
        for solver in split(args.solvers):
            try:
                r = run_bench(ops, spec, nodes, elems, by_step, solver, loads, args.export_dir)
            except Exception as e:  # an unavailable solver: say so and go on
                print(f"{args.export_dir}: {solver}, {loads}: skipped ({e})", file=sys.stderr)
                continue
            r["max_rel_diff"] = max(max_rel_diff(r["hist"][n], ref[n])
                                    for n in spec["monitor_nodes"])
            r["peak_m"] = {str(n): max(abs(x) for x in ref[n]) for n in spec["monitor_nodes"]}
            r["ratio_vs_railfem"] = r["per_step_s"] / timing["per_step_s"]
            del r["hist"]
            results.append(r)
            print(f"{spec['equations']} eq, {spec['mass_kind']} mass, {solver}, loads {loads} "
                  f"({r['series']} series): build {r['build_s']:.2f} s, first step "
                  f"{r['first_step_s']*1e3:.2f} ms, {r['per_step_s']*1e3:.3f} ms/step "
                  f"(railfem {timing['per_step_s']*1e3:.3f} ms/step, ratio "
                  f"{r['ratio_vs_railfem']:.2f}); max rel. diff of midspan uz "
                  f"{r['max_rel_diff']:.3e}", flush=True)
    ops.wipe()
    out = {"equations": spec["equations"], "steps": spec["steps"], "dt": spec["dt"],
           "mass": spec["mass_kind"], "railfem": timing, "opensees": results,
           "loadavg": open("/proc/loadavg").read().strip()}
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=2)
    if not results:
        fail("no OpenSees solver ran")


# ---------------------------------------------------------------- 2. the Pareto force case

SPAN, EI, MASS, SPEED, FORCE, E_MOD, RHO = 25.0, 2.943e10, 2303.0, 27.78, 1.0e5, 2.1e11, 7850.0


def omega(n):
    """Circular frequency of mode n of the simply supported span (rad/s)."""
    return (n * math.pi / SPAN) ** 2 * math.sqrt(EI / MASS)


def fryba_midspan(t, terms=200):
    """Midspan deflection (m, along the force) under P at x = v t, from rest: the modal
    series q_n'' + w_n^2 q_n = (2P/(mL)) sin(n w t), w = pi v / L, solved from rest."""
    w = math.pi * SPEED / SPAN
    c = 2.0 * FORCE / (MASS * SPAN)
    total = 0.0
    for n in range(1, terms + 1):
        wn, f = omega(n), n * w
        q = c / (wn * wn - f * f) * (math.sin(f * t) - f / wn * math.sin(wn * t))
        total += q * math.sin(n * math.pi * 0.5)
    return total


def hermite_loads(ne, t):
    """Consistent nodal loads (node, dof, value) of the downward force at x = v t on a span
    of ne equal elements along X: Fz = -P N1, -P N3; My = P N2, P N4 (the rotation about Y
    is -dw/dx), N1 = 1 - 3s^2 + 2s^3, N2 = h(s - 2s^2 + s^3), N3 = 3s^2 - 2s^3,
    N4 = h(s^3 - s^2)."""
    h = SPAN / ne
    x = SPEED * t
    if x < 0.0 or x > SPAN:
        return []
    e = min(int(x / h), ne - 1)
    s = x / h - e
    s2, s3 = s * s, s * s * s
    i, j = e + 1, e + 2
    return [(i, "uz", -FORCE * (1 - 3 * s2 + 2 * s3)), (i, "ry", FORCE * h * (s - 2 * s2 + s3)),
            (j, "uz", -FORCE * (3 * s2 - 2 * s3)), (j, "ry", FORCE * h * (s3 - s2))]


def build_span(ops, ne):
    """The pareto span: nodes 1..ne+1 along X, ux uy rx rz held everywhere, uz at the ends;
    E = 210 GPa, A = m/rho, Iy = Iz = J = EI/E, G = E/2.6, consistent mass (-cMass)."""
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    for i in range(ne + 1):
        ops.node(i + 1, SPAN * i / ne, 0.0, 0.0)
        ops.fix(i + 1, 1, 1, 1 if i in (0, ne) else 0, 1, 0, 1)
    ops.geomTransf("Linear", 1, 0.0, 0.0, 1.0)
    i_sec = EI / E_MOD
    for e in range(1, ne + 1):
        ops.element("elasticBeamColumn", e, e, e + 1, MASS / RHO, E_MOD, E_MOD / 2.6, i_sec,
                    i_sec, i_sec, 1, "-mass", MASS, "-cMass")


def pareto_run(ops, ne, dt, solver, loads, workdir):
    """One run of the grid: (wall s incl. build, analysis s, error, steps)."""
    t_end = SPAN / SPEED
    steps = int(math.floor(t_end / dt))
    mid = ne // 2 + 1
    t0 = time.perf_counter()
    build_span(ops, ne)
    if loads == "path":
        by_step = {k: hermite_loads(ne, k * dt) for k in range(1, steps + 1)}
        add_path_loads(ops, by_step, dt, steps)
        path = os.path.join(workdir, f"pareto-{os.getpid()}.out")
        ops.recorder("Node", "-file", path, "-precision", 17, "-node", mid, "-dof", 3, "disp")
    else:
        ops.timeSeries("Constant", 1)
    analysis(ops, solver)
    t_build = time.perf_counter() - t0
    t1 = time.perf_counter()
    uz = []
    if loads == "path":
        ok = ops.analyze(steps, dt)
        t_an = time.perf_counter() - t1
        ops.wipe()
        with open(path) as f:
            uz = [float(line.split()[0]) for line in f if line.strip()]
        os.remove(path)
    else:
        probe = 0.0
        ok = 0
        for k in range(1, steps + 1):
            set_step_pattern(ops, hermite_loads(ne, k * dt), k == 1)
            ok = ops.analyze(1, dt)
            if ok != 0:
                break
            s = time.perf_counter()
            uz.append(ops.nodeDisp(mid, 3))
            probe += time.perf_counter() - s
        t_an = time.perf_counter() - t1 - probe
        ops.wipe()
    if ok != 0 or len(uz) != steps:
        raise RuntimeError(f"{ne} elements, dt {dt}: analyze failed ({len(uz)} of {steps} steps)")
    worst = peak = 0.0
    for k, u in enumerate(uz, start=1):
        exact = fryba_midspan(k * dt)
        worst = max(worst, abs(-u - exact))
        peak = max(peak, abs(exact))
    return t_build + t_an, t_an, worst / peak, steps


def pareto_main(args, ops):
    t1 = 2.0 * math.pi / omega(1)
    elements = [int(x) for x in split(args.elements)]
    per_period = [float(x) for x in split(args.per_period)]
    workdir = os.path.dirname(os.path.abspath(args.pareto))
    os.makedirs(workdir, exist_ok=True)
    rows = []
    print(f"load average at start: {open('/proc/loadavg').read().strip()}", flush=True)
    for loads in split(args.loads):
        for solver in split(args.solvers):
            for ne in elements:
                for n in per_period:
                    dt = t1 / n
                    try:
                        reps = [pareto_run(ops, ne, dt, solver, loads, workdir)
                                for _ in range(args.repeat)]
                    except Exception as e:
                        print(f"pareto: {solver}, {loads}: skipped ({e})", file=sys.stderr)
                        break
                    wall = statistics.median(r[0] for r in reps)
                    an = statistics.median(r[1] for r in reps)
                    _, _, err, steps = reps[0]
                    rows.append((f"OpenSees {solver} {loads}", ne, dt, steps, wall, an, err))
                    print(f"pareto: OpenSees {solver} {loads}: {ne} elements, dt = T1/{n:g} "
                          f"= {dt:.3e} s: wall {wall:.4f} s (analysis {an:.4f} s), "
                          f"error {err:.3e}", flush=True)
    with open(args.pareto, "w") as f:
        f.write("peer,elements,dt [s],steps,wall [s],analysis [s],error [-]\n")
        for label, ne, dt, steps, wall, an, err in rows:
            f.write(f"{label},{ne},{dt:.6e},{steps},{wall:.6e},{an:.6e},{err:.6e}\n")
    print(f"load average at end: {open('/proc/loadavg').read().strip()}", flush=True)
    if not rows:
        fail("no OpenSees run finished")


def split(text):
    return [s.strip() for s in text.split(",") if s.strip()]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("export_dir", nargs="?")
    ap.add_argument("--solvers", default=None)
    ap.add_argument("--loads", default="pattern,path")
    ap.add_argument("--json", default=None)
    ap.add_argument("--pareto", default=None, metavar="OUT.csv")
    ap.add_argument("--elements", default="2,4,8,16,32")
    ap.add_argument("--per-period", default="10,20,40,80,160,320")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    if bool(args.export_dir) == bool(args.pareto):
        fail("give either EXPORT_DIR or --pareto OUT.csv")
    for l in split(args.loads):
        if l not in ("pattern", "path"):
            fail(f"--loads {args.loads}: use pattern, path or both")
    try:
        import openseespy.opensees as ops
    except ImportError as e:
        fail(f"openseespy is not importable ({e}); run scripts/opensees_compare.sh, "
             "which installs it in target/opensees-venv")
    if args.pareto:
        args.solvers = args.solvers or "BandSPD"
        pareto_main(args, ops)
    else:
        args.solvers = args.solvers or "UmfPack,BandSPD,BandGeneral,ProfileSPD,SparseSYM"
        bench_main(args, ops)


if __name__ == "__main__":
    main()
