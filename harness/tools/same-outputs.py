#!/usr/bin/env python3
"""Compares two `clipray reconcile --out` folders: report.json field by field with the
measurements of time left out (timings_ms, cpu_ms, first_round_*, analytic_over_raster), and
every other file (PNGs, summary.txt lines without timings) byte for byte; index.html (timings
and the command line) and the folder's lock file are left out. A refactoring that
claims "same outputs" runs the suite into two folders, before and after, and this prints
nothing and exits 0 when they match; otherwise it lists every difference and exits 1. Each
--without FIELD leaves that report.json field out too (screen_path: what only the screen path
writes, when its sweep is compared with the ray path's). --figures-within REL compares the
report's and summary's non-integer numbers within REL of themselves (summary lines in any order:
runs sorted by a figure may trade places) and the error heat maps and depth images within one
level per channel, everything else as before: the screen path's depth figures come
from its planes, within a hair of the ray path's (docs/reconcile.md).

usage: harness/tools/same-outputs.py [--without FIELD]... [--figures-within REL] BEFORE AFTER
"""
import json
import os
import re
import struct
import sys
import zlib

TIME_FIELDS = {"started_at", "command_line", "git_commit", "timings_ms", "cpu_ms", "first_round_timings_ms", "first_round_cpu_ms",
               "analytic_over_raster"}


def without_time(value, left_out=frozenset()):
    if isinstance(value, dict):
        return {k: without_time(v, left_out) for k, v in value.items()
                if k not in TIME_FIELDS and k not in left_out}
    if isinstance(value, list):
        return [without_time(v, left_out) for v in value]
    return value


def close(x, y, within):
    return x == y or abs(x - y) <= within * max(abs(x), abs(y))


def differences(a, b, path="", within=0.0):
    if type(a) is not type(b):
        yield f"{path or '/'}: {a!r} != {b!r}"
    elif isinstance(a, dict):
        for key in sorted(set(a) | set(b)):
            if key not in a or key not in b:
                yield f"{path}/{key}: only in {'after' if key not in a else 'before'}"
            else:
                yield from differences(a[key], b[key], f"{path}/{key}", within)
    elif isinstance(a, list):
        if len(a) != len(b):
            yield f"{path}: {len(a)} entries != {len(b)}"
        for i, (x, y) in enumerate(zip(a, b)):
            yield from differences(x, y, f"{path}/{i}", within)
    elif isinstance(a, float) and within > 0.0:
        if not close(a, b, within):
            yield f"{path}: {a!r} != {b!r} (beyond {within} of each other)"
    elif a != b:
        yield f"{path}: {a!r} != {b!r}"


NUMBER = re.compile(rb"-?\d+\.\d*(?:e[-+]?\d+)?|-?\d+e[-+]?\d+")


def lines_match(a, b, within):
    """Two summary lines: the same text, their decimal numbers within `within` of each other."""
    if within == 0.0 or NUMBER.sub(b"#", a) != NUMBER.sub(b"#", b):
        return a == b
    return all(close(float(x), float(y), within)
               for x, y in zip(NUMBER.findall(a), NUMBER.findall(b)))


def same_lines(a_lines, b_lines, within):
    """Line by line; with figures compared within a fraction, in any order too (summary.txt sorts
    its runs by a figure, and two runs whose figures lie that close may trade places)."""
    if len(a_lines) != len(b_lines):
        return False
    if all(lines_match(x, y, within) for x, y in zip(a_lines, b_lines)):
        return True
    if within == 0.0:
        return False
    unmatched = list(b_lines)
    for x in a_lines:
        match = next((k for k, y in enumerate(unmatched) if lines_match(x, y, within)), None)
        if match is None:
            return False
        del unmatched[match]
    return True


def png_rows(data):
    """The rows of an 8-bit, non-interlaced PNG (what clipray writes), unfiltered."""
    width = height = channels = 0
    compressed, at = b"", 8
    while at < len(data):
        length, kind = struct.unpack(">I4s", data[at:at + 8])
        chunk = data[at + 8:at + 8 + length]
        if kind == b"IHDR":
            width, height, _, colour = struct.unpack(">IIBB", chunk[:10])
            channels = {0: 1, 2: 3, 4: 2, 6: 4}[colour]
        elif kind == b"IDAT":
            compressed += chunk
        at += 12 + length
    raw, stride, rows, previous = zlib.decompress(compressed), width * channels, [], bytearray(width * channels)
    for y in range(height):
        kind, row = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            left = row[x - channels] if x >= channels else 0
            up, corner = previous[x], previous[x - channels] if x >= channels else 0
            if kind == 1:
                row[x] = (row[x] + left) & 255
            elif kind == 2:
                row[x] = (row[x] + up) & 255
            elif kind == 3:
                row[x] = (row[x] + (left + up) // 2) & 255
            elif kind == 4:
                p = left + up - corner
                nearest = min((abs(p - left), 0, left), (abs(p - up), 1, up), (abs(p - corner), 2, corner))[2]
                row[x] = (row[x] + nearest) & 255
        rows.append(bytes(row))
        previous = row
    return rows


def within_one_level(a, b):
    rows_a, rows_b = png_rows(a), png_rows(b)
    return len(rows_a) == len(rows_b) and all(
        len(x) == len(y) and all(abs(u - v) <= 1 for u, v in zip(x, y)) for x, y in zip(rows_a, rows_b))


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
    arguments, left_out, within = sys.argv[1:], set(), 0.0
    while len(arguments) >= 2 and arguments[0] in ("--without", "--figures-within"):
        if arguments[0] == "--without":
            left_out.add(arguments[1])
        else:
            try:
                within = float(arguments[1])
            except ValueError:
                within = -1.0
            if not 0.0 < within < 1.0:
                print(f"--figures-within: expected a fraction between 0 and 1, got {arguments[1]!r}",
                      file=sys.stderr)
                return 2
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
            problems += [f"{name}{d}" for d in differences(a, b, within=within)]
        elif name.endswith(".txt"):
            with open(a_path, "rb") as fa, open(b_path, "rb") as fb:
                a_lines = [TIMING_TAIL.sub(b"", l) for l in fa.read().splitlines()]
                b_lines = [TIMING_TAIL.sub(b"", l) for l in fb.read().splitlines()]
            if not same_lines(a_lines, b_lines, within):
                problems.append(f"{name}: text differs")
        else:
            with open(a_path, "rb") as fa, open(b_path, "rb") as fb:
                a_bytes, b_bytes = fa.read(), fb.read()
            # The heat maps and depth images are drawn from the figures and depths (the depth
            # images over one range both sides share); mismatch.png, from the classes, is exact.
            drawn = name.endswith("heatmap.png") or name.endswith("depth.png")
            if a_bytes != b_bytes and not (within > 0.0 and drawn
                                           and within_one_level(a_bytes, b_bytes)):
                problems.append(f"{name}: bytes differ")
    for p in problems:
        print(p)
    print(f"{len(names)} files compared, {len(problems)} differences", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
