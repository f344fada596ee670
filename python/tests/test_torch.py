"""adaptive_cpca.torch against the compiled relighter and the file's definition.

Run by ctest (python_tests) with PYTHONPATH at the built package, ACPCA_CLI
the adaptive-cpca binary and ACPCA_FIXTURE_DIR the transports the build
makes. Skipped where PyTorch is not installed (Debian's python3-torch).
"""

import glob
import json
import os
import subprocess
import sys

import numpy as np
import pytest

torch = pytest.importorskip("torch")

import adaptive_cpca as ac  # noqa: E402
from adaptive_cpca._contract import MODEL_VERSION, OLDEST_MODEL_VERSION  # noqa: E402
from adaptive_cpca.torch import TorchRelighter  # noqa: E402

CLI = os.environ["ACPCA_CLI"]
FIXTURES = os.environ["ACPCA_FIXTURE_DIR"]
PLANT = os.path.join(FIXTURES, "small-plant.h5")
BLENDER_WORLDS = "/usr/share/blender/datafiles/studiolights/world"
BOUNCED = os.path.join(FIXTURES, "bounced-plant.h5")


def compress(tmp_path_factory, source, *args):
    path = str(tmp_path_factory.mktemp("m") / "model.h5")
    subprocess.run([CLI, "compress", source, *args, "--quiet", "--out", path], check=True)
    return path


# A whole map through the lattice is compared with the compiled relighter's
# sun="off"; exact suns in test_torch_sun.py.

def lightings_for(path, specs=("sky", "sun:50,30,4,1000", "constant:0.5")):
    """The compiled relighter, its Lightings of environment specs (turned 15
    degrees more each) and their values stacked [B, l, 3]."""
    r = ac.open(path)
    made = [r.lighting(ac.Environment(s), sun="off", yaw=15.0 * k) for k, s in enumerate(specs)]
    return r, made, np.stack([m.values for m in made])


def expect_close(mine, theirs, what):
    scale = max(1e-6, float(np.abs(theirs).max()))
    worst = float(np.abs(mine - theirs).max()) / scale
    assert worst < 2e-5, f"{what}: worst difference {worst:.2e} of the largest value"


def relative_l2(mine, theirs):
    return float(np.linalg.norm(mine - theirs) / np.linalg.norm(theirs))


MODELS = [
    ("adaptive-quad", ()),
    ("adaptive-binary", ("--coeffs", "i8", "--bases", "f16")),
    ("cpca", ("--clusters", "6", "--coeffs", "f16")),
    ("block", ("--coeffs", "i8")),
    ("global", ()),
]
# The bounds: relative L2 per image, the order of additions differing.
F32_BOUND, STORED_LOW_BOUND = 1e-6, 1e-5


@pytest.mark.parametrize("method,flags", MODELS, ids=[m for m, _ in MODELS])
def test_every_method_and_precision_relights_as_the_compiled_relighter(tmp_path_factory, method,
                                                                        flags):
    # Lightings made in torch, images against the module's own end to end.
    # Both kernels: a dense product per cluster, and one sparse product a span.
    path = compress(tmp_path_factory, PLANT, "--method", method, *flags)
    r = ac.open(path)
    frames = [("sky", 0, 0, 0), ("sun:50,30,4,1000", 15, 10, 0), ("constant:0.5", 30, 0, 5)]
    bound = F32_BOUND if not flags else STORED_LOW_BOUND
    for kernel in ("clusters", "sparse"):
        t = TorchRelighter(path, kernel=kernel)
        lightings = torch.stack([t.lighting(s, y, p, q) for s, y, p, q in frames])
        mine = t.relight(lightings, layout="hwc").numpy()
        assert mine.shape == (len(frames), r.height, r.width, 3)
        for k, (spec, yaw, pitch, roll) in enumerate(frames):
            theirs = r.relight(ac.Environment(spec), sun="off", yaw=yaw, pitch=pitch, roll=roll,
                               background="black")
            error = relative_l2(mine[k], theirs)
            assert error <= bound, f"{method} {kernel} {spec}: relative L2 {error:.2e} > {bound:g}"


