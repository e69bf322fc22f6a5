#!/usr/bin/env bash
# The pictures of a time history: scripts/post.sh <results dir> [--names FILE] [--size WxH] [--cut-y Y]
#
# Any time_history or seismic_assessment job, or a sweep member (members/<member>), whatever its
# groups and whether or not it has modes. Writes into <results dir>/pictures/:
#   mesh.png, mode-1.png .. mode-3.png (with modes), damage-tension.png,
#   damage-tension-gravity.png, damage-compression.png, envelope-drift.png,
#   damage-by-group.csv, views.json                   (ParaView: scripts/pv_post.py)
#   monitors.png                                      (matplotlib: scripts/plot_monitors.py)
# --names: the job's Gmsh file or a groups.csv, for the group names (default: the folder's
# groups.csv, which the time history writes). --cut-y: the section's plane (default: the model's
# centre). A missing result file is an error (exit 1). Without ParaView (scripts/setup.sh
# --paraview) or matplotlib, the pictures that need them are skipped with the reason, exit 0.
# PVPYTHON=/path/to/pvpython picks another ParaView (default: pvpython on PATH).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
usage() { sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; }

dir="" names="" size="1600x1200" cut=()
while [ $# -gt 0 ]; do
  case "$1" in
    --names|--mesh) names="${2:?$1 needs a file}"; shift 2 ;;
    --size) size="${2:?--size needs WxH}"; shift 2 ;;
    --cut-y) cut=(--cut-y "${2:?--cut-y needs a number}"); shift 2 ;;
    -h|--help) usage; exit 0 ;;
    -*) echo "post.sh: unknown option '$1'" >&2; usage >&2; exit 2 ;;
    *) [ -z "$dir" ] || { echo "post.sh: one results folder, got '$dir' and '$1'" >&2; exit 2; }
       dir="$1"; shift ;;
  esac
done
[ -n "$dir" ] || { usage >&2; exit 2; }
[ -d "$dir" ] || { echo "post.sh: $dir: no such results folder (run the job first)" >&2; exit 1; }
missing=()
for f in results.xdmf results.h5; do
  [ -f "$dir/$f" ] || missing+=("$f")
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "post.sh: $dir: missing ${missing[*]} (a time history writes them: did the job run?)" >&2
  exit 1
fi
[ -z "$names" ] || [ -f "$names" ] || { echo "post.sh: --names: no such file: $names" >&2; exit 1; }
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
  echo "post: rendering with ParaView ($("$pvpython" --version 2>/dev/null | head -n 1))"
  status=0
  bash "$here/with_display.sh" "$pvpython" "$here/pv_post.py" "$dir" --out "$pictures" --size "$size" \
    ${names:+--names "$names"} "${cut[@]}" || status=$?
  if [ "$status" -ne 0 ]; then
    echo "post.sh: the ParaView post-processing failed (exit $status)" >&2
    exit "$status"
  fi
fi

# The monitors, the base shear and the drifts in one picture: any Python with matplotlib.
source "$here/env.sh"
py=$(matplotlib_python)
if [ ! -f "$dir/monitors.csv" ]; then
  skipped+=("monitors.png (no monitors.csv in $dir)")
elif [ -n "$py" ]; then
  "$py" "$here/plot_monitors.py" "$dir/monitors.csv" --out "$pictures/monitors.png"
else
  skipped+=("monitors.png (no Python with matplotlib: apt-get install python3-matplotlib; monitor-<name>.png are in $dir)")
fi

echo "post: pictures in $pictures:"
(cd "$pictures" && ls -1 | sed 's/^/  /')
for s in "${skipped[@]+"${skipped[@]}"}"; do
  echo "post: skipped $s"
done
exit 0
