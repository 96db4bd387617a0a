#!/usr/bin/env python3
"""Writes examples/bridge-check/viaduct10.toml: a 10-span continuous concrete viaduct
(10 x 25 m) of beam3d elements, 10 elements per span, for `railfem bridge-check`
(examples/bridge-check/viaduct10-plan.toml, docs/bridge-check.md).

Usage: python3 scripts/bridge_viaduct.py > examples/bridge-check/viaduct10.toml
"""

SPANS, SPAN, PER = 10, 25.0, 10
# Deck section (SI): E = 35 GPa, G = 14.6 GPa; A = 8 m^2 and rho = 2500 kg/m^3 give
# 20 t/m (the structure with ballast and track smeared into it); Iy = 6 m^4 (vertical
# bending, EI = 2.1e11 N m^2), Iz = 40 m^4 (lateral), J = 10 m^4.
SECTION = dict(E=35e9, G=14.6e9, A=8.0, Iy=6.0, Iz=40.0, J=10.0, rho=2500.0)

print("# A 10-span continuous viaduct (10 x 25 m), beam3d, consistent mass: the deck path is")
print("# elements 1..100. Written by scripts/bridge_viaduct.py; checked by")
print("# `railfem bridge-check examples/bridge-check/viaduct10-plan.toml`.")
print("# Supports: node 0 pinned (ux, uy, uz, rx); every other pier and the far abutment on")
print("# rollers (uy, uz, rx).")
print()
print('[analysis]\nkind = "transient"\nintegrator = "newmark"\ndt = 0.001\nduration = 0.01')
n = SPANS * PER
for i in range(n + 1):
    x = SPAN * i / PER
    print(f"\n[[node]]\nid = {i}\nxyz = [{x:.6g}, 0.0, 0.0]")
    if i == 0:
        print('fix = ["ux", "uy", "uz", "rx"]')
    elif i % PER == 0:
        print('fix = ["uy", "uz", "rx"]')
for e in range(1, n + 1):
    print(f'\n[[element]]\ntype = "beam3d"\nid = {e}\nnodes = [{e - 1}, {e}]')
    for k, v in SECTION.items():
        print(f"{k} = {v}")
    print('mass = "consistent"')
