"""railfem from Python: load or build a model, run it, get numpy arrays back.

The compiled module ``railfem._railfem`` does the work (the same library calls as the
``railfem`` command line, with the GIL released); this file wraps its raw dictionaries in
small result classes. See docs/python.md.

- ``Model.from_file(path)`` / ``Model.from_dict(dict)``; ``model.check()``;
  ``model.run(out=None)`` -> ``Result``.
- ``curve(...)``, ``critical_radius(...)``, ``train_bridge(...)``: the built-in cases.
- ``elements()``: the registered element kinds and their keys; ``load_plugin(path)``.

Errors: bad input raises ``ValueError`` with the command line's one-line message (the text
``railfem`` prints after ``error: ``); a step that cannot go on raises ``SolverError`` (a
``RuntimeError``); a panic inside Rust raises ``RuntimeError`` and the interpreter lives on.
"""

import warnings as _warnings

from . import _railfem
from ._railfem import SolverError, critical_radius, elements, load_plugin

__all__ = [
    "Model",
    "Recording",
    "Result",
    "SolverError",
    "critical_radius",
    "curve",
    "elements",
    "load_plugin",
    "train_bridge",
]


class Recording:
    """One recorder's history: ``time`` (n,), ``values`` (n, len(columns)), ``columns``.

    Time is the first axis. ``rec["1_uz [m]"]`` is one column (``rec["time"]`` the
    times); the names are the recorder's CSV header, units included, and a name without
    its unit finds the column too (``rec["1_uz"]``, ``rec["5_Q"]``). The values are the
    exact doubles of the run (the CSV rounds them to 13 significant digits).
    """

    def __init__(self, raw):
        self.file = raw["file"]
        self.columns = list(raw["columns"])
        self.time = raw["time"]
        self.values = raw["values"]
        self._index = {c: i for i, c in enumerate(self.columns)}
        for i, c in enumerate(self.columns):
            self._index.setdefault(c.split(" [")[0], i)

    def __getitem__(self, name):
        if name == "time":
            return self.time
        try:
            return self.values[:, self._index[name]]
        except KeyError:
            raise KeyError(
                f"{self.file}: no column {name!r}; columns: {', '.join(self.columns)}"
            ) from None

    def __contains__(self, name):
        return name == "time" or name in self._index

    def __len__(self):
        return len(self.time)

    def as_dict(self):
        """``{"time": ..., column: ...}``, one 1-D array per column."""
        d = {"time": self.time}
        d.update({c: self.values[:, i] for i, c in enumerate(self.columns)})
        return d

    def __repr__(self):
        return f"<Recording {self.file!r}: {len(self)} rows x {len(self.columns)} columns>"


class Result:
    """What ``Model.run`` returns.

    - ``recorders``: dict, recorder file name (``file`` in the model) -> ``Recording``;
      ``result["wheels.csv"]`` is the same.
    - ``energy``: a ``Recording`` of the energy ledger (``external_work``, ``kinetic``,
      ``strain``, ``damping``, ``friction``, ``material``, ``integrator``, J; as energy.csv), or ``None``
      for a static or modal analysis; ``energy_summary`` the block ``railfem run`` prints
      and ``energy_relative_error`` its largest |integrator|/energy.
    - ``stats``: steps, iterations, cuts, factorizations, symbolic, equations, wall (s)
      and timings (assembly, factor, solve, loads; s).
    - ``size``: the model's size as ``railfem check`` prints it; ``warnings``: the
      preflight's warnings (also issued as Python warnings); ``out``: the folder the CSV
      files went to, or ``None``.
    """

    def __init__(self, raw):
        self.recorders = {r["file"]: Recording(r) for r in raw["recorders"]}
        e = raw["energy"]
        self.energy = Recording(e) if e is not None else None
        self.energy_summary = e["summary"] if e is not None else None
        self.energy_relative_error = e["relative_error"] if e is not None else None
        self.stats = raw["stats"]
        self.size = raw["size"]
        self.warnings = list(raw["warnings"])
        self.out = raw["out"]

    def __getitem__(self, file):
        return self.recorders[file]

    def __repr__(self):
        s = self.stats
        return (
            f"<Result: {s['steps']} steps, {s['iterations']} Newton iterations, "
            f"{s['equations']} equations, {s['wall']:.3f} s; recorders {list(self.recorders)}>"
        )


def _warn(messages):
    for w in messages:
        _warnings.warn(w, stacklevel=3)


