#!/usr/bin/env python3
"""Compares two outputs of `cargo bench --bench stress` row by row with the
run time left out: every case's unknowns, increments, iterations (median,
largest), solves, bisections, failures and checks must be the same.

    python3 scripts/compare_stress.py OLD.log NEW.log

Prints the rows that differ (old, then new) and exits 1 if any does."""
import difflib
import re
import sys

# The run time: the first number with three decimals standing alone.
TIME = re.compile(r"\s+\d+\.\d{3}\s+")
NOISE = ("   Compiling", "    Finished", "     Running", "    Building", "EXIT", "warning", "  Downloaded")


def rows(path):
    out = []
    for line in open(path):
        line = line.rstrip("\n")
        if not line.strip() or line.startswith(NOISE):
            continue
        out.append(TIME.sub(" T ", line, count=1))
    return out


def main():
    old, new = rows(sys.argv[1]), rows(sys.argv[2])
    diff = [d for d in difflib.unified_diff(old, new, lineterm="", n=0) if not d.startswith(("---", "+++"))]
    print(f"{len(old)} rows against {len(new)}; {sum(d.startswith('+') for d in diff)} differ")
    for d in diff:
        print(d)
    sys.exit(1 if diff else 0)


if __name__ == "__main__":
    main()