def test_rgb_row_models_relight_as_the_compiled_relighter(tmp_path_factory):
    path = compress(tmp_path_factory, BOUNCED, "--method", "adaptive-quad")
    r, t = ac.open(path), TorchRelighter(path)
    assert t.channels == 3
    for spec, yaw in [("sky", 0), ("sun:40,200,10,500", 45)]:
        mine = t.relight(t.lighting(spec, yaw), layout="hwc").numpy()[0]
        theirs = r.relight(ac.Environment(spec), sun="off", yaw=yaw, background="black")
        assert relative_l2(mine, theirs) <= F32_BOUND, spec


def map_files(tmp_path):
    """A map of every kind the reader takes: a Blender world EXR (where
    blender-data is installed), a cube cross from `envmap`, a .pfm written
    here and a run-length .hdr written by OpenImageIO (where its binding is)."""
    worlds = sorted(glob.glob(os.path.join(BLENDER_WORLDS, "*.exr")))
    rng = np.random.default_rng(11)
    latlong = rng.gamma(0.5, 1.0, size=(64, 128, 3)).astype(np.float32)
    latlong[10:12, 30:32] = 500.0  # a small bright sun
    pfm = str(tmp_path / "map.pfm")
    with open(pfm, "wb") as f:  # PFM rows run bottom to top
        f.write(b"PF\n128 64\n-1.0\n" + np.ascontiguousarray(latlong[::-1]).astype("<f4").tobytes())
    cross, flat = str(tmp_path / "cross.exr"), str(tmp_path / "flat.exr")
    subprocess.run([CLI, "envmap", pfm, "--cross", cross, "--out", flat, "--cubemap", "12",
                    "--quiet"], check=True)
    files = worlds[:1] + [pfm, cross]
    try:
        import OpenImageIO as oiio
    except ImportError:
        return files
    hdr = str(tmp_path / "map.hdr")
    out = oiio.ImageOutput.create(hdr)
    out.open(hdr, oiio.ImageSpec(128, 64, 3, oiio.FLOAT))
    out.write_image(latlong)
    out.close()
    return files + [hdr]


ROTATIONS = [(0, 0, 0, 0), (37, 12, -5, -1.5), (200, -80, 30, 2)]


def test_lightings_made_in_torch_equal_the_modules(tmp_path_factory, tmp_path):
    # Every --env kind, rotated and exposed, integrated in float64 both ways
    # (in torch: on the CPU, lighting='auto' would call the compiled part).
    path = compress(tmp_path_factory, PLANT, "--method", "global")
    r, t = ac.open(path), TorchRelighter(path, lighting="torch")
    specs = ["constant:0.5", "constant:1,2,3", "sun:50,30,4,1000", "sun:10,200,0.3,5e4",
             "sun:90,0,179,1", "sky"] + map_files(tmp_path)
    for spec in specs:
        env = t.environment(spec)
        for yaw, pitch, roll, exposure in ROTATIONS:
            mine = t.lighting(env, yaw, pitch, roll, exposure, dtype=torch.float64).numpy()
            theirs = r.lighting(ac.Environment(spec), sun="off", yaw=yaw, pitch=pitch, roll=roll).values
            theirs = theirs * 2.0 ** exposure
            worst = float(np.abs(mine - theirs).max() / np.abs(theirs).max())
            assert worst <= 1e-12, f"{spec} at {yaw, pitch, roll}: {worst:.2e}"
    # A hemisphere sun (its samples on texel edges, where either texel is
    # right) keeps its energy, 2 pi radiance, at any rotation.
    for yaw, pitch, roll, _ in ROTATIONS:
        energy = t.lighting("sun:90,0,180,1", yaw, pitch, roll, dtype=torch.float64).sum(0)
        assert torch.allclose(energy, torch.full((3,), 2 * np.pi, dtype=torch.float64))
    # Many rotations in one pass: each as it is alone; the map's view likewise.
    yaws, pitches, rolls, stops = (list(v) for v in zip(*ROTATIONS))
    for spec in specs:
        env = t.environment(spec)
        together = t.lighting(env, yaws, pitches, rolls, stops, dtype=torch.float64)
        alone = torch.stack([t.lighting(env, *a, dtype=torch.float64) for a in ROTATIONS])
        assert together.shape == (len(ROTATIONS), t.lattice_size, 3)
        assert torch.allclose(together, alone, rtol=1e-12, atol=0), spec
        views = t.view(env, yaws, pitches, rolls, stops)
        assert torch.equal(views, torch.stack([t.view(env, *a) for a in ROTATIONS])), spec
    # A map given as a tensor is the same map as its file.
    from adaptive_cpca.io import read_image
    pfm = [s for s in specs if s.endswith(".pfm")][0]
    given = torch.from_numpy(read_image(pfm).copy())
    assert torch.equal(t.lighting(given, 30), t.lighting(pfm, 30))
    from adaptive_cpca.torch import lighting
    assert lighting.ENVIRONMENT_GRAMMARS in ac.Environment.__init__.__doc__


