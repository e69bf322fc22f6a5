#!/usr/bin/env bash
# The church job's pictures: scripts/post_church.sh <results dir> [--mesh FILE] [--size WxH]
#
# Writes into <results dir>/pictures/:
#   mesh.png, mode-1.png .. mode-3.png, damage-tension.png, damage-compression.png,
#   envelope-drift.png, damage-by-substructure.csv   (ParaView: scripts/pv_post_church.py)
#   monitors.png                                      (matplotlib: scripts/plot_monitors.py)
#   spectrum.png                                      (a copy of <results dir>/spectrum.png)
# --mesh: the job's Gmsh file, for the substructure names (default meshes/church.msh).
# A missing result file is an error (exit 1). Without ParaView (scripts/setup.sh --paraview) or
# matplotlib, the pictures that need them are skipped with the reason, and the exit code is 0.
# PVPYTHON=/path/to/pvpython picks another ParaView (default: pvpython on PATH).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
usage() { sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; }

dir="" mesh="" size="1600x1200"
while [ $# -gt 0 ]; do
  case "$1" in
    --mesh) mesh="${2:?--mesh needs a file}"; shift 2 ;;
    --size) size="${2:?--size needs WxH}"; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    -*) echo "post_church.sh: unknown option '$1'" >&2; usage >&2; exit 2 ;;
    *) [ -z "$dir" ] || { echo "post_church.sh: one results folder, got '$dir' and '$1'" >&2; exit 2; }
       dir="$1"; shift ;;
  esac
done
[ -n "$dir" ] || { usage >&2; exit 2; }
[ -d "$dir" ] || { echo "post_church.sh: $dir: no such results folder (run the church job first)" >&2; exit 1; }
missing=()
for f in modes.xdmf modes.h5 results.xdmf results.h5 monitors.csv; do
  [ -f "$dir/$f" ] || missing+=("$f")
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "post_church.sh: $dir: missing ${missing[*]} (did the church job finish?)" >&2
  exit 1
fi
if [ -z "$mesh" ] && [ -f "$here/../meshes/church.msh" ]; then
  mesh="$here/../meshes/church.msh"
fi
[ -z "$mesh" ] || [ -f "$mesh" ] || { echo "post_church.sh: --mesh: no such file: $mesh" >&2; exit 1; }
pictures="$dir/pictures"
mkdir -p "$pictures"
skipped=()

# ParaView renders the fields (one pvpython process for all of them).
pvpython="${PVPYTHON:-pvpython}"
if ! command -v "$pvpython" >/dev/null 2>&1; then
  skipped+=("the ParaView pictures ($pvpython is not installed: scripts/setup.sh --paraview)")
elif ! command -v Xvfb >/dev/null 2>&1; then
  skipped+=("the ParaView pictures (Xvfb is not installed: scripts/setup.sh --paraview)")
else
  echo "post_church: rendering with ParaView ($("$pvpython" --version 2>/dev/null | head -n 1))"
  status=0
  bash "$here/with_display.sh" "$pvpython" "$here/pv_post_church.py" "$dir" --out "$pictures" --size "$size" \
    ${mesh:+--mesh "$mesh"} || status=$?
  if [ "$status" -ne 0 ]; then
    echo "post_church.sh: the ParaView post-processing failed (exit $status)" >&2
    exit "$status"
  fi
fi

# The monitors in one picture: any Python that has matplotlib (ParaView's package brings it).
py=""
for p in python3 /usr/bin/python3; do
  if command -v "$p" >/dev/null 2>&1 && "$p" -c "import matplotlib" 2>/dev/null; then py="$p"; break; fi
done
if [ -n "$py" ]; then
  "$py" "$here/plot_monitors.py" "$dir/monitors.csv" --out "$pictures/monitors.png"
else
  skipped+=("monitors.png (no Python with matplotlib: apt-get install python3-matplotlib; monitor-<name>.png are in $dir)")
fi

# The record's spectrum against EC8, when the run drew it.
if [ -f "$dir/spectrum.png" ]; then
  cp "$dir/spectrum.png" "$pictures/spectrum.png"
else
  skipped+=("spectrum.png (not in $dir: the spectrum job draws it, jobs/spectrum-vallorcine.toml)")
fi

echo "post_church: pictures in $pictures:"
(cd "$pictures" && ls -1 | sed 's/^/  /')
for s in "${skipped[@]}"; do
  echo "post_church: skipped $s"
done
exit 0
