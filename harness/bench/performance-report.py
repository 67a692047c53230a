#!/usr/bin/env python3
"""Writes docs/performance.md from a fresh run of the benchmarks and reconciles it quotes.

usage: harness/bench/performance-report.py [--build DIR] [--out FILE] [--quick]

Runs, in order (about 12 minutes on the 2-core development machine; --quick: about 2, smaller
frames and fewer repetitions, for checking the script itself, never for the page):
  1. every shipped scene at 1920x1080, D32F, world vertices, with --rounds (steady medians);
  2. the 100k-triangle terrain in steady state, several processes, wall and CPU time;
  3. the analytic primitives' float rays against the CPU's double rays (report by_kind);
  4. `clipray bench` on every hard case and the Google Benchmark ray rows side by side;
  5. `clipray_intersect_bench`: the intersection side by side with Embree, and its scaling;
  6. the screen path (--analytic screen) against the ray path, one thread, the
     analytic phases side by side (screen_path.py);
  7. the terrain multisampled: 4 samples against 1, the analytic time of a frame's sample runs
     summed against the single-sample run's;
  8. a real program's 1080p frame captured with RenderDoc, checked, verified and reconciled
     (capture_timings.py; skipped with a line saying why where RenderDoc or the program is
     missing);
  9. where the analytic CPU time goes, from `perf record` samples (analytic_profile.py; skipped
     with a line saying why where perf cannot record).
Every table is computed here from what those commands print or write; the page's prose says
what the columns mean, never a figure of its own. The machine, date and commit go on top.
"""
import argparse
import datetime
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile

from analytic_profile import profile_section
from capture_timings import capture_section
from screen_path import screen_path_section

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PHASES = ["raster", "readback", "rays", "intersect", "compare"]


def run(command, **kwargs):
    """Runs a command from the repository root; returns its stdout. Exit status 1 (an
    inconsistent reconcile) is data, not a failure of the script."""
    print("+ " + " ".join(command), file=sys.stderr, flush=True)
    result = subprocess.run(command, cwd=ROOT, stdout=subprocess.PIPE, text=True, **kwargs)
    if result.returncode not in (0, 1):
        sys.exit(f"performance-report: {command[0]} exited {result.returncode}")
    return result.stdout


def fmt(value, digits=3):
    if value is None:
        return "-"
    if value == 0:
        return "0"
    if abs(value) >= 100:
        return f"{value:.0f}"
    if abs(value) >= 0.01:
        return f"{value:.{digits}g}" if abs(value) < 10 else f"{value:.1f}"
    return f"{value:.2e}"


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def machine_lines(gl):
    model = "unknown CPU"
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    with open("/proc/meminfo") as f:
        memory_kib = int(f.readline().split()[1])
    debian = open("/etc/debian_version").read().strip() if os.path.exists(
        "/etc/debian_version") else platform.platform()
    commit = run(["git", "rev-parse", "--short", "HEAD"]).strip()
    dirty = run(["git", "status", "--porcelain", "--untracked-files=no"]).strip()
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    return (f"Machine: {model}, {os.cpu_count()} cores, {memory_kib / 1048576:.0f} GiB, "
            f"Debian {debian}, {gl['renderer']} ({gl['version']}). Date: {now}. "
            f"Commit: `{commit}{' (with uncommitted changes)' if dirty else ''}`.")


def reconcile(build, out, arguments):
    run([os.path.join(build, "clipray"), "reconcile", "--out", out] + arguments,
        stderr=subprocess.DEVNULL)
    with open(os.path.join(out, "report.json")) as f:
        return json.load(f)


def worst(values):
    """The largest of the figures that exist (a case without rays has none)."""
    present = [v for v in values if v is not None]
    return max(present) if present else None


def analytic(timings):
    return timings["rays"] + timings["intersect"] + timings["compare"]