def test_the_compiled_lighting_on_the_cpu_is_torchs(tmp_path_factory, tmp_path):
    # lighting='auto' on the CPU integrates through the compiled part: the
    # same values, one rotation or many, exposed; a map given as a tensor
    # and a captured set's cells stay in torch.
    path = compress(tmp_path_factory, PLANT, "--method", "global")
    fast, slow = TorchRelighter(path), TorchRelighter(path, lighting="torch")
    yaws, pitches, rolls, stops = (list(v) for v in zip(*ROTATIONS))
    for spec in ["sky", "sun:50,30,4,1000"] + map_files(tmp_path):
        env = fast.environment(spec)
        assert env.compiled() is not None
        for args in ((yaws, pitches, rolls, stops), ROTATIONS[1]):
            mine = fast.lighting(env, *args, dtype=torch.float64)
            theirs = slow.lighting(spec, *args, dtype=torch.float64)
            assert torch.allclose(mine, theirs, rtol=1e-12, atol=0), spec
    assert fast.environment(torch.ones(8, 16, 3)).compiled() is None
    with pytest.raises(ValueError, match="lighting 'gpu': 'auto' or 'torch'"):
        TorchRelighter(path, lighting="gpu")


def test_frames_over_the_map_equal_the_modules(tmp_path_factory, tmp_path):
    path = compress(tmp_path_factory, PLANT, "--method", "adaptive-quad")
    r, t = ac.open(path), TorchRelighter(path)
    for spec in ["sky", "sun:60,40,25,20"] + map_files(tmp_path):
        for yaw, pitch, roll, exposure in ROTATIONS:
            mine = t.relight_map(spec, yaw, pitch, roll, exposure, layout="hwc",
                                 sun="off").numpy()
            theirs = r.relight(ac.Environment(spec), sun="off", yaw=yaw, pitch=pitch, roll=roll,
                               exposure=exposure, background="env")
            error = relative_l2(mine, theirs)
            assert error <= F32_BOUND, f"{spec} at {yaw, pitch, roll}: relative L2 {error:.2e}"
    alpha = t.relight_map("sky", 20, background="alpha", layout="hwc", sun="off").numpy()
    theirs = r.relight(ac.Environment("sky"), sun="off", yaw=20, background="alpha")
    assert relative_l2(alpha, theirs) <= F32_BOUND


def manifest_sh9(path, specs, yaw, tmp_path):
    out = tmp_path / "batch"
    env_flags = [flag for s in specs for flag in ("--env", s)]
    # --sun off: the lattice's coefficients alone, as the closed form's.
    subprocess.run([CLI, "relight", path, *env_flags, "--rotate", str(yaw), "--background",
                    "black", "--sun", "off", "--out", str(out), "--quiet"], check=True)
    with open(out / "manifest.jsonl") as f:
        return [np.array(json.loads(line)["sh9"]) for line in f]


