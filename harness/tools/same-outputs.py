#!/usr/bin/env python3
"""Compares two `clipray reconcile --out` folders: report.json field by field with the
measurements of time left out (timings_ms, cpu_ms, first_round_*, analytic_over_raster), and
every other file (PNGs, summary.txt lines without timings) byte for byte; index.html (timings
and the command line) and the folder's lock file are left out. A refactoring that
claims "same outputs" runs the suite into two folders, before and after, and this prints
nothing and exits 0 when they match; otherwise it lists every difference and exits 1. Each
--without FIELD leaves that report.json field out too (screen_path: what only the screen path
writes, when its sweep is compared with the ray path's).

usage: harness/tools/same-outputs.py [--without FIELD]... BEFORE_DIR AFTER_DIR
"""
import json
import os
import re
import sys

TIME_FIELDS = {"started_at", "command_line", "git_commit", "timings_ms", "cpu_ms", "first_round_timings_ms", "first_round_cpu_ms",
               "analytic_over_raster"}


def without_time(value, left_out=frozenset()):
    if isinstance(value, dict):
        return {k: without_time(v, left_out) for k, v in value.items()
                if k not in TIME_FIELDS and k not in left_out}
    if isinstance(value, list):
        return [without_time(v, left_out) for v in value]
    return value


def differences(a, b, path=""):
    if type(a) is not type(b):
        yield f"{path or '/'}: {a!r} != {b!r}"
    elif isinstance(a, dict):
        for key in sorted(set(a) | set(b)):
            if key not in a or key not in b:
                yield f"{path}/{key}: only in {'after' if key not in a else 'before'}"
            else:
                yield from differences(a[key], b[key], f"{path}/{key}")
    elif isinstance(a, list):
        if len(a) != len(b):
            yield f"{path}: {len(a)} entries != {len(b)}"
        for i, (x, y) in enumerate(zip(a, b)):
            yield from differences(x, y, f"{path}/{i}")
    elif a != b:
        yield f"{path}: {a!r} != {b!r}"


# Not outputs of the runs: the output folder's lock, and the page that shows the timings and the
# command line (everything else on it comes from report.json, compared field by field).
NOT_COMPARED = {".clipray.lock", "index.html"}


def files_under(root):
    found = set()
    for folder, _, names in os.walk(root):
        for name in names:
            path = os.path.relpath(os.path.join(folder, name), root)
            if path not in NOT_COMPARED:
                found.add(path)
    return found


# summary.txt lines end with the run's timings; everything before them must match.
TIMING_TAIL = re.compile(rb"\s+(raster|ms|analytic).*$")


def main():
    arguments, left_out = sys.argv[1:], set()
    while len(arguments) >= 2 and arguments[0] == "--without":
        left_out.add(arguments[1])
        arguments = arguments[2:]
    if len(arguments) != 2 or arguments[0].startswith("--"):
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    before, after = arguments
    problems = []
    names = files_under(before) | files_under(after)
    for name in sorted(names):
        a_path, b_path = os.path.join(before, name), os.path.join(after, name)
        if not os.path.exists(a_path) or not os.path.exists(b_path):
            problems.append(f"{name}: only in {'before' if os.path.exists(a_path) else 'after'}")
            continue
        if name.endswith(".json"):
            with open(a_path) as fa, open(b_path) as fb:
                a = without_time(json.load(fa), left_out)
                b = without_time(json.load(fb), left_out)
            problems += [f"{name}{d}" for d in differences(a, b)]
        elif name.endswith(".txt"):
            with open(a_path, "rb") as fa, open(b_path, "rb") as fb:
                a_lines = [TIMING_TAIL.sub(b"", l) for l in fa.read().splitlines()]
                b_lines = [TIMING_TAIL.sub(b"", l) for l in fb.read().splitlines()]
            if a_lines != b_lines:
                problems.append(f"{name}: text differs")
        else:
            with open(a_path, "rb") as fa, open(b_path, "rb") as fb:
                if fa.read() != fb.read():
                    problems.append(f"{name}: bytes differ")
    for p in problems:
        print(p)
    print(f"{len(names)} files compared, {len(problems)} differences", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
