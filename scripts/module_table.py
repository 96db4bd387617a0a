#!/usr/bin/env python3
"""Print the module tables of docs/architecture.md: one row per source file of each
library crate, with the first sentence of its `//!` doc paragraph.

    python3 scripts/module_table.py > /tmp/modules.md

tests/architecture.rs checks that docs/architecture.md names every module file."""
import os
import re
import sys

CRATES = [
    ("railfem-framework", "framework/src"),
    ("railfem-elements", "elements/src"),
    ("railfem-solvers", "solvers/src"),
    ("railfem", "src"),
]


def first_sentence(path):
    lines = []
    with open(path, encoding="utf-8") as f:
        for line in f:
            s = line.strip()
            if s.startswith("//!"):
                t = s[3:].strip()
                if not t:
                    if lines:
                        break
                    continue
                lines.append(t)
            elif lines or (s and not s.startswith("#!") and not s.startswith("//")):
                break
    text = " ".join(lines)
    m = re.match(r"(.+?[.:;])(\s|$)", text)
    text = m.group(1) if m else text
    return text.replace("|", "\\|")


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "."
    for crate, src in CRATES:
        print(f"\n### `{crate}` (`{src}/`)\n")
        print("| module | what lives there |")
        print("|---|---|")
        base = os.path.join(root, src)
        for dirpath, dirnames, files in sorted(os.walk(base)):
            dirnames.sort()
            for f in sorted(files):
                if not f.endswith(".rs") or f.endswith(".orig"):
                    continue
                p = os.path.join(dirpath, f)
                rel = os.path.relpath(p, root)
                print(f"| `{rel}` | {first_sentence(p)} |")


if __name__ == "__main__":
    main()
