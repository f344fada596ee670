"""The transport file as a Python user sees it: h5py opens it, the rows are
float16, and the furnace test holds when computed in numpy from the file alone."""
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

cli = sys.argv[1]
with tempfile.TemporaryDirectory() as tmp:
    path = os.path.join(tmp, "sphere.h5")
    subprocess.run([cli, "precompute", "--scene", "sphere", "--size", "12x12", "--cubemap", "8",
                    "--quiet", "--out", path], check=True)
    with h5py.File(path, "r") as f:
        assert f.attrs["complete"] == 1
        assert f.attrs["format"] == b"adaptive-cpca transport" or f.attrs["format"] == "adaptive-cpca transport"
        t = f["transport"]
        assert t.dtype == np.float16, t.dtype
        rows = int(f.attrs["occupied_pixels"])
        assert t.shape == (rows, 6 * 8 * 8), t.shape
        omega = f["lattice_solid_angle"][:]
        assert abs(omega.sum() / (4 * np.pi) - 1) < 1e-9
        b = f["albedo"][:, 0] * (t[:].astype(np.float64) @ omega)
        assert np.all(np.abs(b - 0.5) < 0.5 * 0.005), (b.min(), b.max())
        pixels = f["pixels"][:]
        assert np.all(np.diff(pixels) > 0)
print("h5py check: 1 passed, 0 failed")
