#!/bin/sh
# run_pytest.sh BUILD ROOT [--real] PYTEST-ARGS...: the farm driver's tests in the pinned venv
# (./zz test creates it), on the driver's source tree. Exit 77 (ctest: skipped) without the
# venv, or with --real while the renderer lacks `info`/`merge`/`--region`.
set -eu
BUILD="$1"
ROOT="$2"
shift 2
PY="$BUILD/venv/bin/python"
if [ ! -x "$PY" ]; then
  echo "SKIP: $PY missing: create the venv with ./zz test or ./zz farm (pinned farm/pyproject.toml)"
  exit 77
fi
export PYTHONPATH="$ROOT/farm${PYTHONPATH:+:$PYTHONPATH}"
export ZIGZAG_BIN="$BUILD/zigzag"
cd "$ROOT/tests/farm"
if [ "${1:-}" = "--real" ]; then
  shift
  if ! "$PY" -c "import sys, conftest; sys.exit(0 if conftest.real_renderer_supports_farm() else 1)"; then
    echo "SKIP: $ZIGZAG_BIN has no info --json / merge / --region yet"
    exit 77
  fi
fi
exec "$PY" -m pytest -q -p no:cacheprovider "$@"