def spiral_directions(n):
    i = np.arange(n) + 0.5
    y = 1 - 2 * i / n
    a = np.pi * (3 - np.sqrt(5)) * np.arange(n)
    return np.stack([np.sqrt(1 - y * y) * np.cos(a), y, np.sqrt(1 - y * y) * np.sin(a)], 1)


def captured_model(tmp_path_factory, tmp_path, n, **kwargs):
    """A captured light set of n random images over a spiral of lights, compressed."""
    rng = np.random.default_rng(n)
    images = rng.uniform(0, 1, size=(n, 6, 8, 3)).astype(np.float32)
    captured = str(tmp_path / f"set-{n}.h5")
    ac.import_transport(images, spiral_directions(n), out=captured, precision="f32", **kwargs)
    return compress(tmp_path_factory, captured, "--method", "adaptive-quad", "--coeffs", "i8")


def given_cells_model(tmp_path_factory, tmp_path, n=20):
    """A light set whose lights file gives each light's cell (solid_angle)."""
    rng = np.random.default_rng(7)
    directions = spiral_directions(n)
    cells = rng.uniform(0.5, 1.5, n)
    cells *= 0.9 * 4 * np.pi / cells.sum()
    folder = tmp_path / "olat"
    folder.mkdir()
    lines = ["image,x,y,z,solid_angle"]
    for k in range(n):
        image = rng.uniform(0, 1, size=(6, 8, 3)).astype(np.float32)
        with open(folder / f"{k:03d}.pfm", "wb") as f:
            f.write(b"PF\n8 6\n-1.0\n" + np.ascontiguousarray(image[::-1]).tobytes())
        lines.append(f"{k:03d}.pfm,{','.join(map(str, directions[k]))},{cells[k]}")
    (folder / "lights.csv").write_text("\n".join(lines) + "\n")
    captured = str(tmp_path / "given.h5")
    subprocess.run([CLI, "import", str(folder / "lights.csv"), "--out", captured, "--quiet"],
                   check=True)
    return compress(tmp_path_factory, captured, "--method", "adaptive-quad")


def test_captured_sets_light_and_label_as_the_module_and_cli(tmp_path_factory, tmp_path):
    # The cells as import finds them (uncapped, capped) and as a lights file gives them.
    worlds = sorted(glob.glob(os.path.join(BLENDER_WORLDS, "*.exr")))[:1]
    models = [captured_model(tmp_path_factory, tmp_path, 12),
              captured_model(tmp_path_factory, tmp_path, 40, cell_cap=20.0),
              given_cells_model(tmp_path_factory, tmp_path)]
    for index, path in enumerate(models):
        r, t = ac.open(path), TorchRelighter(path)
        assert t.is_light_set
        for spec in ["sky", "sun:40,200,10,500"] + worlds:
            mine = t.lighting(spec, yaw=20, dtype=torch.float64).numpy()
            theirs = r.lighting(ac.Environment(spec), sun="off", yaw=20).values
            worst = float(np.abs(mine - theirs).max() / np.abs(theirs).max())
            assert worst <= 1e-12, f"{path} {spec}: {worst:.2e}"
            image = t.relight(t.lighting(spec, yaw=20), layout="hwc").numpy()[0]
            reference = r.relight(ac.Environment(spec), sun="off", yaw=20, background="black")
            assert relative_l2(image, reference) <= STORED_LOW_BOUND
        specs = ["sky", "sun:40,200,10,500"]
        expected = manifest_sh9(path, specs, 20, tmp_path / f"batch-{index}")
        for spec, sh in zip(specs, expected):
            mine = t.sh9(t.lighting(spec, yaw=20, dtype=torch.float64)).numpy()
            assert np.abs(mine - sh).max() <= 1e-9 * np.abs(sh).max(), spec
        with pytest.raises(ValueError, match="captured light set"):
            t.view("sky")


