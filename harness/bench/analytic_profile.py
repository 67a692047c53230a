"""Where the analytic side of a reconcile spends its CPU time, from `perf record` samples: the
section "Where the analytic time goes" of docs/performance.md (performance-report.py calls
profile_section).

The reconcile's own clock gives each phase's CPU time (`cpu_ms`: rays, intersect, compare); perf's
samples of the clipray binary split that time over the kernels. Each category below is a set of
functions (substrings of perf's symbol names); the analytic CPU time of a run is shared out over
the categories in proportion to their samples. Samples in clipray's code outside every category
(scene loading, the BVH build, the GL calls) are counted apart and shown, not shared out.

For each category, the page also gives the CPU ratio (analytic / raster) the run would have if
that category cost nothing: an upper bound on what speeding that code up can give, however it
is done (wider SIMD, float filters with a double fallback, or removing it).
"""
import json
import os
import re
import shutil
import subprocess

# (label, substrings of the symbols it holds); the first match wins.
CATEGORIES = [
    ("ray generation (intersect and compare)",
     ["finishRowBlock", "directionsOfRow", "RobustRayGenerator::generateRow",
      "PixelCentreRays::row"]),
    ("intersect: loading packets, checking rays stay on their pixels, writing hits",
     ["loadUniformTile", "raysOnTheirPixels", "prepareShear", "writeHits", "traceTile<",
      "forEachTile<", "closestHitsTileBinned", "PacketKernels::traceBinned"]),
    ("intersect: watertight triangle tests in the bins", ["traceBins", "testGroup"]),
    ("intersect: analytic primitives", ["addAnalyticToTile", "PrimitiveKernels",
                                        "intersectPrimitive"]),
    ("intersect: screen bins (FrameBins)", ["FrameBins::FrameBins", "pixelRange", "binChunk"]),
    ("intersect: the screen path's triangle setups, tile walks and decisions",
     ["setupTriangle", "walkTileAvx2", "walkTilePortable", "intersectFrameInScreenSpace",
      "closestOfListed"]),
    ("compare: pixels decided from planes (depth, error, tolerance from the planes)",
     ["FromPlanes"]),
    ("compare: per-pixel kernels (hit depth, error, tolerance)",
     ["classifyFour", "fourTrianglePixels", "fourAnalyticPixels", "appendFour", "classifyPixel",
      "loadFourHits", "finishFour"]),
    ("compare: rows, background runs, raster ids", ["classifyRows", "idsInRaster"]),
    ("compare: tolerance polygons", ["ToleranceModel::", "toleranceModelOfRaster"]),
    ("compare: error distributions", ["CountingPass", "distributionOf", "__introsort_loop",
                                      "histogramOf", "BucketValues"]),
]

# The arithmetic that float kernels with a double fallback would take over: the last row frees
# these categories together.
FLOAT_FILTERABLE = ["intersect: watertight triangle tests in the bins",
                    "compare: per-pixel kernels (hit depth, error, tolerance)",
                    "ray generation (intersect and compare)"]
assert all(label in dict(CATEGORIES) for label in FLOAT_FILTERABLE)

SCENES = [("terrain_100k", "the 100k-triangle terrain"), ("standard", "the standard scene")]

SAMPLE_LINE = re.compile(r"^\s*([\d.]+)%\s+(\S+)\s+\[\.\]\s+(.*?)\s*$")


def perf_works(work):
    perf = shutil.which("perf")
    if not perf:
        return None, "perf is not installed (Debian's linux-perf)"
    probe = subprocess.run([perf, "record", "-q", "-o", os.path.join(work, "probe.data"), "--",
                            "true"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if probe.returncode != 0:
        reason = probe.stderr.strip().splitlines()[:1]
        return None, "perf record fails here" + (f" ({reason[0]})" if reason else "")
    return perf, None


def clipray_shares(perf, data):
    """Percent of all samples per symbol of the clipray binary."""
    report = subprocess.run([perf, "report", "-i", data, "--no-children", "--sort", "dso,symbol",
                             "--stdio"], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                            text=True, check=True).stdout
    shares = {}
    for line in report.splitlines():
        match = SAMPLE_LINE.match(line)
        if match and match.group(2) == "clipray":
            shares[match.group(3)] = shares.get(match.group(3), 0.0) + float(match.group(1))
    return shares


def categorize(shares):
    by_category = {label: 0.0 for label, _ in CATEGORIES}
    other = 0.0
    for symbol, share in shares.items():
        for label, keys in CATEGORIES:
            if any(key in symbol for key in keys):
                by_category[label] += share
                break
        else:
            other += share
    return by_category, other


def profile_section(build, work, quick, run, fmt, table):
    perf, missing = perf_works(work)
    size = "480x270" if quick else "1920x1080"
    rounds = "3" if quick else "20"
    if not perf:
        return f"Not measured: {missing}.\n"
    text = (f"`perf record` of `clipray reconcile scenes/SCENE.json --size {size} --conventions "
            f"zo --depth-formats 32f --rounds {rounds} --images none`. The run's analytic CPU time "
            f"(the median of rounds 2-{rounds} of rays + intersect + compare, as in the tables "
            f"above) is shared out over the kernels in proportion to their samples; \"ratio if "
            f"free\" is the CPU ratio (analytic / raster) with that category at no cost, a bound "
            f"on what any speed-up of it can give. The last row frees three categories at "
            f"once: the arithmetic that float kernels with a double fallback would take over.\n")
    for scene, name in SCENES:
        out = os.path.join(work, f"profile-{scene}")
        data = os.path.join(work, f"profile-{scene}.data")
        run([perf, "record", "-q", "-o", data, "--", os.path.join(build, "clipray"), "reconcile",
             f"scenes/{scene}.json", "--size", size, "--conventions", "zo", "--depth-formats",
             "32f", "--rounds", rounds, "--images", "none", "--out", out],
            stderr=subprocess.DEVNULL)
        with open(os.path.join(out, "report.json")) as f:
            cpu = json.load(f)["runs"][0]["cpu_ms"]
        analytic = cpu["rays"] + cpu["intersect"] + cpu["compare"]
        by_category, other = categorize(clipray_shares(perf, data))
        counted = sum(by_category.values())
        rows = []
        for label, _ in CATEGORIES:
            ms = analytic * by_category[label] / counted if counted else 0.0
            rows.append([label, fmt(ms), f"{100 * ms / analytic:.0f}%" if analytic else "-",
                         fmt((analytic - ms) / cpu["raster"])])
        freed = (sum(analytic * by_category[label] / counted for label in FLOAT_FILTERABLE)
                 if counted else 0.0)
        rows.append(["triangle tests, per-pixel kernels and ray generation together", fmt(freed),
                     f"{100 * freed / analytic:.0f}%" if analytic else "-",
                     fmt((analytic - freed) / cpu["raster"])])
        text += (f"\n{name.capitalize()}: raster {fmt(cpu['raster'])} ms CPU, analytic "
                 f"{fmt(analytic)} ms CPU (ratio {fmt(analytic / cpu['raster'])}); clipray code "
                 f"outside these categories: {other / (counted + other) * 100 if counted else 0:.1f}"
                 f"% of clipray's samples.\n\n")
        text += table(["kernels", "ms CPU per run", "share of analytic", "ratio if free"], rows)
    return text
