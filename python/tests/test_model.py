"""Model files run from Python against the `railfem` command on the same files.

The references are the command's own outputs (CSV files, stdout, stderr), produced by a
separate process: the arrays must be the numbers the command writes, bit for bit after the
CSV's rounding, and the files written from Python must be the command's files, byte for
byte. The CSV holds 13 significant digits (`{:.12e}`; time `{:.9e}`), so each exact double
from Python, printed the same way and read back, must give the very double read from the
command's CSV.
"""

import json
import re
import threading
import time

import numpy as np
import pytest

import railfem
from conftest import MODELS, bare, cli, cli_error_lines, plugin_lib, read_csv_text

SPRUNG = MODELS / "moving_sprung_mass.toml"


def bits(a):
    """The IEEE bit patterns of a float array (so -0.0 != 0.0 and NaN == same NaN)."""
    return np.ascontiguousarray(np.asarray(a, dtype=np.float64)).view(np.uint64)


def as_printed(values, digits):
    """Each value printed with `digits` decimals in scientific notation and read back."""
    fmt = "%." + str(digits) + "e"
    return np.array([float(fmt % v) for v in np.ravel(values)]).reshape(np.shape(values))


@pytest.fixture(scope="module")
def sprung(tmp_path_factory):
    """The sprung mass on a beam: run by the command and from Python (with out=)."""
    cli_out = tmp_path_factory.mktemp("cli")
    py_out = tmp_path_factory.mktemp("py")
    proc = cli("run", SPRUNG, "--out", cli_out)
    assert proc.returncode == 0, proc.stderr
    result = railfem.Model.from_file(SPRUNG).run(out=py_out)
    return cli_out, py_out, result, proc.stdout


def test_arrays_are_the_cli_csv_numbers(sprung):
    cli_out, _, result, _ = sprung
    assert set(result.recorders) == {"midspan.csv", "sprung_mass.csv"}
    for name, rec in result.recorders.items():
        header, rows = read_csv_text(cli_out / name)
        assert bare(header[0]) == "time" and header[1:] == rec.columns, name
        assert rec.values.shape == (len(rows), len(rec.columns))
        csv_time = np.array([float(r[0]) for r in rows])
        csv_values = np.array([[float(x) for x in r[1:]] for r in rows])
        assert np.array_equal(bits(csv_time), bits(as_printed(rec.time, 9))), name
        assert np.array_equal(bits(csv_values), bits(as_printed(rec.values, 12))), name
        # Columns by name are the same data.
        j = rec.columns.index(rec.columns[-1])
        assert np.array_equal(bits(rec[rec.columns[-1]]), bits(rec.values[:, j]))
        # Every header field has its unit, and the name without it finds the same column.
        for k, c in enumerate(rec.columns):
            assert c.endswith("]") and " [" in c, (name, c)
            assert np.array_equal(bits(rec[bare(c)]), bits(rec.values[:, k])), (name, c)
    # The energy ledger is energy.csv's numbers.
    header, rows = read_csv_text(cli_out / "energy.csv")
    assert [bare(h) for h in header] == ["time"] + result.energy.columns
    csv = np.array([[float(x) for x in r] for r in rows])
    assert np.array_equal(bits(csv[:, 0]), bits(as_printed(result.energy.time, 9)))
    assert np.array_equal(bits(csv[:, 1:]), bits(as_printed(result.energy.values, 9)))


def test_files_written_from_python_are_the_cli_files(sprung):
    cli_out, py_out, _, _ = sprung
    names = sorted(p.name for p in cli_out.iterdir())
    assert names == sorted(p.name for p in py_out.iterdir())
    for n in names:
        if n == "run.json":
            continue  # the sidecar names its command and times: compared below
        assert (cli_out / n).read_bytes() == (py_out / n).read_bytes(), n
    cli, py = (json.loads((d / "run.json").read_text()) for d in (cli_out, py_out))
    assert cli["status"] == py["status"] == "completed"
    assert cli["railfem"] == py["railfem"]
    assert py["command"] == "python: railfem.Model.run"


def test_statistics_and_energy_are_what_the_cli_prints(sprung):
    _, _, result, stdout = sprung
    m = re.search(
        r"(\d+) steps, (\d+) Newton iterations, (\d+) factorizations, (\d+) equations", stdout
    )
    assert m, stdout
    s = result.stats
    assert [s["steps"], s["iterations"], s["factorizations"], s["equations"]] == [
        int(g) for g in m.groups()
    ]
    assert result.energy_summary in stdout


def test_from_dict_runs_the_same_numbers_as_the_file():
    tomllib = pytest.importorskip("tomllib")
    data = tomllib.loads(SPRUNG.read_text())
    a = railfem.Model.from_file(SPRUNG).run()
    b = railfem.Model.from_dict(data, name=str(SPRUNG)).run()
    for name, rec in a.recorders.items():
        assert rec.columns == b[name].columns
        assert np.array_equal(bits(rec.time), bits(b[name].time))
        assert np.array_equal(bits(rec.values), bits(b[name].values))


BAD = """
[analysis]
kind = "static"

[[node]]
id = 1
xyz = [0.0, 0.0, 0.0]
fix = "all"

[[node]]
id = 2
xyz = [1.0, 0.0, 0.0]

[[element]]
id = 1
type = "spring_dampr"
nodes = [1, 2]
k = [1e6, 1e6, 1e6, 1e6, 1e6, 1e6]

[[element]]
id = 2
type = "mass"
nodes = [2]
mass = -5.0
"""


