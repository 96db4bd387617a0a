"""The built-in cases from Python against the `railfem` command with the same inputs.

The command runs in its own process; its printed numbers and CSV files are the reference.
Each number Python returns, printed as the command prints it, must be the command's text
(or, for CSV fields, read back to the very same double), and the files written from Python
must be the command's files byte for byte.
"""

import re

import numpy as np

import railfem
from conftest import bare, cli, read_csv_text


def same_doubles(csv_fields, values, fmt):
    """Each CSV field read back equals the value printed with `fmt` and read back."""
    a = np.array([float(x) for x in csv_fields])
    b = np.array([float(fmt % v) for v in values])
    return np.array_equal(a.view(np.uint64), b.view(np.uint64))


def rs(v, digits):
    """`v` as Rust prints `{:.<digits>e}`: no `+` and no leading zeros in the exponent."""
    mantissa, exponent = f"{v:.{digits}e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def test_curve_agrees_with_the_cli(tmp_path):
    proc = cli("curve", "--quick", "--quiet", "--out", tmp_path / "cli")
    assert proc.returncode == 0, proc.stderr
    r = railfem.curve(quick=True, out=str(tmp_path / "py"))
    m, s = r["metrics"], r["stats"]
    out = proc.stdout
    assert f"{s['steps']} steps, {s['iterations']} Newton iterations" in out
    assert (
        f"normal vs statics {rs(m['max_rel_normal_statics'], 3)}, "
        f"axle shear vs Eq. 26 {rs(m['max_rel_shear'], 3)} "
        f"(single wheel {rs(m['max_rel_shear_wheel'], 3)}); "
        f"normal vs Eq. 25 as printed {rs(m['max_rel_normal_printed'], 3)}"
    ) in out
    assert (
        f"settled-arc mean FE normal inner {m['arc_mean_normal_inner']:.1f} N, "
        f"outer {m['arc_mean_normal_outer']:.1f} N"
    ) in out
    assert f"contact spacing used by the statics: {m['contact_spacing']:.4f} m" in out
    # On this left-hand curve the left wheels are the inner ones.
    assert r["wheel_names"] == ["w1L", "w1R", "w2L", "w2R", "w3L", "w3R", "w4L", "w4R"]
    assert r["inner"] == [True, False] * 4
    # Every wheel's Q and Y history is curve.csv's.
    header, rows = read_csv_text(tmp_path / "cli" / "curve.csv")
    col = {bare(h): i for i, h in enumerate(header)}
    assert len(rows) == len(r["time"])
    assert same_doubles([row[0] for row in rows], r["time"], "%.4f")
    for w, name in enumerate(r["wheel_names"]):
        for key in ("Q_fe", "Y_fe", "Q_statics", "Q_printed"):
            j = col[f"{name}_{key}"]
            assert same_doubles([row[j] for row in rows], r["wheels"][key][:, w], "%.6e"), (name, key)
    for f in ("curve.csv", "case.json", "curve.svg"):
        assert (tmp_path / "cli" / f).read_bytes() == (tmp_path / "py" / f).read_bytes(), f


def test_critical_radius_agrees_with_the_cli():
    proc = cli("critical-radius", "--speed", "120", "--ct", "200", "--mu", "0.3")
    assert proc.returncode == 0, proc.stderr
    r = railfem.critical_radius(speed=120.0, ct=200.0, mu=0.3)
    assert r["case"]["criterion"] == "sliding"
    assert (
        f"FE {r['fe']:.1f} m (gross sliding {r['fe_gross']:.1f} m), "
        f"theory (statics) {r['theory']:.1f} m"
    ) in proc.stdout
    rel = abs(r["fe"] - r["theory"]) / r["theory"]
    assert f"relative difference FE vs theory: {rs(rel, 3)}" in proc.stdout


def test_train_bridge_agrees_with_the_cli(tmp_path):
    args = dict(cars=1, spans=2, steps=20)
    proc = cli(
        "train-bridge", "--cars", "1", "--spans", "2", "--steps", "20", "--out", tmp_path / "cli"
    )
    assert proc.returncode == 0, proc.stderr
    r = railfem.train_bridge(out=str(tmp_path / "py"), **args)
    assert f"{r['dofs']} DOF, {r['elements']} elements, {r['nodes']} nodes" in proc.stdout
    assert f"{r['stats']['steps']} steps, {r['stats']['iterations']} Newton iterations" in proc.stdout
    header, rows = read_csv_text(tmp_path / "cli" / "summary.csv")
    rows = rows[: rows.index([""])]  # the per-wheel table; per-span maxima follow
    assert [row[0] for row in rows] == r["wheel_names"]
    w = r["wheels"]
    assert same_doubles([row[1] for row in rows], r["q_static"], "%.6e")
    assert same_doubles([row[4] for row in rows], w["max_dqq"], "%.6e")
    assert same_doubles([row[6] for row in rows], w["min_q"], "%.6e")
    # Times are printed shortest round-trip: the very doubles.
    assert [float(row[5]) for row in rows] == list(w["t_max_dqq"])
    header, rows = read_csv_text(tmp_path / "cli" / "midspan.csv")
    assert [bare(h) for h in header[1:]] == [f"span{k}" for k in sorted(r["midspan"])]
    for j, k in enumerate(sorted(r["midspan"]), start=1):
        assert same_doubles([row[j] for row in rows], r["midspan"][k]["deflection"], "%.6e")
    for f in ("wheels.csv", "midspan.csv", "summary.csv"):
        assert (tmp_path / "cli" / f).read_bytes() == (tmp_path / "py" / f).read_bytes(), f


def test_case_arguments_are_checked():
    import pytest

    with pytest.raises(ValueError, match='geometry="curly"'):
        railfem.curve(quick=True, geometry="curly")
    with pytest.raises(ValueError, match="cars=0"):
        railfem.train_bridge(cars=0)
    with pytest.raises(TypeError):
        railfem.curve(speed="fast")