def test_sh9_labels_are_the_manifests_and_the_closed_form(tmp_path_factory, tmp_path):
    path = compress(tmp_path_factory, PLANT, "--method", "global")
    t = TorchRelighter(path)
    specs = ["sky", "sun:50,30,4,1000"]
    expected = manifest_sh9(path, specs, 35, tmp_path)
    lightings = torch.stack([t.lighting(s, yaw=35, dtype=torch.float64) for s in specs])
    mine = t.sh9(lightings).numpy()
    assert mine.shape == (2, 9, 3)
    for k, spec in enumerate(specs):
        assert np.abs(mine[k] - expected[k]).max() <= 1e-9 * np.abs(expected[k]).max(), spec
    # Constant radiance 1: Y00's coefficient is 2 sqrt(pi), the others vanish.
    constant = t.sh9(t.lighting("constant:1", dtype=torch.float64)).numpy()
    assert abs(constant[0, 0] - 2 * np.sqrt(np.pi)) < 1e-12
    assert np.abs(constant[1:]).max() < 1e-12


def test_the_relit_rows_are_the_formats_definition(tmp_path_factory, monkeypatch):
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
    # Whole spans, and spans of 1,000 values (clusters split into pieces).
    import adaptive_cpca.torch.model as torch_model
    for span in (torch_model._SPAN_ENTRIES, 1000):
        monkeypatch.setattr(torch_model, "_SPAN_ENTRIES", span)
        for kernel in ("clusters", "sparse"):
            t = TorchRelighter(path, kernel=kernel)
            assert len(t.model.spans) > 1 or span > 1000
            mine = t.relit_rows(torch.from_numpy(lighting)).double().numpy()[0]
            expect_close(mine, expected * albedo, f"relit rows, {kernel}, spans of {span}")


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
    # Into a buffer of either layout: the same values, the buffer itself.
    two = torch.from_numpy(np.concatenate([lightings, 2 * lightings]))
    for layout, channels in (("chw", 3), ("hwc", 3), ("chw", 4), ("hwc", 4)):
        background = "alpha" if channels == 4 else "black"
        fresh = t.relight(two, background=background, layout=layout)
        buffer = torch.full_like(fresh, float("nan"))
        assert t.relight(two, background=background, layout=layout, out=buffer) is buffer
        assert torch.equal(buffer, fresh), (layout, channels)
    with pytest.raises(ValueError, match=r"out: a contiguous float32 tensor \[2, 3, 40, 40\]"):
        t.relight(two, out=torch.zeros(2, 3, 40, 41))
    # One background for every lighting, or one each.
    behind = torch.rand(2, 3, r.height, r.width)
    each = t.relight(two, background=behind)
    assert relative_l2(each[1].numpy(), t.relight(two[1], background=behind[1])[0].numpy()) < 1e-6
    with pytest.raises(ValueError, match="a background of 2 images for 1 lightings"):
        t.relight(two[0], background=behind)


