"""Captured transport from Python: import_transport against the CLI's import,
and an imported set relit by the Relighter as its images say it should be.

Run by ctest (python_tests) with PYTHONPATH at the built module and ACPCA_CLI
the adaptive-cpca binary.
"""

import os
import subprocess

import h5py
import numpy as np
import pytest

import adaptive_cpca as ac
from adaptive_cpca._contract import TRANSPORT_VERSION

CLI = os.environ["ACPCA_CLI"]


def spiral(n):
    """n directions spread evenly over the sphere (the golden-angle spiral)."""
    i = np.arange(n) + 0.5
    y = 1 - 2 * i / n
    r = np.sqrt(1 - y * y)
    a = np.pi * (3 - np.sqrt(5)) * np.arange(n)
    return np.stack([r * np.cos(a), y, r * np.sin(a)], axis=1)


def test_an_imported_array_relights_as_the_sum_of_its_images_over_the_cells(tmp_path):
    rng = np.random.default_rng(7)
    n, h, w = 12, 5, 7
    images = rng.uniform(0.0, 2.0, size=(n, h, w, 3)).astype(np.float32)
    directions = spiral(n) * 3.0  # any length: normalised
    intensities = rng.uniform(0.5, 2.0, size=(n, 3))
    calls = []
    out = str(tmp_path / "set.h5")
    report = ac.import_transport(images, directions, out=out, intensities=intensities,
                                 precision="f32", progress=lambda done, total: calls.append(done))
    assert report["lights"] == n and report["channels"] == 3
    assert report["occupied_pixels"] == h * w and calls[-1] == h
    with h5py.File(out) as f:
        assert f.attrs["cubemap"] == 0 and f.attrs["version"] == TRANSPORT_VERSION
        cells = f["light_solid_angle"][:]
        assert abs(cells.sum() + report["uncovered_sr"] - 4 * np.pi) < 1e-6
    # Under constant radiance 1 each light's lighting is its cell's solid angle.
    r = ac.Relighter(out)
    lighting = r.lighting(ac.Environment("constant:1"))
    assert lighting.domain == f"{n} lights" and lighting.values.shape == (n, 3)
    assert np.allclose(lighting.values, cells[:, None], rtol=1e-9, atol=0)
    relit = r.relight(ac.Environment("constant:1"))
    expected = np.einsum("khwc,kc->hwc", images.astype(np.float64), cells[:, None] / intensities)
    assert relit.shape == (h, w, 3)
    assert np.max(np.abs(relit - expected) / expected) < 1e-5


def test_import_of_files_writes_the_bytes_the_cli_writes(tmp_path):
    # Six small EXR images: what the lattice sees of suns in six places.
    names, lines = [], ["image,x,y,z"]
    for k, d in enumerate(spiral(6)):
        name = f"olat_{k}.exr"
        theta = np.degrees(np.arccos(d[1]))
        subprocess.run([CLI, "envmap", f"sun:{theta:.3f},{30 * k},20,10", "--cubemap", "4",
                        "--size", "8x4", "--quiet", "--out", str(tmp_path / name)], check=True)
        names.append(str(tmp_path / name))
        lines.append(f"{name},{d[0]!r},{d[1]!r},{d[2]!r}")
    (tmp_path / "set.csv").write_text("\n".join(lines) + "\n")
    subprocess.run([CLI, "import", str(tmp_path / "set.csv"), "--quiet", "--out",
                    str(tmp_path / "set.h5")], check=True)
    os.mkdir(tmp_path / "py")
    ac.import_transport(names, spiral(6), out=str(tmp_path / "py" / "set.h5"))
    assert (tmp_path / "set.h5").read_bytes() == (tmp_path / "py" / "set.h5").read_bytes()


def test_bad_sets_are_refused_and_nothing_is_written(tmp_path):
    images = np.ones((3, 2, 2, 3), np.float32)
    out = str(tmp_path / "x.h5")
    with pytest.raises(ValueError, match="directions.*must be 3 x 3"):
        ac.import_transport(images, spiral(2), out=out)
    with pytest.raises(ValueError, match=r"directions\[2\] is the same as directions\[0\]"):
        ac.import_transport(images, np.array([[0, 1, 0], [1, 0, 0], [0, 2, 0]]), out=out)
    with pytest.raises(ValueError, match="must not be zero"):
        ac.import_transport(images, np.array([[0, 1, 0], [1, 0, 0], [0, 0, 0]]), out=out)
    bad = images.copy()
    bad[1, 0, 1, 2] = np.nan
    with pytest.raises(ValueError, match=r"images\[1\]: pixel \(1, 0\) is not a finite number"):
        ac.import_transport(bad, spiral(3), out=out)
    with pytest.raises(FileNotFoundError):
        ac.import_transport([str(tmp_path / f"missing{k}.png") for k in (0, 1)], spiral(2), out=out)
    # One light's cell is the whole sphere: every relight would be its image scaled.
    with pytest.raises(ValueError, match=r"images: 1 light\(s\); a light set needs at least 2"):
        ac.import_transport(images[:1], spiral(1), out=out)
    assert not os.path.exists(out)
