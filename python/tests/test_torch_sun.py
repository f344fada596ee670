"""A map's sun lit exactly in adaptive_cpca.torch: sun= as `relight --sun`,
the sources' light made by the compiled part on the CPU and the frame
composed in torch; without the compiled part, the lattice with a warning."""

import os
import shutil
import subprocess
import sys
import warnings

import numpy as np
import pytest

torch = pytest.importorskip("torch")
pytest.importorskip("h5py")

import adaptive_cpca as ac  # noqa: E402
from adaptive_cpca.torch import RelightDataset, TorchRelighter  # noqa: E402

CLI = os.environ["ACPCA_CLI"]
PLANT = os.path.join(os.environ["ACPCA_FIXTURE_DIR"], "small-plant.h5")
# A sun high in a clear sky, one low and wide, the built-in sky's.
SUNNY = ["sky", "sun:40,30,2,20000", "sun:75,200,8,600"]


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    path = str(tmp_path_factory.mktemp("m") / "model.h5")
    subprocess.run([CLI, "compress", PLANT, "--method", "adaptive-quad", "--quiet", "--out",
                    path], check=True)
    return path


def relative_l2(a, b):
    return float(np.linalg.norm(a - b) / max(np.linalg.norm(b), 1e-30))


@pytest.mark.parametrize("background", ["env", "black", "alpha"])
def test_a_maps_sun_is_lit_as_the_compiled_relighter_lights_it(model, background):
    r, t = ac.open(model), TorchRelighter(model)
    for spec in SUNNY:
        for yaw, pitch, roll, exposure in ((0, 0, 0, 0), (37, 12, -5, -1.5), (200, -30, 10, 1)):
            mine = t.relight_map(spec, yaw, pitch, roll, exposure, background=background,
                                 layout="hwc").numpy()
            theirs = r.relight(ac.Environment(spec), yaw=yaw, pitch=pitch, roll=roll,
                               exposure=exposure, background=background)
            assert relative_l2(mine, theirs) <= 1e-6, (spec, yaw)
            lattice = r.relight(ac.Environment(spec), sun="off", yaw=yaw, pitch=pitch, roll=roll,
                                exposure=exposure, background=background)
            # The exact sun is not the lattice's: shadows move by up to a
            # texel (where the turned sun is below the subject, both are black).
            assert relative_l2(theirs, lattice) > 1e-3 or np.abs(lattice[..., :3]).max() == 0, spec


def test_split_lightings_carry_the_sources_light_and_the_rest(model):
    r, t = ac.open(model), TorchRelighter(model)
    rest, light = t.split_lighting("sky", yaw=[90, 90], exposure=[0, 1], dtype=torch.float64)
    assert rest.shape == (2, t.lattice_size, 3) and light.shape == (2, t.rows, 3)
    theirs = r.lighting(ac.Environment("sky"), yaw=90)
    assert np.allclose(rest[1].numpy(), 2 * theirs.values, rtol=1e-12, atol=0)
    # The sun alone: what the whole map's lattice lighting holds beyond the rest.
    whole = t.lighting("sky", yaw=[90, 90], exposure=[0, 1], dtype=torch.float64)
    sun = (whole - rest).sum(dim=1)
    assert torch.all(sun > 0) and torch.allclose(sun[1], 2 * sun[0], rtol=1e-9)
    assert torch.allclose(light[1], 2 * light[0], rtol=1e-6, atol=0)
    # A map without a source, and sun="off": the lattice alone.
    for env, sun_mode in (("constant:0.5", "auto"), ("sky", "off")):
        lighting, none = t.split_lighting(env, yaw=30, sun=sun_mode)
        assert none is None and torch.equal(lighting, t.lighting(env, yaw=30))
    # K = 1 finds the sky's one sun; bad values are refused as the CLI refuses them.
    assert torch.equal(t.split_lighting("sky", sun=1)[1], t.split_lighting("sky")[1])
    for bad in ("on", 0, -2, True):
        with pytest.raises(ValueError, match="'auto', 'off' or a number of sources"):
            t.split_lighting("sky", sun=bad)


def test_a_map_given_as_pixels_goes_through_the_lattice_with_a_warning(model):
    t = TorchRelighter(model)
    pixels = torch.ones(16, 32, 3)
    pixels[4, 5] = 1e5  # a sun
    with pytest.warns(UserWarning, match="given as pixels.*go through the lattice"):
        frame = t.relight_map(pixels, 30)
    assert torch.equal(frame, t.relight_map(pixels, 30, sun="off"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        t.relight_map(pixels, 30, sun="off")


def test_the_dataset_lights_suns_in_the_main_process_and_refuses_in_workers(model):
    data = RelightDataset(model, SUNNY, batch_size=3, seed=5, draws=6, rotation="sphere",
                          background="black")
    alone = list(torch.utils.data.DataLoader(data, batch_size=None, num_workers=0))
    r = ac.open(model)
    for batch in alone:
        for k in range(len(batch["draw"])):
            theirs = r.relight(ac.Environment(SUNNY[int(batch["map"][k])]),
                               yaw=float(batch["yaw"][k]), pitch=float(batch["pitch"][k]),
                               roll=float(batch["roll"][k]), background="black")
            mine = batch["images"][k].permute(1, 2, 0).numpy()
            assert relative_l2(mine, theirs) <= 1e-6
    # sh9 is the whole map's, sun and all, whatever sun= says.
    off = list(RelightDataset(model, SUNNY, batch_size=3, seed=5, draws=6, rotation="sphere",
                              background="black", sun="off"))
    for a, b in zip(alone, off):
        assert torch.equal(a["sh9"], b["sh9"])
        assert not torch.equal(a["images"], b["images"])
    with pytest.raises(RuntimeError, match="num_workers=0, or pass sun='off'"):
        list(torch.utils.data.DataLoader(data, batch_size=None, num_workers=1))


def test_without_the_compiled_part_the_sun_goes_through_the_lattice_with_a_warning(model,
                                                                                    tmp_path):
    shutil.copytree(os.path.dirname(ac.__file__), tmp_path / "adaptive_cpca",
                    ignore=shutil.ignore_patterns("*.so", "__pycache__"))
    script = """
import sys, warnings, torch
from adaptive_cpca.torch import TorchRelighter
t = TorchRelighter(sys.argv[1])
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    auto = t.relight_map("sky", 30)
    t.relight_map("sky", 60)
said = [str(w.message) for w in caught]
assert len(said) == 1 and "compiled part did not load" in said[0], said
with warnings.catch_warnings():
    warnings.simplefilter("error")
    assert torch.equal(auto, t.relight_map("sky", 30, sun="off"))
print("ok")
"""
    done = subprocess.run([sys.executable, "-c", script, model], capture_output=True, text=True,
                          cwd=tmp_path, env={**os.environ, "PYTHONPATH": str(tmp_path)})
    assert done.returncode == 0 and done.stdout.strip() == "ok", done.stderr
