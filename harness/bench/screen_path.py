"""The screen path (`clipray reconcile --analytic screen`) against the ray path, for
performance-report.py: the analytic phases' CPU time on scenes the screen path covers at 1080p,
one thread, the two paths alternating process by process, and what the screen path traced and
compared along rays per frame."""
import os
import statistics

SCENES = ["terrain_100k", "standard", "grazing_floor", "far_from_origin", "coplanar", "infinite_far",
          "logarithmic_depth", "object_depth_range", "object_clip_planes", "polygon_offset"]


def screen_path_section(root, build, work, quick, reconcile, fmt, table):
    processes = 1 if quick else 3
    size = "480x270" if quick else "1920x1080"
    rounds = "2" if quick else "5"
    per = {}  # (scene, path) -> runs
    for p in range(processes):
        for path in ("rays", "screen"):
            arguments = [os.path.join(root, "scenes", f"{s}.json") for s in SCENES] + [
                "--size", size, "--depth-formats", "32f", "--conventions", "zo", "--rounds",
                rounds, "--images", "none", "--threads", "1", "--analytic", path]
            report = reconcile(build, os.path.join(work, f"screen-{path}{p}"), arguments)
            for r in report["runs"]:
                per.setdefault((r["scene"], path), []).append(r)
    rows = []
    for scene in SCENES:
        rays = per.get((scene, "rays"), [])
        screen = per.get((scene, "screen"), [])
        if not rays or not screen:
            continue
        paths = (("rays", rays), ("screen", screen))

        def median(runs, value):
            return statistics.median(value(r) for r in runs)

        def analytic_ms(r):
            return r["cpu_ms"]["rays"] + r["cpu_ms"]["intersect"] + r["cpu_ms"]["compare"]
        cpu = {path: median(runs, analytic_ms) for path, runs in paths}
        intersect = {path: median(runs, lambda r: r["cpu_ms"]["intersect"]) for path, runs in paths}
        compare = {path: median(runs, lambda r: r["cpu_ms"]["compare"]) for path, runs in paths}
        # The targets: the analytic side's CPU time against the raster's, and per pixel.
        ratio = {path: median(runs, lambda r: analytic_ms(r) / r["cpu_ms"]["raster"])
                 for path, runs in paths}
        per_pixel = {path: median(runs, lambda r: 1e6 * analytic_ms(r) / r["pixels"])
                     for path, runs in paths}
        counts = screen[0].get("screen_path")
        if counts and "declined" not in counts:
            pixels = sum(counts[k] for k in ("background", "decided", "contested", "traced"))
            share = (f"{counts['background']} / {counts['decided']} / {counts['contested']} / "
                     f"{counts['traced']} of {pixels}")
            along = f"{counts.get('compared_along_rays', 0)} of {counts['decided']}"
            deviation = f"{counts['ray_deviation_ndc']:.2g}"
        else:
            share, along, deviation = "not evaluated", "-", "-"
        rows.append([scene, fmt(intersect["rays"]), fmt(intersect["screen"]), fmt(compare["rays"]),
                     fmt(compare["screen"]), fmt(cpu["screen"] / cpu["rays"] if cpu["rays"] else None),
                     fmt(ratio["rays"]), fmt(ratio["screen"]), fmt(per_pixel["rays"]),
                     fmt(per_pixel["screen"]), share, along, deviation])
    text = (f"`clipray reconcile SCENES --size {size} --depth-formats 32f --conventions zo "
            f"--rounds {rounds} --threads 1 --analytic rays|screen`, the two paths alternating "
            f"over {processes} processes each, one thread (CPU time is the figure here): the "
            f"medians of rounds 2-{rounds} of the intersect and compare phases' CPU time "
            f"(milliseconds), the whole analytic side's (rays + intersect + compare) on the screen "
            f"path over the ray path's and over the raster's, and per pixel (nanoseconds); the "
            f"screen path's pixels: background (no ray computed) / decided from one triangle's "
            f"planes / contested (several within the depth margin, their watertight tests) / "
            f"traced (the ray path's search), the decided pixels the compare took along their "
            f"rays (sides that differ, or a class the planes' reach leaves open), and the bound on "
            f"the rays' deviation it decided with (NDC).\n\n")
    header = ["scene", "intersect CPU: rays", "screen", "compare CPU: rays", "screen",
              "analytic: screen / rays", "analytic / raster CPU: rays", "screen",
              "ns per pixel: rays", "screen", "pixels", "compared along rays", "deviation"]
    return text + table(header, rows)
