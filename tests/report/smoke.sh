#!/bin/sh
# report_quick: check the report's logic on made-up rows, then run the quick report into
# BUILD/report-quick and check what it wrote.
set -eu
BUILD="$1"
ROOT="$2"
PY="$BUILD/venv/bin/python"
if [ ! -x "$PY" ]; then
  echo "SKIP: $PY missing: create the venv with ./zz report (pinned tools/requirements.txt)"
  exit 77
fi
"$PY" "$ROOT/tests/report/check_logic.py"  # the report's logic on made-up rows: seconds, no rendering
OUT="$BUILD/report-quick"
rm -rf "$OUT"  # the check reads this run's outputs, not an earlier run's
"$PY" "$ROOT/tools/report/report.py" --build "$BUILD" --quick --out "$OUT"
"$PY" "$ROOT/tests/report/check_quick.py" "$BUILD" "$ROOT" "$OUT"