def suite_section(build, work, quick):
    size = "480x270" if quick else "1920x1080"
    rounds = "2" if quick else "5"
    arguments = ["--size", size, "--depth-formats", "32f", "--rounds", rounds]
    report = reconcile(build, os.path.join(work, "suite"), arguments)
    rows, wall_ratios, cpu_ratios = [], [], []
    for r in report["runs"]:
        t, c = r["timings_ms"], r["cpu_ms"]
        cpu_ratio = analytic(c) / c["raster"] if c["raster"] > 0 else None
        wall_ratios.append(r["analytic_over_raster"])
        if cpu_ratio is not None:
            cpu_ratios.append(cpu_ratio)
        rows.append([f"{r['scene']}/{r['camera']}", r["convention"]] +
                    [fmt(t[p]) for p in ("raster", "readback", "intersect", "compare")] +
                    [fmt(r["analytic_over_raster"]), fmt(cpu_ratio), r["verdict"]])
    consistent = report["summary"]["consistent"]
    text = (f"`clipray reconcile {' '.join(arguments)}`: every run made {rounds} times in one "
            f"process, the medians of rounds 2-{rounds} (milliseconds, wall time; the analytic "
            f"pass on all cores). {consistent} of {len(rows)} runs consistent. The ratio "
            f"(rays + intersect + compare) / raster is {fmt(min(wall_ratios))}-"
            f"{fmt(max(wall_ratios))} in wall time (median {fmt(statistics.median(wall_ratios))})"
            f" and {fmt(min(cpu_ratios))}-{fmt(max(cpu_ratios))} in CPU time (median "
            f"{fmt(statistics.median(cpu_ratios))}).\n\n")
    header = ["scene/camera", "conv", "raster", "readback", "intersect", "compare", "ratio, wall",
              "ratio, CPU", "verdict"]
    return report["gl"], text + table(header, rows)


def terrain_section(build, work, quick):
    processes = 1 if quick else 3
    size = "480x270" if quick else "1920x1080"
    rounds = "3" if quick else "9"
    arguments = ["scenes/terrain_100k.json", "--size", size, "--depth-formats", "32f",
                 "--conventions", "no,zo", "--rounds", rounds]
    per_conv = {}
    for p in range(processes):
        report = reconcile(build, os.path.join(work, f"terrain{p}"), arguments)
        for r in report["runs"]:
            per_conv.setdefault(r["convention"], []).append(r)
    rows = []
    for conv, runs in per_conv.items():
        row = [conv]
        for phase in ("raster", "intersect", "compare"):
            wall = statistics.median(r["timings_ms"][phase] for r in runs)
            cpu = statistics.median(r["cpu_ms"][phase] for r in runs)
            row += [fmt(wall), fmt(cpu), fmt(cpu / wall if wall else None)]
        wall_ratio = [r["analytic_over_raster"] for r in runs]
        cpu_ratio = [analytic(r["cpu_ms"]) / r["cpu_ms"]["raster"] for r in runs]
        row += [f"{fmt(statistics.median(wall_ratio))} ({fmt(min(wall_ratio))}-"
                f"{fmt(max(wall_ratio))})",
                f"{fmt(statistics.median(cpu_ratio))} ({fmt(min(cpu_ratio))}-"
                f"{fmt(max(cpu_ratio))})"]
        rows.append(row)
    header = ["conv", "raster: wall", "CPU", "cores", "intersect: wall", "CPU", "cores",
              "compare: wall", "CPU", "cores", "ratio, wall", "ratio, CPU"]
    text = (f"`clipray reconcile {' '.join(arguments)}` in {processes} processes; per process "
            f"the medians of rounds 2-{rounds}, then the median over the processes "
            f"(milliseconds; \"cores\" is CPU time over wall time; the ratios' range over the "
            f"processes in brackets).\n\n")
    return text + table(header, rows)


