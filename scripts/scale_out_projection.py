#!/usr/bin/env python3
"""Cost model of the partitioned solver shared by P ranks (docs/scale-out.md, "Cost model
and projection"), fitted to the measured bench rows below and projected to 8-64 ranks and
10M DOF. Prints the table the page shows.

Per Newton iteration, milliseconds:

    T(P, N) = R(N) + Pr(N)/P + Prom + Bs(N)/P + Top(n_T(N)) + Comm(P, N)

R     replicated work, the same on every rank (search, elements, loads, other): r0 + r1*N
      (r0: the 96 wheels' contact, r1: the full-length vector passes);
Pr    the products with K, M, C ("assembly" phase): p0 + p1*N, divided among the ranks since
      each forms the residual of its own rows (Driver::keep_own_rows);
Prom  the promotions of the blocks under the train ("blocks" phase): a function of the
      train, not of N (measured 18.0 and 17.6 ms); done by the owners of the few blocks under
      the train, so not divided among the ranks;
Bs    block triangular solves ("solve" phase): b0 + b1*N, divided among the ranks;
Top   forming and factoring the top system on rank 0 ("top"): t0 + t1*n_T, with the top
      equations n_T = v + s*blocks (v: the carriages' bodies and promoted equations, s:
      separator equations per block) and blocks proportional to N (3000 interior equations
      a block). The blocks do not depend on P, so neither does the top system;
Comm  N_COLL collectives of latency ALPHA*ceil(log2 P) each, plus the bytes the busiest rank
      receives at bandwidth BETA: (P-1)/P * (c1*N + c2*n_T) (the interiors of the other ranks
      once per step, the block pieces and top vectors), fitted at P = 2.

Memory per rank: the larger of the build's peak B(P, N) = Br(N) + Bd(N)/P and the steady
state of the steps M(P, N) = Mr(N) + Mf(N)/P. Each rank splits the blocks on the pattern
and forms K, M, C on its own columns only (Driver::new_across_ranks), so part of the build
is divided: Br (replicated: the generated track, every node and element of the model —
today's elements, which issue 15's element work shrinks —, maps, the pattern's transient,
the splits) = 2*B2 - B1 and Bd (divided: the columns of K, M, C) = 2*(B1 - B2), from the
1-rank peak after the build B1 and the larger 2-rank one B2 at the sizes MEM_N. The steps:
Mr (replicated after the build: the track, the elements every rank keeps, state vectors,
maps, top system) = 2*M2 - M1 and Mf (divided: block factors, promotions, the columns of
the effective matrix and of K, M, C, the elements of the rank's rows) = 2*(M1 - M2) from
the 1-rank resident memory after the steps M1 and the larger 2-rank one M2, measured with
the residual and the elements per rank (docs/scale-out.md, "Memory per rank"). All four
are affine in N.

Every affine law goes through the two measured sizes exactly (two points, two parameters).
"""
import math

# Measured, one rank, ms per Newton iteration by phase: `railfem bench --case train-bridge
# --sizes 1e5` and `--sizes 1043430 --cars 12 --steps 20` of main 267f0e3 on a quiet machine
# (docs/performance.md, "Quiet re-timing after the evening's merges"; 2.00 iterations a step,
# the top chain condensed on one rank, the block solves from the factors' non-zeros).
N = [112542, 1043052]
BLOCKS = [37, 345]
R = [6.5, 22.2]      # search + elements + assembly + loads + other
PR = [1.8, 10.5]     # assembly (the products with K, M, C on their non-zeros), part of R
PROM = [1.4, 2.6]    # blocks
BS = [4.1, 13.6]     # solve
TOP = [4.9, 6.3]     # top (the reduced system of the top chain: 2 214 and 3 228 factored)
NT = [2592, 8166]    # top equations
# Two ranks: bytes received by the busiest rank per iteration (2.00 iterations a step), and
# memory (MiB, 2026-11-27 21:00-21:01, the MPI build of main db775c7: K, M, C formed on each
# rank's columns, light beams, block factors on their non-zeros): resident after the steps of
# one rank and of the larger of two ranks.
RECV2 = [669185, 4573650]
MEM_N = [112542, 1043052]
MEM1 = [366, 2444]
MEM2 = [273, 1781]
# The peak after the build (MiB, same runs, `mpirun -n 1` and the larger of `-n 2`).
BUILD1 = [252, 1875]
BUILD2 = [203, 1580]
# Assumed network: latency of one step of a collective, bandwidth (a 100 Gb/s fabric).
ALPHA = 2e-3  # ms
BETA = 10e9   # B/s
N_COLL = 6    # collectives per iteration (measured: 4, the norms of the own-rows residual,
              # and the energy balance's sums once per step)


