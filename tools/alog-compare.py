#!/usr/bin/env python3
"""Compares two alogs (or two folders of them, by file name) of the same mission:

    tools/alog-compare.py <before.alog|dir> <after.alog|dir>

For each pair it prints: the lines that differ (lines only in one of them, as `diff` marks
them), the helm's decisions (DESIRED_HEADING/SPEED/DEPTH): how many postings differ and by
how much at most (heading difference taken around the circle), each matched by time and order,
and the mission's progress: the times at which WPT_INDEX and MISSION change value, with the
first place the two sequences part. Exit status 0; it reports, it does not judge.
"""
import os
import subprocess
import sys
from collections import defaultdict

DECISIONS = ("DESIRED_HEADING", "DESIRED_SPEED", "DESIRED_DEPTH")
PROGRESS = ("WPT_INDEX", "MISSION")


def records(path):
    """(time, var, source, value) per data line, header lines skipped."""
    out = []
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            if line.startswith("%"):
                continue
            parts = line.split(None, 3)
            if len(parts) < 4:
                continue
            try:
                t = float(parts[0])
            except ValueError:
                continue
            out.append((t, parts[1], parts[2], parts[3].strip()))
    return out


def changed_lines(a, b):
    """Lines only in one of the two files (`diff` lines marked < or >; the `%%` header, which
    names the log's folder, left out), and the line count."""
    cmd = ["diff", "--ignore-matching-lines=^%", a, b]
    out = subprocess.run(cmd, capture_output=True, text=True, errors="replace").stdout
    n = sum(1 for line in out.splitlines() if line[:2] in ("< ", "> ") and line[2:3] != "%")
    with open(a, "rb") as f:
        total = sum(1 for _ in f)
    return n, total


def series(recs, var):
    return [(t, v) for (t, name, _src, v) in recs if name == var]


def num(v):
    try:
        return float(v)
    except ValueError:
        return None


def decision_diff(ra, rb, var):
    """Postings compared by (time, rank at that time); returns (count differing, max |delta|,
    time of the max, postings only in one)."""
    def keyed(s):
        seen = defaultdict(int)
        out = {}
        for t, v in s:
            k = (t, seen[t])
            seen[t] += 1
            out[k] = v
        return out
    ka, kb = keyed(series(ra, var)), keyed(series(rb, var))
    differ, worst, at = 0, 0.0, None
    for k in ka.keys() & kb.keys():
        x, y = num(ka[k]), num(kb[k])
        if x is None or y is None:
            if ka[k] != kb[k]:
                differ += 1
            continue
        d = abs(x - y)
        if var == "DESIRED_HEADING":
            d = min(d % 360.0, 360.0 - d % 360.0)
        if d > 0:
            differ += 1
            if d > worst:
                worst, at = d, k[0]
    only = len(ka.keys() ^ kb.keys())
    return differ, worst, at, only, len(ka)


def changes(recs, var):
    out, last = [], None
    for t, v in series(recs, var):
        if v != last:
            out.append((t, v))
            last = v
    return out


def compare(a, b, name):
    ra, rb = records(a), records(b)
    n, total = changed_lines(a, b)
    print(f"== {name}: {n} of {total} lines differ")
    for var in DECISIONS:
        differ, worst, at, only, count = decision_diff(ra, rb, var)
        if count == 0 and only == 0:
            continue
        where = f" (largest {worst:.4g} at t={at:.2f})" if differ else ""
        print(f"   {var}: {differ} of {count} postings differ{where}; {only} unmatched")
    for var in PROGRESS:
        ca, cb = changes(ra, var), changes(rb, var)
        if not ca and not cb:
            continue
        if ca == cb:
            seq = ", ".join(f"{v}@{t:.2f}" for t, v in ca)
            print(f"   {var}: same changes ({len(ca)}): {seq}")
        else:
            first = next((i for i, (x, y) in enumerate(zip(ca, cb)) if x != y), min(len(ca), len(cb)))
            same_vals = [v for _, v in ca] == [v for _, v in cb]
            shift = max((abs(x[0] - y[0]) for x, y in zip(ca, cb)), default=0.0)
            print(f"   {var}: {len(ca)} vs {len(cb)} changes, first differs at #{first}; "
                  f"same value sequence: {same_vals}; largest time shift {shift:.2f} s")
            for label, c in (("before", ca), ("after", cb)):
                print(f"      {label}: " + ", ".join(f"{v}@{t:.2f}" for t, v in c))


def main():
    if len(sys.argv) != 3:
        print(__doc__.strip(), file=sys.stderr)
        sys.exit(2)
    a, b = sys.argv[1], sys.argv[2]
    if os.path.isdir(a):
        for name in sorted(os.listdir(a)):
            if name.endswith(".alog") and os.path.exists(os.path.join(b, name)):
                compare(os.path.join(a, name), os.path.join(b, name), name)
    else:
        compare(a, b, os.path.basename(a))


if __name__ == "__main__":
    main()
