#!/usr/bin/env bash
# The Python package's CI step (for .ci/run): builds and installs the extension from this
# checkout with its extras (maturin, numpy, dask, distributed, pytest, mypy come from
# PyPI), then runs its tests. The real-mesh tests read the first shared/meshes above the
# repository or $MULTIRES_MESHES; the OpenMesh tests need `openmesh` (installed by .ci/run);
# the comparison with the command line uses $MULTIRES_BIN or target/release/multires when
# present.
set -euo pipefail
cd "$(dirname "$0")/.."
python3 -m pip install "./python[dask,test]" ||
    python3 -m pip install --break-system-packages "./python[dask,test]"
python3 -m pytest python/tests -q "$@"