def test_bad_input_is_refused_in_words(tmp_path_factory, tmp_path, monkeypatch):
    path = compress(tmp_path_factory, PLANT, "--method", "global")
    t = TorchRelighter(path)
    with pytest.raises(ValueError, match=r"\[B, 384, 3\]"):
        t.relight(torch.zeros(2, 10, 3))
    with pytest.raises(ValueError, match="dtype torch.int64: float32 or float64"):
        t.relight(torch.zeros(384, 3, dtype=torch.int64))
    with pytest.raises(ValueError, match="not finite"):
        t.relight(torch.full((384, 3), float("nan")))
    with pytest.raises(ValueError, match="'black', 'alpha' or a tensor"):
        t.relight(torch.zeros(384, 3), background="env")
    with pytest.raises(ValueError, match=r"takes \[3, 40, 40\]"):
        t.relight(torch.zeros(384, 3), background=torch.zeros(3, 20, 20))
    with pytest.raises(ValueError, match="not an adaptive-cpca model"):
        TorchRelighter(PLANT)
    # Maps: NaN, more negative energy than ringing has, an aspect neither 2:1 nor 4:3.
    nan = np.ones((16, 32, 3), np.float32)
    nan[3, 5, 1] = np.nan
    with pytest.raises(ValueError, match=r"pixel \(5, 3\) channel 1 is nan; radiance must be finite"):
        t.lighting(nan)
    negative = np.ones((16, 32, 3), np.float32)
    negative[:4] = -1
    with pytest.raises(ValueError, match="not ringing but a broken map"):
        t.lighting(torch.from_numpy(negative))
    ringing = np.ones((16, 32, 3), np.float32)
    ringing[0, 0, 0] = -0.01  # 6.5e-6 of the summed magnitude
    with pytest.warns(UserWarning, match="1 negative values clamped to 0"):
        t.lighting(ringing)
    with pytest.raises(ValueError, match="neither a lat-long map"):
        t.lighting(np.ones((16, 16, 3), np.float32))
    with pytest.raises(ValueError, match="sun:THETA,PHI,SIZE_DEG,INTENSITY"):
        t.lighting("sun:1,2")
    with pytest.raises(ValueError, match="no such file, and not constant:V"):
        t.lighting(str(tmp_path / "missing.exr"))
    with pytest.raises(ValueError, match="yaw nan"):
        t.lighting("sky", yaw=float("nan"))
    # A file of a newer format version, and a device without the memory.
    import h5py
    import shutil
    newer = str(tmp_path / "newer.h5")
    shutil.copy(path, newer)
    with h5py.File(newer, "r+") as f:
        f.attrs["version"] = MODEL_VERSION + 1
    with pytest.raises(ValueError, match=f"model format version {MODEL_VERSION + 1}; this reader "
                                         f"reads {OLDEST_MODEL_VERSION} to {MODEL_VERSION}: "
                                         "written by a newer adaptive-cpca"):
        TorchRelighter(newer)
    import adaptive_cpca.torch.relighter as acpca_torch
    monkeypatch.setattr(acpca_torch, "_free_bytes", lambda device: 1000)
    with pytest.raises(MemoryError, match=r"the model needs 0\.\d+ GiB on cpu, which has 0\.00 GiB free"):
        TorchRelighter(path)


def test_the_torch_module_imports_and_relights_without_the_compiled_part(tmp_path_factory,
                                                                         tmp_path):
    # A copy of the package's pure-Python files alone, as on a machine whose
    # Python the compiled module was not built for.
    import shutil
    path = compress(tmp_path_factory, PLANT, "--method", "adaptive-quad")
    shutil.copytree(os.path.dirname(ac.__file__), tmp_path / "adaptive_cpca",
                    ignore=shutil.ignore_patterns("*.so", "__pycache__"))
    # Its map: a Blender world EXR read through OpenImageIO's binding, where
    # both are installed; else the built-in sky.
    worlds = sorted(glob.glob(os.path.join(BLENDER_WORLDS, "*.exr")))
    try:
        import OpenImageIO  # noqa: F401
        env = worlds[0] if worlds else "sky"
    except ImportError:
        env = "sky"
    script = ("import sys, torch\n"
              "from adaptive_cpca.torch import TorchRelighter\n"
              "import adaptive_cpca\n"
              "assert adaptive_cpca.__file__.startswith(sys.argv[2]), adaptive_cpca.__file__\n"
              "assert adaptive_cpca._core is None\n"
              "t = TorchRelighter(sys.argv[1])\n"
              "print(repr(float(t.lighting(sys.argv[3], yaw=30).sum())))\n"
              "print(float(t.relight_map(sys.argv[3], yaw=30).sum()))\n")
    # Run from the copy's directory: the build's package must not be on the path.
    done = subprocess.run([sys.executable, "-c", script, path, str(tmp_path), env],
                          capture_output=True, text=True, cwd=tmp_path,
                          env={**os.environ, "PYTHONPATH": str(tmp_path)})
    assert done.returncode == 0, done.stderr
    energy, image = (float(v) for v in done.stdout.split())
    # The map read without the compiled part is the map the CLI's reader reads.
    assert energy == float(TorchRelighter(path).lighting(env, yaw=30).sum())
    assert image > 0
