#!/bin/sh
# A renderer that only takes time, started in a millisecond so the benchmark measures the
# driver, not this: `render SCENE -o OUT --frame F ...` sleeps for F's duration from SCENE
# (lines "FRAME SECONDS") and writes "frame F" to OUT, so each output can be checked.
set -eu
[ "$1" = render ] || { echo "zigzag: error: only render is simulated" >&2; exit 1; }
scene=$2
shift 2
out="" frame=""
while [ $# -gt 0 ]; do
  case "$1" in
    -o) out=$2; shift ;;
    --frame) frame=$2; shift ;;
  esac
  shift
done
seconds=$(awk -v f="$frame" '$1 == f { print $2 }' "$scene")
sleep "${seconds:?no duration for frame $frame}"
printf 'frame %s\n' "$frame" > "$out"
