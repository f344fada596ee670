"""What the Python tests share: the CLI, the fixture transport, and helpers
that run the CLI or write a map. Run by ctest (python_tests) with PYTHONPATH
at the built module, ACPCA_CLI the adaptive-cpca binary and
ACPCA_FIXTURE_DIR the transports the build makes."""

import os
import subprocess

import numpy as np

import adaptive_cpca as ac

CLI = os.environ["ACPCA_CLI"]
TRANSPORT = os.path.join(os.environ["ACPCA_FIXTURE_DIR"], "small-plant.h5")
# Debian's blender-data world maps.
WORLD = "/usr/share/blender/datafiles/studiolights/world"


def cli(*args):
    subprocess.run([CLI, *args, "--quiet"], check=True)


def cli_image(tmp_path, source, *args):
    out = str(tmp_path / "cli.exr")
    cli("relight", source, "--exr-float", "--out", out, *args)
    return ac.read_image(out)


def cli_error(*args):
    """The CLI's error message for args (it must fail as a user error)."""
    r = subprocess.run([CLI, *args], capture_output=True, text=True)
    assert r.returncode == 1, r.stderr
    return r.stderr.strip().split("error: ", 1)[1]


def write_pfm(path, rgb):
    """A portable float map (rows stored bottom to top), as OpenImageIO reads it."""
    height, width, _ = rgb.shape
    with open(path, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (width, height))
        f.write(np.ascontiguousarray(rgb[::-1], dtype="<f4").tobytes())
