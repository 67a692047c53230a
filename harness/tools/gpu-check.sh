#!/bin/bash
# The GL suite and every shipped scene through EGL on whatever GPU EGL offers, with both kernel
# choices and both analytic paths (--analytic rays and screen) compared
# (harness/tools/same-outputs.py): the check docs/reconcile.md ("On a real GPU") reports. Run from the repository root of a release build (cmake --preset release), on a machine
# with an EGL driver. The logs go to $OUT (default /tmp/gpu-check), the two sweeps' output folders
# to $SWEEPS (default /tmp/gpu-check-sweeps). The test binary reads the shipped scenes from the
# source folder it was built in (a copy elsewhere needs a link there). Nothing here is needed by CI.
#
# NVIDIA's EGL vendor file is used where it sits in the container images we were lent
# (/usr/local/nvidia); elsewhere glvnd finds the vendor itself.
set -u
build=${BUILD:-build/release}
out=${OUT:-/tmp/gpu-check}
sweeps=${SWEEPS:-/tmp/gpu-check-sweeps}
mkdir -p "$out" "$sweeps"
vendor=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
[ -f "$vendor" ] && export __EGL_VENDOR_LIBRARY_FILENAMES=$vendor
export CLIPRAY_EGL_PLATFORM=${CLIPRAY_EGL_PLATFORM:-device}
command -v nvidia-smi >/dev/null && nvidia-smi -L
status=0

started=$(date +%s)
CLIPRAY_TEST_GL_BACKEND=egl timeout 300 "$build/tests/clipray_gl_tests" \
  --gtest_output=json:"$out/gl-tests.json" >"$out/gl-tests.log" 2>&1
echo "GL suite: exit $? in $(($(date +%s) - started)) s (the OSMesa comparison fails where OSMesa is absent)"
grep -E '^\[  (PASSED|FAILED) ' "$out/gl-tests.log"

every="--backend egl --conventions no,zo,zo-reversed --depth-formats 16,24,32f"
every="$every --vertex-modes world,camera-relative,pretransformed --images all"
for choice in "--analytic rays --kernels simd" "--analytic rays --kernels portable" \
  "--analytic screen --kernels simd"; do
  name=${choice##* }
  [ "$choice" = "--analytic screen --kernels simd" ] && name=screen
  started=$(date +%s)
  # Exit 1 is a finished sweep with inconsistent runs (27 expected: docs/reconcile.md).
  timeout 300 "$build/clipray" reconcile $every $choice --out "$sweeps/$name" \
    >"$out/reconcile-$name.txt" 2>&1
  code=$?
  echo "reconcile $choice: exit $code in $(($(date +%s) - started)) s"
  [ $code -le 1 ] || status=1
done
if python3 harness/tools/same-outputs.py "$sweeps/simd" "$sweeps/portable" >"$out/same-outputs.txt"; then
  echo "kernel choices: the same outputs"
else
  echo "kernel choices differ:"; head -20 "$out/same-outputs.txt"; status=1
fi
# The screen path's depth figures come from its planes: within a hair of the ray path's.
if python3 harness/tools/same-outputs.py --without screen_path --figures-within 0.01 \
  "$sweeps/simd" "$sweeps/screen" >"$out/same-outputs-screen.txt"; then
  echo "analytic paths: the same outputs"
else
  echo "analytic paths differ:"; head -20 "$out/same-outputs-screen.txt"; status=1
fi
python3 - "$sweeps/simd/report.json" "$sweeps/screen/report.json" <<'PY'
import json, statistics, sys
runs = json.load(open(sys.argv[1]))["runs"]
bad = [r for r in runs if r["verdict"] != "consistent"]
explained = sum(r["id_mismatch"]["depth_ambiguous"] + r["id_mismatch"]["edge_ambiguous"] for r in runs)
worst = {}
for r in runs:
    if r["verdict"] == "consistent":
        worst[r["depth_format"]] = max(worst.get(r["depth_format"], 0), r["tolerance_ratio"]["max"] or 0)
print(f"{len(runs)} runs, {len(bad)} inconsistent, {explained} explained mismatches, "
      "max error / tolerance: " + " / ".join(f"{k} {v:.2f}" for k, v in sorted(worst.items())))
# Per path, the analytic side's wall time against the GPU's raster and readback of the same run.
for name, path in (("rays", sys.argv[1]), ("screen", sys.argv[2])):
    ratios = [(r["timings_ms"]["rays"] + r["timings_ms"]["intersect"] + r["timings_ms"]["compare"]) /
              (r["timings_ms"]["raster"] + r["timings_ms"]["readback"])
              for r in json.load(open(path))["runs"]]
    print(f"analytic / (raster + readback), {name} path: median {statistics.median(ratios):.2f}, "
          f"max {max(ratios):.2f} over {len(ratios)} runs")
PY
exit $status