class Model:
    """A railfem model: ``Model.from_file(path)`` or ``Model.from_dict(d)``.

    It holds the description; ``check()`` and ``run()`` build it afresh each time through
    the same calls as ``railfem check`` and ``railfem run``.
    """

    def __init__(self, inner):
        self._inner = inner

    @classmethod
    def from_file(cls, path):
        """The model file at ``path`` (TOML or JSON, by extension), read by each
        ``check()`` and ``run()``."""
        return cls(_railfem.Model.from_file(str(path)))

    @classmethod
    def from_dict(cls, data, name="model", base=None):
        """A model from a dict with the keys of a model file (docs/model-format.md).

        ``name`` stands for the file name in messages; ``base`` is the folder relative
        plugin paths start from (default: the current directory).
        """
        return cls(
            _railfem.Model.from_dict(data, name, None if base is None else str(base))
        )

    @property
    def name(self):
        """The name messages use: the path as given, or the dict's ``name``."""
        return self._inner.name

    def check(self):
        """Everything ``railfem check`` checks; returns ``{"size", "warnings"}``.

        Raises ``ValueError`` with the lines ``railfem check`` prints after ``error: ``.
        """
        r = self._inner.check()
        _warn(r["warnings"])
        return r

    def run(self, out=None):
        """Runs the model (GIL released) and returns a ``Result``; with ``out``, also
        writes the CSV files ``railfem run --out`` writes."""
        raw = self._inner.run(None if out is None else str(out))
        _warn(raw["warnings"])
        return Result(raw)

    def __repr__(self):
        return repr(self._inner)


def curve(
    *,
    speed=None,
    radius=None,
    ct=None,
    mu=None,
    dt=None,
    penalty=None,
    duration=None,
    lengths=None,
    quick=False,
    geometry="linear",
    anti_roll=None,
    out=None,
):
    """The paper's curved-track case (Fig. 6), as ``railfem curve``.

    Keywords (defaults as the command's): ``speed`` (m/s, 80), ``radius`` (m, 6250),
    ``ct`` (m, 200), ``mu`` (0.3), ``dt`` (s, 0.01), ``penalty`` (N/m, 1e10),
    ``duration`` (s, 0 = to the end of the track), ``lengths`` (five segment lengths, m),
    ``quick`` (the short track of ``--quick``), ``geometry`` ("linear"/"nonlinear"),
    ``anti_roll`` (N·m/rad), ``out`` (folder: curve.csv, curve.svg, case.json).

    Returns a dict: ``time``, ``station`` (n,); ``wheel_names`` (``w1L``, ``w1R``, ...,
    left = inner on this left-hand curve) and ``inner`` (bool per wheel); ``wheels``: per
    quantity an (n, wheels) array named as the curve.csv columns (``Q_fe``, ``Y_fe``,
    ``Q_statics``, ``Q_printed``, ``Y_theory``, ``Q_lean``, ``station``, ``radius``,
    ``cant``, ``n_contact``, ``n_slide``; N, m, rad); ``metrics``: the numbers the command
    prints (largest relative differences FE vs theory on the arc, settled-arc means);
    ``stats``; ``energy_summary``; ``case`` (the inputs).
    """
    return _railfem.curve(
        speed=speed,
        radius=radius,
        ct=ct,
        mu=mu,
        dt=dt,
        penalty=penalty,
        duration=duration,
        lengths=lengths,
        quick=quick,
        geometry=geometry,
        anti_roll=anti_roll,
        out=None if out is None else str(out),
    )


def train_bridge(
    *,
    cars=None,
    spans=None,
    span=None,
    element_length=None,
    dof=None,
    speed=None,
    radius=None,
    ct=None,
    duration=None,
    dt=None,
    record_every=None,
    pier_height=None,
    midspans=None,
    quake=None,
    seed=1,
    pga=0.3,
    quake_duration=30.0,
    geometry="linear",
    steps=None,
    out=None,
):
    """The train on a viaduct, as ``railfem train-bridge`` (the same options, with
    ``_`` for ``-``; the defaults are the command's 1M-DOF case, so give ``cars``,
    ``spans`` and ``steps`` for a small run). ``quake`` is a record's path or
    ``"synthetic"`` (with ``seed``, ``pga``, ``quake_duration``).

    Returns a dict: ``dofs``, ``elements``, ``nodes``, ``element_length``,
    ``build_seconds``; ``wheel_names``, ``q_static`` (N); ``wheels``: per wheel
    ``max_yq``, ``max_dqq``, ``min_q`` (N), ``mean_q`` (N) and the times ``t_...`` (s);
    ``midspan``: span number (1-based) -> ``Recording`` with the column ``deflection``
    (girder midspan relative to the span's ends, m, positive down); ``stats``.
    """
    r = _railfem.train_bridge(
        cars=cars,
        spans=spans,
        span=span,
        element_length=element_length,
        dof=dof,
        speed=speed,
        radius=radius,
        ct=ct,
        duration=duration,
        dt=dt,
        record_every=record_every,
        pier_height=pier_height,
        midspans=midspans,
        quake=None if quake is None else str(quake),
        seed=seed,
        pga=pga,
        quake_duration=quake_duration,
        geometry=geometry,
        steps=steps,
        out=None if out is None else str(out),
    )
    r["midspan"] = {k: Recording(v) for k, v in r["midspan"].items()}
    return r
