"""adaptive_cpca.torch against the compiled relighter and the file's definition.

Run by ctest (python_tests) with PYTHONPATH at the built package, ACPCA_CLI
the adaptive-cpca binary and ACPCA_FIXTURE_DIR the transports the build
makes. Skipped where PyTorch is not installed (Debian's python3-torch).
"""

import os
import subprocess
import sys

import numpy as np
import pytest

torch = pytest.importorskip("torch")

import adaptive_cpca as ac  # noqa: E402
from adaptive_cpca.torch import TorchRelighter  # noqa: E402

CLI = os.environ["ACPCA_CLI"]
FIXTURES = os.environ["ACPCA_FIXTURE_DIR"]
PLANT = os.path.join(FIXTURES, "small-plant.h5")
BOUNCED = os.path.join(FIXTURES, "bounced-plant.h5")


def compress(tmp_path_factory, source, *args):
    path = str(tmp_path_factory.mktemp("m") / "model.h5")
    subprocess.run([CLI, "compress", source, *args, "--quiet", "--out", path], check=True)
    return path


def lightings_for(path, specs=("sky", "sun:50,30,4,1000", "constant:0.5")):
    """The compiled relighter, its Lightings of environment specs (turned 15
    degrees more each) and their values stacked [B, l, 3]."""
    r = ac.open(path)
    made = [r.lighting(ac.Environment(s), yaw=15.0 * k) for k, s in enumerate(specs)]
    return r, made, np.stack([m.values for m in made])


def expect_close(mine, theirs, what):
    scale = max(1e-6, float(np.abs(theirs).max()))
    worst = float(np.abs(mine - theirs).max()) / scale
    assert worst < 2e-5, f"{what}: worst difference {worst:.2e} of the largest value"


MODELS = [
    ("adaptive-quad", ()),
    ("adaptive-binary", ("--coeffs", "i8", "--bases", "f16")),
    ("cpca", ("--clusters", "6", "--coeffs", "f16")),
    ("block", ("--coeffs", "i8")),
    ("global", ()),
]


@pytest.mark.parametrize("method,flags", MODELS, ids=[m for m, _ in MODELS])
def test_every_method_and_precision_relights_as_the_compiled_relighter(tmp_path_factory, method,
                                                                        flags):
    path = compress(tmp_path_factory, PLANT, "--method", method, *flags)
    r, made, lightings = lightings_for(path)
    mine = TorchRelighter(path).relight(torch.from_numpy(lightings), layout="hwc").numpy()
    assert mine.shape == (len(lightings), r.height, r.width, 3)
    for k, lighting in enumerate(made):
        expect_close(mine[k], r.relight(lighting, background="black"), f"{method} frame {k}")


def test_rgb_row_models_and_captured_sets_relight_as_the_compiled_relighter(tmp_path_factory,
                                                                            tmp_path):
    rgb = compress(tmp_path_factory, BOUNCED, "--method", "adaptive-quad")
    r, made, lightings = lightings_for(rgb, ("sky", "sun:40,200,10,500"))
    assert TorchRelighter(rgb).channels == 3
    mine = TorchRelighter(rgb).relight(lightings, layout="hwc").numpy()
    for k, lighting in enumerate(made):
        expect_close(mine[k], r.relight(lighting, background="black"), f"RGB rows, frame {k}")
    # A captured light set: 12 images of a random subject over a spiral of lights.
    rng = np.random.default_rng(3)
    n = 12
    i = np.arange(n) + 0.5
    y = 1 - 2 * i / n
    a = np.pi * (3 - np.sqrt(5)) * np.arange(n)
    directions = np.stack([np.sqrt(1 - y * y) * np.cos(a), y, np.sqrt(1 - y * y) * np.sin(a)], 1)
    images = rng.uniform(0, 1, size=(n, 6, 8, 3)).astype(np.float32)
    captured = str(tmp_path / "set.h5")
    ac.import_transport(images, directions, out=captured, precision="f32")
    model = compress(tmp_path_factory, captured, "--method", "adaptive-quad", "--coeffs", "i8")
    r, made, lightings = lightings_for(model, ("sky",))
    mine = TorchRelighter(model).relight(lightings, layout="hwc").numpy()[0]
    expect_close(mine, r.relight(made[0], background="black"), "captured set")


