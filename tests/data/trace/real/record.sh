#!/usr/bin/env bash
# Re-records tests/data/trace/real/*.dump.txt: unmodified Debian 12 programs traced with apitrace
# under Xvfb (Mesa llvmpipe), their dumps trimmed by trim-dump.py to the first frames and to the
# calls that can change a reading. tests/trace/RealProgramsTest.cpp pins what clipray reads from
# each. Run as root on Debian 12 (installs what is missing), from anywhere:
#
#   tests/data/trace/real/record.sh [NAME...]      (default: every program below)
#
# With CLIPRAY=path/to/clipray it also checks the trimming: the whole trace (through apitrace, over
# the same frames) must read exactly as the trimmed listing does (through apitrace-cat.sh), or the
# script fails naming the program.
#
# Recorded with: apitrace 11.1+repack-1.1+b2, openscad 2021.01-6, openscenegraph
# 3.6.5+dfsg1-8+b2, glmark2-x11 2023.01+dfsg-1, f3d 1.3.1+dfsg-5 (libvtk9.1
# 9.1.0+really9.1.0+dfsg2-5+deb12u1), Mesa llvmpipe (libgl1-mesa-dri 22.3.6-1+deb12u2), xvfb
# 2:21.1.7-3+deb12u13; each listing's header names its program's package version.
# The programs draw into a 320x240 window (OSG_WINDOW, --imgsize, -s) on a 1024x768 screen. OSG
# runs single-threaded (OSG_THREADING) for 3 frames (OSG_RUN_FRAME_COUNT; osgshadow runs its
# own loop: stopped by timeout, then trimmed to 3 frames). MeshLab (meshlab 2020.09+dfsg1-2, Qt 5)
# opens model.stl in its maximised window and runs until the timeout's SIGINT (it then crashes,
# after apitrace has flushed the trace); its mesh is first drawn in frame 2 (once loaded), so 5
# frames are kept.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

need=(apitrace apitrace-tracers xvfb xauth openscad openscenegraph glmark2-x11 f3d meshlab
  stellarium)
missing=()
for p in "${need[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"
fi

# The model every program draws: a cube less a sphere (OpenSCAD's CSG preview needs the
# difference; 8 facets keep the immediate-mode draws few).
cat >"$work/model.scad" <<'SCAD'
difference() { cube(10, center = true); sphere(6.5, $fn = 8); }
SCAD
(cd "$work" && openscad -q -o model.stl model.scad)

export OSG_RUN_FRAME_COUNT=3 OSG_WINDOW="0 0 320 240" OSG_THREADING=SingleThreaded
scad="openscad --imgsize=320,240 -o out.png model.scad"
# name | frames kept (0: all) | seconds allowed | command (run in $work)
# Stellarium (stellarium 0.22.2-1) starts from a fresh home (its config written there) at a fixed
# date and time; it runs until the timeout. Its first frame alone is 370 KB of start-up texture
# uploads, so it is trimmed "lean" (trim-dump.py) to that frame.
programs=(
  "openscad-render-ortho|0|60|$scad --render --projection=o"
  "openscad-render-persp|0|60|$scad --render --projection=p"
  "openscad-preview-ortho|0|60|$scad --preview --projection=o"
  "openscad-preview-persp|0|60|$scad --preview --projection=p"
  "osgviewer|3|60|osgviewer model.stl"
  "osghud|3|60|osghud model.stl"
  "osgshadow-sm|3|8|osgshadow --sm"
  "osgshadow-lispsm|3|8|osgshadow --lispsm"
  "osgtext|3|60|osgtext"
  "osguniformbuffer|3|60|osguniformbuffer model.stl"
  "osgteapot|3|60|osgteapot"
  "osgdepthpartition|3|60|osgdepthpartition"
  "osgreflect|3|60|osgreflect model.stl"
  "osgmultiplerendertargets|3|60|osgmultiplerendertargets"
  "osgscalarbar|1|60|osgscalarbar"
  "osgdistortion|3|60|osgdistortion model.stl"
  "osgfpdepth|3|60|osgfpdepth model.stl"
  "glmark2-build|3|20|glmark2 -s 320x240 -b build:use-vbo=true:duration=1"
  "f3d|0|60|f3d --output=out.png --resolution=320,240 model.stl"
  "meshlab|5|25|meshlab model.stl"
  "stellarium|1|90|env HOME=$work/home stellarium --sky-date 20230101 --sky-time 22:00:00"
)

version() { dpkg-query -W -f='${Package} ${Version}' "$1"; }
for entry in "${programs[@]}"; do
  IFS='|' read -r name frames seconds command <<<"$entry"
  if [ $# -gt 0 ] && [[ " $* " != *" $name "* ]]; then continue; fi
  case "$name" in
    openscad-*) package=openscad ;;
    glmark2-*) package=glmark2-x11 ;;
    f3d) package=f3d ;;
    meshlab) package=meshlab ;;
    stellarium) package=stellarium ;;
    *) package=openscenegraph ;;
  esac
  rm -f "$work/$name.trace"
  # timeout's status is 124 where a program runs its own loop (osgshadow, meshlab, stellarium):
  # the trace is whole up to the signal, and only its first frames are kept.
  # osgdepthpartition sometimes aborts at start-up under Xvfb (GLXBadDrawable): up to 3 tries.
  for try in 1 2 3; do
    status=0
    rm -f "$work/$name.trace"
    (cd "$work" && timeout -s INT "$seconds" xvfb-run -a -s "-screen 0 1024x768x24" \
      apitrace trace --api gl -o "$name.trace" $command >"$name.log" 2>&1) || status=$?
    if [ "$status" -eq 0 ] || [ "$status" -eq 124 ]; then break; fi
  done
  if [ "$status" -ne 0 ] && [ "$status" -ne 124 ]; then
    cat "$work/$name.log" >&2
    echo "$name: apitrace trace exited with status $status" >&2
    exit 1
  fi
  lean=""
  [ "$name" = stellarium ] && lean=lean
  header="$name: $(version "$package"), $(version apitrace), Mesa llvmpipe under Xvfb
recorded by tests/data/trace/real/record.sh: apitrace trace --api gl ${command//$work/\$work}
trimmed by trim-dump.py to frames: ${frames/#0/all}${lean:+, lean}"
  apitrace dump --color=never --multiline=false "$work/$name.trace" 2>/dev/null |
    "$here/trim-dump.py" "$frames" "$header" $lean >"$here/$name.dump.txt"
  echo "$name: $(grep -c '^[0-9]' "$here/$name.dump.txt") calls, $(wc -c <"$here/$name.dump.txt") bytes"
  if [ -n "${CLIPRAY:-}" ]; then
    range=()
    [ "$frames" -gt 0 ] && range=(--frames "0-$((frames - 1))")
    # Statuses 0 and 1 (findings) are readings; the file names differ, the rest must not.
    whole=$("$CLIPRAY" check --trace "$work/$name.trace" "${range[@]}" | tail -n +2) || true
    trimmed=$(CLIPRAY_APITRACE="$here/apitrace-cat.sh" "$CLIPRAY" check \
      --trace "$here/$name.dump.txt" | tail -n +2) || true
    if [ "$whole" != "$trimmed" ]; then
      diff <(echo "$whole") <(echo "$trimmed") >&2 || true
      echo "$name: the trimmed listing reads differently from the whole trace" >&2
      exit 1
    fi
  fi
done
