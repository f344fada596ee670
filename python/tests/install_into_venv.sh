#!/bin/bash
# Installs the module into a new virtual environment (Debian's python, system
# site packages for numpy) and relights a fixture from outside the build tree.
# Usage: install_into_venv.sh PYTHON BUILD_DIR TRANSPORT_FILE
set -euo pipefail
python=$1 build=$2 transport=$(realpath "$3")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$python" -m venv --without-pip --system-site-packages "$work/venv"
cmake --install "$build" --component python --prefix "$work/venv" > /dev/null
cd "$work"
PYTHONPATH= "$work/venv/bin/python" - "$transport" <<'PY'
import sys
import adaptive_cpca as ac
assert ac.__file__.startswith(sys.prefix), f"imported {ac.__file__}, not the venv's copy"
r = ac.open(sys.argv[1])
image = r.relight(ac.Environment("sky"))
assert image.shape == (r.height, r.width, 3) and image.max() > 0, image.shape
# The image codecs load on the first image, from beside the installed module.
def mapped(name):
    with open("/proc/self/maps") as maps:
        return [line.split()[-1] for line in maps if name in line]
assert not mapped("libOpenImageIO"), "OpenImageIO loaded by the import"
with open("pixel.ppm", "wb") as ppm:  # a 2x1 binary PPM, written by hand
    ppm.write(b"P6 2 1 255\n" + bytes([255, 0, 0, 0, 0, 255]))
assert ac.read_image("pixel.ppm").shape == (1, 2, 3)
codecs = mapped("libacpca_image_codecs")
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
if torch is not None:  # the pure-Python part, installed beside the compiled one
    import adaptive_cpca.torch as act
    from adaptive_cpca.torch import RelightDataset, TorchRelighter  # noqa: F401
    assert act.__file__.startswith(sys.prefix), act.__file__
    assert act.lattice.CubeLattice(2).size == 24
print("installed module relit", sys.argv[1], "from", ac.__file__, "with", codecs[0])
PY
