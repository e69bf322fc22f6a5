#!/usr/bin/env bash
# The church job's pictures: scripts/post_church.sh <results dir> [--mesh FILE] [--size WxH]
#
# scripts/post.sh with the church's mesh for the substructure names (default meshes/church.msh)
# and its section on the nave axis (y = 0); then, for the church's comparisons
# (scripts/compare_church.py), damage-by-group.csv again as damage-by-substructure.csv (its
# column "group" named "substructure") and a copy of <results dir>/spectrum.png when the run drew
# one. Writes into <results dir>/pictures/ what post.sh writes (its header), and those two.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
usage() { sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'; }

dir="" mesh="$here/../meshes/church.msh" size="1600x1200"
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
[ -f "$mesh" ] || mesh=""
bash "$here/post.sh" "$dir" --size "$size" --cut-y 0 ${mesh:+--names "$mesh"}
table="$dir/pictures/damage-by-group.csv"
if [ -f "$table" ]; then
  sed '1s/^state,group,/state,substructure,/' "$table" > "$dir/pictures/damage-by-substructure.csv"
fi
if [ -f "$dir/spectrum.png" ]; then
  cp "$dir/spectrum.png" "$dir/pictures/spectrum.png"
fi