def affine(x, y):
    """y = a + b*x through the two points."""
    b = (y[1] - y[0]) / (x[1] - x[0])
    return y[0] - b * x[0], b


def main():
    r0, r1 = affine(N, [r - pr for r, pr in zip(R, PR)])
    p0, p1 = affine(N, PR)
    b0, b1 = affine(N, BS)
    v, s = affine(BLOCKS, NT)
    t0, t1 = affine(NT, TOP)
    prom = sum(PROM) / 2
    per_block = N[1] / BLOCKS[1]
    # 2*RECV2 = c1*N + c2*n_T at the two sizes.
    y = [2 * x for x in RECV2]
    det = N[0] * NT[1] - NT[0] * N[1]
    c1 = (y[0] * NT[1] - NT[0] * y[1]) / det
    c2 = (N[0] * y[1] - N[1] * y[0]) / det
    mr0, mr1 = affine(MEM_N, [2 * m2 - m1 for m1, m2 in zip(MEM1, MEM2)])
    mf0, mf1 = affine(MEM_N, [2 * (m1 - m2) for m1, m2 in zip(MEM1, MEM2)])
    br0, br1 = affine(MEM_N, [2 * b2 - b1 for b1, b2 in zip(BUILD1, BUILD2)])
    bd0, bd1 = affine(MEM_N, [2 * (b1 - b2) for b1, b2 in zip(BUILD1, BUILD2)])
    print(f"R = {r0:.1f} ms + {r1 * 1e6:.1f} ms per 1e6 DOF; Pr = {p0:.1f} + {p1 * 1e6:.1f} per 1e6 DOF; Bs = {b0:.1f} + {b1 * 1e6:.1f} per 1e6 DOF; "
          f"Prom = {prom:.1f} ms")
    print(f"n_T = {v:.0f} + {s:.1f} per block; Top = {t0:.1f} ms + {t1 * 1e3:.2f} ms per 1000 top equations")
    print(f"busiest rank receives (P-1)/P * ({c1:.2f} B per DOF + {c2:.0f} B per top equation)")
    print(f"memory: replicated {mr0:.0f} MiB + {mr1 * 1e6:.0f} MiB per 1e6 DOF; "
          f"divided {mf0:.0f} MiB + {mf1 * 1e6:.0f} MiB per 1e6 DOF; "
          f"build peak: replicated {br0:.0f} MiB + {br1 * 1e6:.0f} MiB per 1e6 DOF, "
          f"divided {bd0:.0f} MiB + {bd1 * 1e6:.0f} MiB per 1e6 DOF")
    print()
    print("| DOF | ranks | top equations | ms/iteration | replicated | products / P | promotions | block solves / P | "
          "top (rank 0) | communication | received by the busiest rank | GiB per rank, steps | "
          "GiB per rank, build | GiB per rank, peak |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for n in [1e6, 1e7]:
        nt = v + s * n / per_block
        for p in [1, 2, 8, 16, 32, 64]:
            recv = (p - 1) / p * (c1 * n + c2 * nt)
            comm = N_COLL * ALPHA * math.ceil(math.log2(p)) + recv / BETA * 1e3 if p > 1 else 0.0
            parts = [r0 + r1 * n, (p0 + p1 * n) / p, prom, (b0 + b1 * n) / p, t0 + t1 * nt, comm]
            mem = (mr0 + mr1 * n + (mf0 + mf1 * n) / p) / 1024
            build = (br0 + br1 * n + (bd0 + bd1 * n) / p) / 1024
            peak = max(mem, build)
            print(f"| {n:.0e} | {p} | {nt:.0f} | {sum(parts):.0f} | {parts[0]:.0f} | {parts[1]:.1f} | "
                  f"{parts[2]:.0f} | {parts[3]:.1f} | {parts[4]:.0f} | {parts[5]:.1f} | {recv / 1e6:.1f} MB | "
                  f"{mem:.1f} | {build:.1f} | {peak:.1f} |")
    print()
    for n in [1e5, 1e6, 1e7]:
        nt = v + s * n / per_block
        top = t0 + t1 * nt
        bs = b0 + b1 * n
        print(f"N = {n:.0e}: top {top:.0f} ms, block solves {bs:.0f} ms: the top exceeds the divided "
              f"block solves from P = {bs / top:.1f}; replicated {r0 + r1 * n:.0f} ms, products {p0 + p1 * n:.0f} ms")


if __name__ == "__main__":
    main()
