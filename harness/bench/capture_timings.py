"""The RenderDoc capture section of docs/performance.md (performance-report.py): a real program's
1080p frame captured, checked, verified and reconciled, each step timed in wall time.

The program is glmark2-es2's build scene (Debian's glmark2-es2-x11), launched under Xvfb by
harness/renderdoc/clipray-capture-frame.py, which captures its next presented frame through
RenderDoc's target control; then `clipray check --capture`, `check --capture --verify` and
`reconcile --capture` read that capture. Each step is repeated and its median reported.
"""
import json
import os
import shutil
import statistics
import subprocess
import sys
import time

REPETITIONS = 3
NEEDED = ["xvfb-run", "renderdoccmd", "glmark2-es2"]


def timed(command, cwd, env=None):
    """Runs a command; returns its wall time in seconds, or exits the script naming it."""
    print("+ " + " ".join(command), file=sys.stderr, flush=True)
    start = time.monotonic()
    result = subprocess.run(command, cwd=cwd, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True, env=env)
    elapsed = time.monotonic() - start
    if result.returncode not in (0, 1):
        sys.exit(f"performance-report: {command[0]} exited {result.returncode}: "
                 f"{result.stderr.strip()[-400:]}")
    return elapsed


def capture_section(root, build, work, quick, fmt, table):
    missing = [tool for tool in NEEDED if shutil.which(tool) is None]
    if subprocess.run(["/usr/bin/python3", "-c", "import renderdoc"],
                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode != 0:
        missing.append("python3-renderdoc")
    if missing:
        return ("Not measured: " + ", ".join(missing) + " missing (harness/install-deps.sh "
                "installs them).\n")
    width, height = (480, 270) if quick else (1920, 1080)
    clipray = os.path.join(build, "clipray")
    script = os.path.join(root, "harness", "renderdoc", "clipray-capture-frame.py")
    env = dict(os.environ, CLIPRAY_CAPTURE_PYTHON="/usr/bin/python3")
    steps = {"capture": [], "check": [], "verify": [], "reconcile": []}
    sizes = []
    report = None
    for k in range(REPETITIONS):
        rdc = os.path.join(work, f"glmark2-{k}.rdc")
        steps["capture"].append(timed(
            ["xvfb-run", "-a", "-s", f"-screen 0 {width}x{height}x24", "env",
             "LIBGL_ALWAYS_SOFTWARE=1", "/usr/bin/python3", script, rdc, "--timeout", "30", "--",
             "glmark2-es2", "-s", f"{width}x{height}", "-b", "build"], work, env))
        sizes.append(os.path.getsize(rdc))
        steps["check"].append(timed([clipray, "check", "--capture", rdc], work, env))
        steps["verify"].append(timed([clipray, "check", "--capture", rdc, "--verify"], work,
                                     env))
        out = os.path.join(work, f"capture-reconcile-{k}")
        steps["reconcile"].append(timed([clipray, "reconcile", "--capture", rdc, "--out", out],
                                        work, env))
        with open(os.path.join(out, "report.json")) as f:
            report = json.load(f)["runs"][0]
    run = report
    text = (f"glmark2-es2's build scene at {width}x{height} (`xvfb-run -a -s '-screen 0 "
            f"{width}x{height}x24' env LIBGL_ALWAYS_SOFTWARE=1 "
            f"harness/renderdoc/clipray-capture-frame.py glmark2.rdc -- glmark2-es2 -s "
            f"{width}x{height} -b build`), then `clipray check --capture glmark2.rdc`, the same "
            f"with `--verify`, and `clipray reconcile --capture glmark2.rdc`: the median wall "
            f"time of {REPETITIONS} runs of each, in seconds. The capture includes starting the "
            f"program and its first frames; each clipray step includes RenderDoc opening and "
            f"replaying the capture in its reader.\n\n")
    header = ["step", "median s", "min s", "max s"]
    rows = [[name, fmt(statistics.median(values)), fmt(min(values)), fmt(max(values))]
            for name, values in steps.items()]
    text += table(header, rows)
    timings = run["timings_ms"]
    text += (f"\nThe capture file: {statistics.median(sizes) / 1e6:.2f} MB. The reconcile of "
             f"the last run: verdict {run['verdict']}, {run['raster_hits']} pixels drawn, "
             f"{run['depth_compared']} depths compared, the analytic side "
             f"{fmt(timings['rays'] + timings['intersect'] + timings['compare'])} ms of it "
             f"(rays {fmt(timings['rays'])}, intersect {fmt(timings['intersect'])}, compare "
             f"{fmt(timings['compare'])}); the rest is RenderDoc's two replays in the reader "
             f"(the draws' state, then their geometry and the depth after each).\n")
    return text