def test_the_relit_rows_are_the_formats_definition(tmp_path_factory):
    # docs/formats.md: albedo_p (u_p . W_c^T V_g^T L + mean_c . V_g^T L), in float64.
    import h5py
    path = compress(tmp_path_factory, PLANT, "--method", "adaptive-binary", "--coeffs", "i8")
    rng = np.random.default_rng(5)
    with h5py.File(path) as f:
        l = f["global_basis"].shape[0]
        lighting = rng.uniform(0, 1, size=(l, 3))
        vg = f["global_basis"][:].astype(np.float64)
        rows, offsets = f["cluster_rows"][:], f["cluster_row_offsets"][:]
        ranks, bases, means = f["cluster_rank"][:], f["bases"][:], f["means"][:]
        basis_offsets, coefficients = f["cluster_basis_offsets"][:], f["coefficients"][:]
        coefficient_offsets, scale = f["coefficient_offsets"][:], f["coefficient_scale"][:]
        albedo = f["albedo"][:].astype(np.float64)
        n = vg.shape[1]
        projected = vg.T @ lighting
        expected = np.zeros((len(rows), 3))
        first = 0
        for c in range(len(ranks)):
            k = ranks[c]
            wt = bases[basis_offsets[c]:basis_offsets[c + 1]].astype(np.float64).reshape(k, n)
            p = offsets[c + 1] - offsets[c]
            u = coefficients[coefficient_offsets[c]:coefficient_offsets[c] + p * k]
            u = u.astype(np.float64).reshape(p, k) * scale[first:first + k]
            value = u @ (wt @ projected) + means[c * n:(c + 1) * n].astype(np.float64) @ projected
            expected[rows[offsets[c]:offsets[c + 1]]] = value
            first += k
    mine = TorchRelighter(path).relit_rows(torch.from_numpy(lighting)).double().numpy()[0]
    expect_close(mine, expected * albedo, "relit rows")


def test_layouts_backgrounds_and_negative_values(tmp_path_factory):
    path = compress(tmp_path_factory, PLANT, "--method", "cpca", "--clusters", "4")
    r, made, lightings = lightings_for(path, ("sky",))
    t = TorchRelighter(path)
    chw = t.relight(lightings)
    assert tuple(chw.shape) == (1, 3, r.height, r.width)
    hwc = t.relight(lightings, layout="hwc")
    assert torch.equal(chw.permute(0, 2, 3, 1), hwc)
    alpha = t.relight(lightings, background="alpha", layout="hwc").numpy()[0]
    expect_close(alpha, r.relight(made[0], background="alpha"), "alpha")
    # A lighting with negative texels makes negative values: clamped unless kept.
    negative = torch.from_numpy(-lightings)
    assert float(t.relight(negative).min()) == 0.0
    kept = t.relight(negative, keep_negative=True)
    assert float(kept.min()) < 0
    # Relighting is linear in the lighting.
    expect_close(kept.numpy(), -t.relight(lightings, keep_negative=True).numpy(), "linearity")


def test_bad_input_is_refused_in_words(tmp_path_factory, tmp_path):
    path = compress(tmp_path_factory, PLANT, "--method", "global")
    t = TorchRelighter(path)
    with pytest.raises(ValueError, match=r"\[B, 384, 3\]"):
        t.relight(torch.zeros(2, 10, 3))
    with pytest.raises(ValueError, match="not finite"):
        t.relight(torch.full((384, 3), float("nan")))
    with pytest.raises(ValueError, match="'black' or 'alpha'"):
        t.relight(torch.zeros(384, 3), background="env")
    with pytest.raises(ValueError, match="not an adaptive-cpca model"):
        TorchRelighter(PLANT)


def test_the_torch_module_imports_and_relights_without_the_compiled_part(tmp_path_factory,
                                                                         tmp_path):
    # A copy of the package's pure-Python files alone, as on a machine whose
    # Python the compiled module was not built for.
    import shutil
    path = compress(tmp_path_factory, PLANT, "--method", "adaptive-quad")
    package = tmp_path / "adaptive_cpca"
    package.mkdir()
    for name in ("__init__.py", "torch.py"):
        shutil.copy(os.path.join(os.path.dirname(ac.__file__), name), package / name)
    script = ("import sys, torch\n"
              "from adaptive_cpca.torch import TorchRelighter\n"
              "import adaptive_cpca\n"
              "assert adaptive_cpca.__file__.startswith(sys.argv[2]), adaptive_cpca.__file__\n"
              "assert adaptive_cpca._core is None\n"
              "t = TorchRelighter(sys.argv[1])\n"
              "print(float(t.relight(torch.ones(t.lattice_size, 3)).sum()))\n")
    # Run from the copy's directory: the build's package must not be on the path.
    done = subprocess.run([sys.executable, "-c", script, path, str(tmp_path)], capture_output=True,
                          text=True, cwd=tmp_path, env={**os.environ, "PYTHONPATH": str(tmp_path)})
    assert done.returncode == 0, done.stderr
    assert float(done.stdout) > 0
