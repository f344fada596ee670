#!/bin/bash
# Builds the wheel (target python_wheel: Debian's python3-build, offline),
# installs it with pip --no-index into a new virtual environment (Debian's
# python, system site packages for numpy) and relights a fixture from outside
# the build tree, with the image codecs from inside the installed package.
# Usage: wheel_into_venv.sh PYTHON BUILD_DIR TRANSPORT_FILE VERSION
set -euo pipefail
python=$1 build=$2 transport=$(realpath "$3") version=$4
cmake --build "$build" --target python_wheel > /dev/null
wheel=$(ls "$build"/python/dist/adaptive_cpca-"$version"-*.whl)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$python" -m venv --system-site-packages "$work/venv"
cd "$work"
PYTHONPATH= "$work/venv/bin/python" -m pip install -q --no-index "$wheel" 2> pip.log ||
  { cat pip.log >&2; exit 1; }
PYTHONPATH= "$work/venv/bin/python" - "$transport" "$version" <<'PY'
import sys
import adaptive_cpca as ac
assert ac.__file__.startswith(sys.prefix), f"imported {ac.__file__}, not the venv's copy"
assert ac.__version__ == sys.argv[2], (ac.__version__, sys.argv[2])
r = ac.open(sys.argv[1])
image = r.relight(ac.Environment("sky"))
assert image.shape == (r.height, r.width, 3) and image.max() > 0, image.shape
with open("pixel.ppm", "wb") as ppm:  # the first image file loads the codecs
    ppm.write(b"P6 2 1 255\n" + bytes([255, 0, 0, 0, 0, 255]))
assert ac.read_image("pixel.ppm").shape == (1, 2, 3)
with open("/proc/self/maps") as maps:
    codecs = [line.split()[-1] for line in maps if "libacpca_image_codecs" in line]
assert codecs and all(c.startswith(sys.prefix) for c in codecs), codecs
# The generated contract ships with the package, and the draws use it.
from adaptive_cpca import _contract, sampling
assert _contract.__file__.startswith(sys.prefix), _contract.__file__
assert _contract.VERSION == ac.__version__, (_contract.VERSION, ac.__version__)
assert sampling.draw(3, 2, seed=1) == sampling.pure_draw(3, 2, seed=1)
try:
    import torch
except ImportError:
    torch = None
if torch is not None:
    import adaptive_cpca.torch as act
    from adaptive_cpca.torch import RelightDataset, TorchRelighter  # noqa: F401
    assert act.__file__.startswith(sys.prefix), act.__file__
    assert act.lattice.CubeLattice(2).size == 24
print("wheel", sys.argv[2], "installed and relit", sys.argv[1], "with", codecs[0])
PY
