#!/usr/bin/env python3
"""Checks that clipray's internal layers only include downwards (docs/design.md, "Layers").

Each folder under harness/clipray/ is a layer; a file may include headers of its own layer and of
the layers listed below it, never of one above. The public headers (harness/include/clipray/)
include only each other. Prints every include that breaks this, with file and line, and exits 1;
prints nothing and exits 0 when the layering holds.

usage: harness/tools/check-layers.py [REPOSITORY_ROOT]
"""
import os
import re
import sys

# Lowest first. A layer may use every layer before it in this list.
LAYERS = [
    "io",         # files a user names, located JSON, staged writes, the output folder, deflate, XML
    "util",       # option values, frame buffers, huge pages, the phase clock, the kernel choice
    "math",       # projection builders, the conventions
    "rays",       # ray generation, the quad-precision reference, picking in an app's window
    "scene",      # the scene format, mesh files, primitives, terrain
    "intersect",  # watertight triangles, analytic primitives, BVH, packets, screen bins
    "compare",    # frames, the tolerance model, the per-pixel comparison
    "report",     # report.json, the summary, index.html, the images, JUnit
    "check",      # clipray check: reading a matrix, the findings
    "trace",      # apitrace dumps: the GL state of each draw, uniform buffers, replayed depth
    "page",       # WebGL pages: headless chromium over the DevTools pipe, the recorder, --page
    "gl",         # the headless contexts, the renderer, the app's render function
    "engine",     # the reconcile plan and runner, check --verify, the current-state check
]
INCLUDE = re.compile(r'^\s*#\s*include\s+"clipray/([^"]+)"')


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..")
    internal = os.path.join(root, "harness", "clipray")
    public = os.path.join(root, "harness", "include", "clipray")
    problems = []
    folders = sorted(f for f in os.listdir(internal) if os.path.isdir(os.path.join(internal, f)))
    for folder in folders:
        if folder not in LAYERS:
            problems.append(f"harness/clipray/{folder}/: a folder that is not a layer in {__file__}")
    for folder, _, names in os.walk(internal):
        layer = os.path.relpath(folder, internal).split(os.sep)[0]
        if layer not in LAYERS:
            continue
        for name in sorted(names):
            path = os.path.join(folder, name)
            with open(path, encoding="utf-8") as text:
                for number, line in enumerate(text, 1):
                    match = INCLUDE.match(line)
                    if not match or "/" not in match.group(1):
                        continue  # a public header: every layer may use it
                    used = match.group(1).split("/")[0]
                    if used in LAYERS and LAYERS.index(used) > LAYERS.index(layer):
                        shown = os.path.relpath(path, root)
                        problems.append(f"{shown}:{number}: {layer}/ includes {match.group(1)}, "
                                        f"a layer above it ({used}/)")
    for name in sorted(os.listdir(public)):
        path = os.path.join(public, name)
        with open(path, encoding="utf-8") as text:
            for number, line in enumerate(text, 1):
                match = INCLUDE.match(line)
                if match and "/" in match.group(1):
                    shown = os.path.relpath(path, root)
                    problems.append(f"{shown}:{number}: a public header includes the internal "
                                    f"clipray/{match.group(1)}")
    for problem in problems:
        print(problem)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
