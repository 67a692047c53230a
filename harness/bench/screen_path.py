"""The screen path (`clipray reconcile --analytic screen`) against the ray path, for
performance-report.py: the intersect phase of scenes the screen path covers at 1080p, the two
paths alternating process by process, and what the screen path traced per frame."""
import os
import statistics

SCENES = ["terrain_100k", "standard", "grazing_floor", "far_from_origin"]


def screen_path_section(root, build, work, quick, reconcile, fmt, table):
    processes = 1 if quick else 3
    size = "480x270" if quick else "1920x1080"
    rounds = "2" if quick else "5"
    per = {}  # (scene, path) -> runs
    for p in range(processes):
        for path in ("rays", "screen"):
            arguments = [os.path.join(root, "scenes", f"{s}.json") for s in SCENES] + [
                "--size", size, "--depth-formats", "32f", "--conventions", "zo", "--rounds",
                rounds, "--images", "none", "--analytic", path]
            report = reconcile(build, os.path.join(work, f"screen-{path}{p}"), arguments)
            for r in report["runs"]:
                per.setdefault((r["scene"], path), []).append(r)
    rows = []
    for scene in SCENES:
        rays = per.get((scene, "rays"), [])
        screen = per.get((scene, "screen"), [])
        if not rays or not screen:
            continue
        cpu = {path: statistics.median(r["cpu_ms"]["intersect"] for r in runs)
               for path, runs in (("rays", rays), ("screen", screen))}
        wall = {path: statistics.median(r["timings_ms"]["intersect"] for r in runs)
                for path, runs in (("rays", rays), ("screen", screen))}
        counts = screen[0].get("screen_path")
        if counts:
            pixels = sum(counts[k] for k in ("background", "decided", "contested", "traced"))
            share = (f"{counts['background']} / {counts['decided']} / {counts['contested']} / "
                     f"{counts['traced']} of {pixels}")
            deviation = f"{counts['ray_deviation_ndc']:.2g}"
        else:
            share, deviation = "not evaluated", "-"
        # The target: the whole analytic side's CPU time against the raster's.
        analytic = {path: statistics.median(
            (r["cpu_ms"]["rays"] + r["cpu_ms"]["intersect"] + r["cpu_ms"]["compare"]) /
            r["cpu_ms"]["raster"] for r in runs) for path, runs in (("rays", rays),
                                                                      ("screen", screen))}
        rows.append([scene, fmt(wall["rays"]), fmt(wall["screen"]), fmt(cpu["rays"]),
                     fmt(cpu["screen"]), fmt(cpu["screen"] / cpu["rays"] if cpu["rays"] else None),
                     fmt(analytic["rays"]), fmt(analytic["screen"]), share, deviation])
    text = (f"`clipray reconcile SCENES --size {size} --depth-formats 32f --conventions zo "
            f"--rounds {rounds} --analytic rays|screen`, the two paths alternating over "
            f"{processes} processes each; the intersect phase's medians (milliseconds), the whole "
            f"analytic side's CPU time (rays + intersect + compare) over the raster's, and the "
            f"screen path's pixels: background (no ray computed) / decided (one watertight test) "
            f"/ contested (several) / traced (the ray path's search), with the bound on the rays' "
            f"deviation it decided with (NDC).\n\n")
    header = ["scene", "intersect wall: rays", "screen", "CPU: rays", "screen", "screen / rays",
              "analytic / raster CPU: rays", "screen", "pixels", "deviation"]
    return text + table(header, rows)
