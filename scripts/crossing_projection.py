#!/usr/bin/env python3
"""Projects the wall time of the paper's whole crossing from two timed segments.

The paper's case (docs/performance.md, issue 16 item 2): 12 carriages at 80 m/s over 113
spans of 29.75 m, front carriage's centre starting 15 m before the bridge, run until the
last carriage has left it: duration (113 * 29.75 + 12 * 25 + 15) / 80 = 45.96 s. Two
`railfem bench --case train-bridge --sizes 1043430 --cars 12` runs give the per-step
timelines (`steps-<dofs>.csv`: t [s], iterations [-], halvings [-], block_factorizations
[-], wall [s]):

  ENTRY  from the default start (the train entering the viaduct), at least 5000 steps;
  MIDDLE from `--train-start X` with the whole train on the bridge (the steady running).

The crossing is split by what the wheels do:
  entry   while some carriage is still on the approach: t < (15 + cars * car) / v;
  exit    the same time span at the far end (wheels leaving the bridge onto the approach),
          taken to cost what the entry costs (the mirror of the same transition);
  middle  the rest, at the MIDDLE segment's mean cost per step.
Entry steps beyond the ENTRY segment are charged at the mean cost of its last quarter.

Usage: crossing_projection.py ENTRY/steps-N.csv MIDDLE/steps-N.csv [--dt 5e-4]
Prints a Markdown table. Standard library only.
"""
import argparse
import csv
import statistics


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    head, body = rows[0], rows[1:]
    col = {name.split(" [")[0]: j for j, name in enumerate(head)}
    return [
        {k: float(r[j]) for k, j in col.items()}
        for r in body
        if r
    ]


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("entry")
    p.add_argument("middle")
    p.add_argument("--dt", type=float, default=5e-4)
    p.add_argument("--spans", type=int, default=113)
    p.add_argument("--span", type=float, default=29.75)
    p.add_argument("--cars", type=int, default=12)
    p.add_argument("--car", type=float, default=25.0, help="carriage length (m)")
    p.add_argument("--speed", type=float, default=80.0)
    a = p.parse_args()

    entry, middle = read(a.entry), read(a.middle)
    duration = (a.spans * a.span + a.cars * a.car + 15.0) / a.speed
    steps_total = round(duration / a.dt)
    t_in = (15.0 + a.cars * a.car) / a.speed
    steps_in = round(t_in / a.dt)
    steps_mid = steps_total - 2 * steps_in

    wall_entry_measured = sum(r["wall"] for r in entry)
    late = entry[-len(entry) // 4 :]
    late_rate = statistics.fmean(r["wall"] for r in late)
    missing = max(steps_in - len(entry), 0)
    wall_entry = wall_entry_measured + missing * late_rate
    mid_rate = statistics.fmean(r["wall"] for r in middle)
    wall_mid = steps_mid * mid_rate
    total = 2 * wall_entry + wall_mid

    def its(rows):
        return statistics.fmean(r["iterations"] for r in rows)

    print(f"| part | steps | s per step | iterations per step | wall |")
    print(f"|---|---:|---:|---:|---:|")
    print(
        f"| entry, measured ({len(entry)} steps, t ≤ {entry[-1]['t']:.3f} s) | {len(entry)} | "
        f"{wall_entry_measured / len(entry):.3f} | {its(entry):.2f} | {wall_entry_measured / 60:.1f} min |"
    )
    print(
        f"| entry, rest (at its last quarter's rate) | {missing} | {late_rate:.3f} | {its(late):.2f} | "
        f"{missing * late_rate / 60:.1f} min |"
    )
    print(
        f"| middle (MIDDLE segment's mean, {len(middle)} steps) | {steps_mid} | {mid_rate:.3f} | "
        f"{its(middle):.2f} | {wall_mid / 3600:.2f} h |"
    )
    print(f"| exit (as the entry) | {steps_in} | – | – | {wall_entry / 60:.1f} min |")
    print(
        f"| **whole crossing** ({duration:.2f} s simulated) | {steps_total} | "
        f"{total / steps_total:.3f} | – | **{total / 3600:.2f} h** ({total / duration:.0f}× real time) |"
    )
    halvings = sum(r["halvings"] for r in entry) + sum(r["halvings"] for r in middle)
    refs = sum(r["block_factorizations"] for r in entry) + sum(
        r["block_factorizations"] for r in middle
    )
    print(f"\nhalvings in the segments: {halvings:.0f}; block factorizations: {refs:.0f}")


if __name__ == "__main__":
    main()