def test_bad_model_raises_the_cli_message(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(BAD)
    ran = cli("run", path)
    assert ran.returncode == 2
    [line] = cli_error_lines(ran)
    model = railfem.Model.from_file(str(path))
    with pytest.raises(ValueError) as e:
        model.run()
    assert str(e.value) == line
    checked = cli("check", path)
    assert checked.returncode == 2
    lines = cli_error_lines(checked)
    assert len(lines) == 2, checked.stderr
    with pytest.raises(ValueError) as e:
        model.check()
    assert str(e.value).split("\n") == lines


def test_dict_with_nan_is_refused_like_the_file(tmp_path):
    path = tmp_path / "nan.toml"
    path.write_text("[[node]]\nid = 1\nxyz = [0.0, nan, 0.0]\n")
    [line] = cli_error_lines(cli("check", path))
    with pytest.raises(ValueError) as e:
        railfem.Model.from_dict({"node": [{"id": 1, "xyz": [0.0, float("nan"), 0.0]}]}, name=str(path))
    assert str(e.value) == line


def test_missing_file_raises_the_cli_message(tmp_path):
    path = tmp_path / "nowhere.toml"
    [line] = cli_error_lines(cli("run", path))
    model = railfem.Model.from_file(str(path))
    with pytest.raises(ValueError) as e:
        model.run()
    assert str(e.value) == line


def test_check_gives_the_cli_size(sprung):
    proc = cli("check", SPRUNG)
    assert proc.returncode == 0, proc.stderr
    r = railfem.Model.from_file(SPRUNG).check()
    assert proc.stdout.strip() == f"{SPRUNG}: ok — {r['size']}"


def test_panic_becomes_runtime_error_and_the_interpreter_lives_on():
    with pytest.raises(RuntimeError, match="internal error: boom"):
        railfem._railfem._panic_inside("boom")
    assert railfem.elements()


def test_run_releases_the_gil():
    """While a run is in progress on another thread, this thread keeps running: the
    longest pause of its loop stays well below the run's duration. A run holding the GIL
    would stop this loop for the whole run."""
    # The sprung-mass model at a sixteenth of its time step: about 5700 steps, long enough
    # (a few tenths of a second) to tell a released GIL from a held one, whichever linear
    # solver the model resolves to (the low-rank solver runs the model file itself in 30 ms).
    tomllib = pytest.importorskip("tomllib")
    data = tomllib.loads(SPRUNG.read_text())
    data["analysis"]["dt"] = data["analysis"]["dt"] / 16
    model = railfem.Model.from_dict(data, name=str(SPRUNG))
    done = threading.Event()
    span = {}

    def work():
        t0 = time.perf_counter()
        model.run()
        span["run"] = time.perf_counter() - t0
        done.set()

    t = threading.Thread(target=work)
    t.start()
    last = time.perf_counter()
    longest = 0.0
    while not done.is_set():
        now = time.perf_counter()
        longest = max(longest, now - last)
        last = now
    t.join()
    assert span["run"] > 0.05, "the run is too short to tell"
    assert longest < 0.5 * span["run"], (longest, span["run"])


def test_elements_are_the_cli_table():
    proc = cli("elements")
    assert proc.returncode == 0
    table = {}
    for line in proc.stdout.splitlines():
        if not line.startswith(" "):
            kind = line.split(" — ")[0]
            table[kind] = []
        else:
            table[kind].append(line.split()[0])
    got = {k["name"]: [p["key"] for p in k["params"]] for k in railfem.elements()}
    assert got == table


def test_plugin_loads_and_its_kinds_are_listed():
    lib = plugin_lib()
    if not lib.is_file():
        pytest.skip(f"{lib} not built (cargo build --release -p railfem-plugin-hysteretic)")
    kinds = railfem.load_plugin(str(lib))
    assert kinds, "the plugin registered no kind"
    names = {k["name"] for k in railfem.elements()}
    assert set(kinds) <= names
    assert railfem.load_plugin(str(lib)) == kinds  # loading again changes nothing


def test_bad_plugin_raises_the_cli_message(tmp_path):
    path = tmp_path / "libnothing.so"
    [line] = cli_error_lines(cli("elements", "--plugin", path))
    with pytest.raises(ValueError) as e:
        railfem.load_plugin(str(path))
    assert str(e.value) == line


def test_a_model_files_activity_window_runs_as_the_command_runs_it(tmp_path):
    """`[analysis.window]` is honoured from Python: the files are the command's, byte for
    byte, and they are not those of the same file with the window off (the window holds
    blocks, which changes the answers at least by round-off)."""
    model = MODELS / "window_bridge.toml"
    cli_out, py_out, off_out = tmp_path / "cli", tmp_path / "py", tmp_path / "off"
    proc = cli("run", model, "--out", cli_out)
    assert proc.returncode == 0, proc.stderr
    assert "activity window" in proc.stdout, proc.stdout
    railfem.Model.from_file(model).run(out=py_out)
    text = model.read_text()
    assert 'mode = "on"\nahead = 66.0' in text
    off = tmp_path / "window_off.toml"
    off.write_text(text.replace('mode = "on"\nahead = 66.0', 'mode = "off"'))
    railfem.Model.from_file(off).run(out=off_out)
    csvs = sorted(p.name for p in cli_out.iterdir() if p.suffix == ".csv")
    assert csvs, list(cli_out.iterdir())
    for n in csvs:
        assert (cli_out / n).read_bytes() == (py_out / n).read_bytes(), n
    assert any((cli_out / n).read_bytes() != (off_out / n).read_bytes() for n in csvs)