def multisample_section(build, work, quick):
    size = "480x270" if quick else "1920x1080"
    rounds = "2" if quick else "5"
    base = ["scenes/terrain_100k.json", "--size", size, "--depth-formats", "32f",
            "--conventions", "zo", "--rounds", rounds]
    single = reconcile(build, os.path.join(work, "msaa1"), base)["runs"]
    sampled = reconcile(build, os.path.join(work, "msaa4"), base + ["--samples", "4"])["runs"]
    one = single[0]
    rows = [["1", fmt(one["timings_ms"]["raster"]), fmt(one["timings_ms"]["readback"]),
             fmt(analytic(one["timings_ms"])), "1", one["verdict"]]]
    total = sum(analytic(r["timings_ms"]) for r in sampled)
    verdicts = sorted({r["verdict"] for r in sampled})
    rows.append([str(len(sampled)), fmt(sampled[0]["timings_ms"]["raster"]),
                 fmt(sampled[0]["timings_ms"]["readback"]), fmt(total),
                 fmt(total / analytic(one["timings_ms"])), ", ".join(verdicts)])
    text = (f"`clipray reconcile {' '.join(base)}` with and without `--samples 4`, one process "
            f"each, the medians of rounds 2-{rounds} (milliseconds, wall time). A multisampled "
            f"frame is drawn and read once (raster and readback: every sample's copy through "
            f"texelFetch included) and each sample is traced and compared as a frame of its own "
            f"(rays through its position): its analytic time is the sum over the sample runs, "
            f"and the last column is that sum over the single-sample run's.\n\n")
    header = ["samples", "raster", "readback", "analytic", "analytic / 1 sample", "verdicts"]
    return text + table(header, rows)


def primitives_section(build, work):
    scenes = ["primitives", "spheres_across_scales", "sphere_touching_near", "box_edge_on",
              "nested_spheres"]
    arguments = [f"scenes/{s}.json" for s in scenes] + ["--size", "320x240", "--depth-formats",
                                                         "32f", "--conventions", "no,zo"]
    report = reconcile(build, os.path.join(work, "primitives"), arguments)
    kinds = {}
    for r in report["runs"]:
        for kind, figures in (r.get("by_kind") or {}).items():
            k = kinds.setdefault(kind, {"quanta": 0.0, "rel": 0.0, "ratio": 0.0, "pixels": 0})
            k["quanta"] = max(k["quanta"], figures["depth_error_quanta"]["max"] or 0.0)
            k["rel"] = max(k["rel"], figures["distance_rel_error"]["max"] or 0.0)
            k["ratio"] = max(k["ratio"], figures["tolerance_ratio"]["max"] or 0.0)
            k["pixels"] += figures["depth_compared"]
    rows = [[kind, k["pixels"], fmt(k["quanta"]), fmt(k["rel"]), fmt(k["ratio"])]
            for kind, k in sorted(kinds.items())]
    consistent = report["summary"]["consistent"]
    text = (f"`clipray reconcile {' '.join(arguments)}`: {consistent} of "
            f"{report['summary']['runs']} runs consistent; per kind, the worst over all runs.\n\n")
    return text + table(["kind", "pixels compared", "depth error max (quanta)",
                         "distance error max (relative)", "tolerance ratio max"], rows)


def ray_methods_section(build, work, quick):
    rows_path = os.path.join(work, "bench.json")
    arguments = ["--size", "480x270" if quick else "1920x1080", "--json", rows_path]
    if quick:
        arguments += ["--cases", "standard,eye_1e7"]
    run([os.path.join(build, "clipray"), "bench"] + arguments, stderr=subprocess.DEVNULL)
    with open(rows_path) as f:
        rows = json.load(f)["rows"]
    shown_cases = ["standard", "seed002_renderer", "eye_1e7", "infinite_far_eye_mmm", "ortho_far",
                   "telephoto"]
    shown_methods = ["unproject_glm", "two_point", "full", "robust"]
    selected = []
    for r in rows:
        if r["convention"] != "no" or r["case"] not in shown_cases:
            continue
        if r["method"] in shown_methods and (r["precision"] == "float" or r["method"] == "robust"):
            label = r["method"] + (" (double)" if r["precision"] == "double" else "")
            selected.append([r["case"], label, fmt(r["ns_per_ray"]),
                             fmt(r["angle_err_px"]["max"]), fmt(r["origin_lateral_err_px"]["max"]),
                             r["nonfinite"], r["backward"], fmt(r["floor_angle_px"]),
                             fmt(r["floor_output_angle_px"])])
    robust = [r for r in rows if r["method"] == "robust" and r["precision"] == "float"]
    worst_over_floor = worst(
        r["angle_err_px"]["max"] / max(r["floor_angle_px"], r["floor_output_angle_px"])
        for r in robust if r["angle_err_px"]["max"] is not None)
    double = [r for r in rows if r["method"] == "robust" and r["precision"] == "double"]
    shown = [a for a in arguments if a not in ("--json", rows_path)]
    text = (f"`clipray bench {' '.join(shown)} --json FILE` "
            f"(float rows unless marked; NO shown; errors in pixels; `floor`: what storing the "
            f"matrix in float costs, `out floor`: what storing the exact direction in float "
            f"costs). Over all {len(robust)} case x convention rows, `robust` float's worst angle "
            f"is at most {fmt(worst_over_floor)}x the larger floor, with "
            f"{sum(r['nonfinite'] + r['backward'] for r in robust)} non-finite or backward rays; "
            f"`robust` double's worst angle is "
            f"{fmt(worst(r['angle_err_px']['max'] for r in double))} px and worst lateral origin "
            f"error {fmt(worst(r['origin_lateral_err_px']['max'] for r in double))} px.\n\n")
    header = ["case", "method", "ns/ray", "angle max", "origin max", "non-finite", "backward",
              "floor", "out floor"]
    return text + table(header, selected)


