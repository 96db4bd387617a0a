"""The paper's Fig. 6 case from Python: Q of the leading wheelset's inner and outer wheel.

    python python/examples/fig6_q.py [OUT.svg]

Runs `railfem.curve()` (V = 80 m/s, R = 6250 m, Ct = 200 m; the whole 16 km track) and
plots the FE normal contact force of wheels w1L (inner, this is a left-hand curve) and w1R
(outer) against the rigid-body statics of the paper's Section 3. docs/python.md walks
through it; docs/figures/python-fig6-q.svg is its output.
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import railfem  # noqa: E402

out = sys.argv[1] if len(sys.argv) > 1 else "python-fig6-q.svg"

r = railfem.curve(speed=80.0, radius=6250.0, ct=200.0)  # the Fig. 6 case
t = r["time"]  # s, one entry per recorded step
q = r["wheels"]["Q_fe"] / 1e3  # kN, shape (steps, wheels)
q_statics = r["wheels"]["Q_statics"] / 1e3  # kN, the paper's Section 3 (statics)
inner = r["inner"].index(True)  # w1L: the leading wheelset's inner wheel
outer = r["inner"].index(False)  # w1R: its outer wheel

fig, ax = plt.subplots(figsize=(9, 4.5))
ax.plot(t, q[:, outer], color="tab:red", lw=3, alpha=0.6, label=f"outer wheel ({r['wheel_names'][outer]}), FE")
ax.plot(t, q[:, inner], color="tab:blue", lw=3, alpha=0.6, label=f"inner wheel ({r['wheel_names'][inner]}), FE")
# The theory on top, thin and dashed: it lies on the FE curves.
ax.plot(t, q_statics[:, outer], color="k", ls="--", lw=0.9, label="statics (Section 3)")
ax.plot(t, q_statics[:, inner], color="k", ls="--", lw=0.9)
ax.set_xlabel("time t [s]")
ax.set_ylabel("normal contact force Q [kN]")
ax.set_title("Fig. 6 case: V = 80 m/s, R = 6250 m, Ct = 200 m")
ax.grid(alpha=0.3)
ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)  # beside the data
fig.savefig(out, bbox_inches="tight")

m = r["metrics"]
print(f"{r['stats']['steps']} steps in {r['stats']['wall']:.1f} s; on the settled arc: "
      f"mean Q inner {m['arc_mean_normal_inner']:.1f} N, outer {m['arc_mean_normal_outer']:.1f} N; "
      f"largest |FE - statics| / statics {m['max_rel_normal_statics']:.2e}")
