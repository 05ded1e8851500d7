#!/usr/bin/env bash
# The Python package's CI step (called by .ci/run): build and install the extension from
# this checkout with its extras, then run its tests.
set -euo pipefail
cd "$(dirname "$0")/.."
python3 -m pip install "./python[dask,test]"
python3 -m pytest python/tests -q "$@"
