#!/usr/bin/env bash
# Runs a command on a private virtual X display, for ParaView's pictures on machines without a screen.
#
#     scripts/with_display.sh pvpython scripts/pv_church.py meshes/church.msh --out mesh.png
#
# Xvfb picks a free display number itself and writes it to a pipe only once it accepts connections
# (`-displayfd`). So two renders started at the same moment cannot take the same display, and the
# command never starts before its display is ready, which `xvfb-run -a` guarantees neither of (its
# free-number scan races, and its readiness wait is skipped where SIGUSR1 is ignored).
# The exit status is the command's; the display is shut down on every exit path.
set -euo pipefail
[ "$#" -ge 1 ] || { echo "usage: scripts/with_display.sh COMMAND [ARGS...]" >&2; exit 2; }
command -v Xvfb >/dev/null 2>&1 || {
  echo "with_display.sh: Xvfb is not installed (scripts/setup.sh --paraview)" >&2
  exit 127
}
work="$(mktemp -d)"
xpid=""
cleanup() {
  if [ -n "$xpid" ]; then
    kill "$xpid" 2>/dev/null || true
    wait "$xpid" 2>/dev/null || true
  fi
  rm -rf "$work"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# 24-bit colour: ParaView's OpenGL context needs it; 2560x1600 holds every picture size the scripts use.
Xvfb -displayfd 3 -screen 0 2560x1600x24 -nolisten tcp -noreset 3>"$work/display" 2>"$work/xvfb.log" &
xpid=$!
number=""
for _ in $(seq 1 600); do # up to 60 s on a loaded machine
  if grep -q . "$work/display" 2>/dev/null && [ "$(tail -c 1 "$work/display" | od -An -c | tr -d ' ')" = '\n' ]; then
    number="$(head -n 1 "$work/display")"
    break
  fi
  if ! kill -0 "$xpid" 2>/dev/null; then
    echo "with_display.sh: Xvfb exited before its display was ready:" >&2
    cat "$work/xvfb.log" >&2
    xpid=""
    exit 1
  fi
  sleep 0.1
done
[ -n "$number" ] || {
  echo "with_display.sh: Xvfb gave no display within 60 s" >&2
  cat "$work/xvfb.log" >&2
  exit 1
}
status=0
DISPLAY=":$number" "$@" || status=$?
exit "$status"