def google_benchmark_section(build, quick):
    repetitions = "2" if quick else "5"
    command = [os.path.join(build, "clipray_ray_benchmarks"),
               "--benchmark_filter=(robust|unproject_glm)/float/row.*",
               f"--benchmark_repetitions={repetitions}", "--benchmark_format=json"]
    results = json.loads(run(command, stderr=subprocess.DEVNULL))["benchmarks"]
    medians = {b["run_name"]: b for b in results if b.get("aggregate_name") == "median"}
    rows = []
    for name, b in sorted(medians.items()):
        pixels = b.get("items_per_second")
        ns = 1e9 / pixels if pixels else b["real_time"]
        rows.append([name, fmt(ns)])
    robust = medians.get("robust/float/row_1920x1080")
    glm_row = medians.get("unproject_glm/float/row_1920x1080")
    ratio = ""
    if robust and glm_row and robust.get("items_per_second"):
        ratio = (f" `robust` float is {robust['items_per_second'] / glm_row['items_per_second']:.0f}x "
                 f"faster than `unproject_glm` float on this machine.")
    binary = os.path.relpath(command[0], ROOT)
    binary = command[0] if binary.startswith("..") else binary
    text = (f"`{' '.join([binary] + command[1:])}`"
            f": medians of {repetitions} repetitions, one core, origin, direction and t_max of a "
            f"row of pixels written into a cache-resident buffer; the three `robust` rows are "
            f"the same bits on three code paths (the unsuffixed one is the path this CPU "
            f"picks).{ratio}\n\n")
    return text + table(["benchmark", "ns/ray"], rows)


def intersection_section(build, quick):
    runs = "3" if quick else "15"
    size = ["--size", "480x270"] if quick else []
    side = run([os.path.join(build, "clipray_intersect_bench"), "--runs", runs, "--no-scaling"] +
               size)
    text = (f"`clipray_intersect_bench --runs {runs} --no-scaling{' ' + ' '.join(size) if size else ''}`"
            f" (medians of {runs}, one process, every run visiting the rows in a new shuffled "
            f"order; every path's hits are checked against the brute-force scan):\n\n```\n"
            f"{side.strip()}\n```\n")
    if quick:
        return text
    scaling = run([os.path.join(build, "clipray_intersect_bench"), "--runs", "10",
                   "--scaling-only"])
    return text + (f"\n`clipray_intersect_bench --runs 10 --scaling-only` (each case in its own "
                   f"process, 2 threads, as a reconcile runs it):\n\n```\n{scaling.strip()}\n```\n")


INTRO = """# Performance

Written by `harness/bench/performance-report.py` from one run of the commands each section
names; do not edit by hand, run the script. {machine} The machine is small and shared: compare
figures within one page, not across pages from different runs.

## What the figures mean

A reconcile has five phases, each timed in wall time (`timings_ms`) and in the CPU time of the
whole process (`cpu_ms`, every thread's, llvmpipe's own threads in `raster`):

- **raster**: llvmpipe draws the run into its FBO. **readback**: `glReadPixels` of depth and ids.
- **rays**: setting up the robust ray generator. clipray stores no ray of its own: each is
  computed where it is used, eight rows of 64 pixels at a time in `intersect`, and per run of 64
  pixels that shows something in `compare`.
- **intersect**: binning the triangles in screen space (`FrameBins`), then on the screen path
  (`--analytic auto`, the default, takes it for meshes where the frame, or each group of
  objects drawn with state of their own, has 16 pixels or more a triangle) each binned
  triangle's edge functions and depth plane at its 8x8 tiles' pixel centres, a ray traced only
  where the margins leave a pixel open or an analytic primitive may show; on the ray path
  (`--analytic rays`, and every frame of primitives alone) every tile traced
  as SIMD packets in double.
- **compare**: building the tolerance model of the primitives the raster shows, classifying every
  pixel (a pixel decided from planes from its triangle's planes, others along their rays), and
  the error distributions.

The ratio (rays + intersect + compare) / raster is what clipray adds to the raster it checks.
CPU time over wall time is how many cores a phase keeps busy: a ratio that differs between wall
and CPU time comes from how the work is spread over the cores, not from the work. Scenes of a few
triangles are drawn by llvmpipe in a few milliseconds, so a millisecond of noise moves their
ratio a lot; the terrain is the representative case. The compare grows with the pixels that show
something (floors that fill the frame cost most). The first run of a process after idle time can be several times slower than
these steady medians: the virtual machine's host reclaims idle memory, and touching it again is
slow; `--rounds` keeps round 1 apart (`first_round_timings_ms`).

Why the ray path's intersection is fast: a camera's own rays need no BVH. `FrameBins` projects each triangle
once per camera and lists, per 8x8 tile, the triangles whose padded outline may cover it (by its
edges, per half row of eight pixels, not only by its bounds); a tile whose rays stay within 1/4 px
of their pixels' lines of sight tests only those, skipping triangles behind all its
current hits. The watertight test runs on four lanes of doubles and keeps accepted lanes by
blending, not branching (a third of the groups the bins test have no lane inside, in no order a
predictor can learn). Rays are computed eight tiles at a time into a per-thread buffer, with the
generator's per-row terms kept per frame row, so no frame of rays is stored.

"""


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    parser.add_argument("--out", default=os.path.join(ROOT, "docs", "performance.md"))
    parser.add_argument("--quick", action="store_true",
                        help="small frames and few repetitions: checks the script, not the page")
    options = parser.parse_args()
    build = os.path.abspath(options.build)
    for binary in ("clipray", "clipray_ray_benchmarks", "clipray_intersect_bench"):
        if not os.access(os.path.join(build, binary), os.X_OK):
            sys.exit(f"performance-report: {os.path.join(build, binary)} not found; build the "
                     f"release preset first (cmake --workflow --preset test)")
    with tempfile.TemporaryDirectory(prefix="clipray-perf-") as work:
        gl, suite = suite_section(build, work, options.quick)
        sections = [
            INTRO.format(machine=machine_lines(gl)),
            "## Reconcile, every shipped scene\n\n" + suite,
            "\n## The 100k-triangle terrain in steady state\n\n" +
            terrain_section(build, work, options.quick),
            "\n## The screen path\n\n" +
            screen_path_section(ROOT, build, work, options.quick, reconcile, fmt, table),
            "\n## Multisampling\n\n" + multisample_section(build, work, options.quick),
            "\n## A RenderDoc capture of a 1080p frame\n\n" +
            capture_section(ROOT, build, work, options.quick, fmt, table),
            "\n## Analytic primitives: GLSL float rays against CPU double rays\n\n" +
            primitives_section(build, work),
            "\n## Ray methods\n\n" + ray_methods_section(build, work, options.quick),
            "\n" + google_benchmark_section(build, options.quick),
            "\n## Intersection\n\n" + intersection_section(build, options.quick),
            "\n## Where the analytic time goes\n\n" +
            profile_section(build, work, options.quick, run, fmt, table),
        ]
    page = "".join(sections)
    staging = options.out + ".tmp"
    with open(staging, "w") as f:
        f.write(page)
    os.replace(staging, options.out)
    print(f"performance-report: wrote {options.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
