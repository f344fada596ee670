"""RelightDataset and the training example against the module and the CLI.

Run by ctest (python_tests) as test_torch.py is; skipped where PyTorch is
not installed (Debian's python3-torch).
"""

import glob
import os
import subprocess
import sys

import numpy as np
import pytest

torch = pytest.importorskip("torch")

import adaptive_cpca as ac  # noqa: E402
from adaptive_cpca import sampling  # noqa: E402
from adaptive_cpca.torch import RelightDataset  # noqa: E402

CLI = os.environ["ACPCA_CLI"]
FIXTURES = os.environ["ACPCA_FIXTURE_DIR"]
PLANT = os.path.join(FIXTURES, "small-plant.h5")
EXAMPLE = os.path.join(os.path.dirname(__file__), "..", "examples", "train_sh9.py")
MAPS = ["sky", "sun:50,30,4,1000", "constant:0.5,0.4,0.3"]


@pytest.fixture(scope="module")
def models(tmp_path_factory):
    """Two views' models: the plant compressed two ways."""
    out = []
    for method in ("adaptive-quad", "cpca"):
        path = str(tmp_path_factory.mktemp("m") / f"{method}.h5")
        subprocess.run([CLI, "compress", PLANT, "--method", method, "--quiet", "--out", path],
                       check=True)
        out.append(path)
    return out


def test_the_dataset_is_where_users_look_for_it():
    # adaptive_cpca.torch holds both classes, whichever module is imported first.
    for first in ("adaptive_cpca.torch", "adaptive_cpca.torch.dataset"):
        code = (f"import {first}\n"
                "from adaptive_cpca.torch import TorchRelighter, RelightDataset\n"
                "from adaptive_cpca.torch.dataset import RelightDataset as Same\n"
                "assert RelightDataset is Same and TorchRelighter.__name__ == 'TorchRelighter'\n")
        subprocess.run([sys.executable, "-c", code], check=True, env=os.environ)


def test_draws_are_the_clis(models):
    for rotation in ("yaw", "sphere"):
        for seed in (0, 12345, 2**64 - 1):
            theirs = ac.draw_lightings(3, 500, seed=seed, rotation=rotation, exposure_jitter=2.5)
            # The pure-Python copy, the compiled part's draws through the
            # package, and each draw made alone, in any order.
            pure = [sampling.pure_draw(i, 3, seed, rotation, 2.5) for i in range(500)]
            assert [tuple(d) for d in pure] == theirs, (rotation, seed)
            through = sampling.draw_lightings(3, 500, seed, rotation, 2.5)
            assert [tuple(d) for d in through] == theirs, (rotation, seed)
            alone = [sampling.draw(i, 3, seed, rotation, 2.5) for i in (499, 0, 250)]
            assert [tuple(d) for d in alone] == [theirs[i] for i in (499, 0, 250)]
    # The dataset's frames carry those draws, batch after batch.
    data = RelightDataset(models[0], MAPS, batch_size=4, seed=9, draws=10, rotation="sphere",
                          exposure=-1.0, exposure_jitter=1.5)
    theirs = ac.draw_lightings(3, 10, seed=9, rotation="sphere", exposure_jitter=1.5)
    frames = [f for batch in data for f in zip(batch["map"].tolist(), batch["yaw"].tolist(),
                                                 batch["pitch"].tolist(), batch["roll"].tolist(),
                                                 batch["exposure"].tolist())]
    assert len(data) == 3 and len(frames) == 10
    assert frames == [(m, y, p, r, e - 1.0) for m, y, p, r, e in theirs]


def stream(data, workers):
    loader = torch.utils.data.DataLoader(data, batch_size=None, num_workers=workers)
    return list(loader)


def expect_equal_streams(a, b):
    assert len(a) == len(b)
    for x, y in zip(a, b):
        assert x["view"] == y["view"]
        for key in ("images", "sh9", "draw", "map", "yaw", "pitch", "roll", "exposure"):
            assert torch.equal(x[key], y[key]), key


def test_any_worker_count_gives_the_same_stream_and_a_seed_the_same_tensors(models):
    def data(**kwargs):
        return RelightDataset(models, MAPS, batch_size=3, seed=4, draws=14, rotation="sphere",
                              exposure_jitter=1.0, sun="off", **kwargs)
    alone = stream(data(), 0)
    assert [b["view"] for b in alone] == [0, 1, 0, 1, 0]  # views alternate by batch
    assert [len(b["draw"]) for b in alone] == [3, 3, 3, 3, 2]
    expect_equal_streams(alone, stream(data(), 2))
    expect_equal_streams(alone, stream(data(), 0))  # the same seed: equal tensors
    # Another epoch draws anew; epoch 0 again gives the first stream back.
    d = data()
    d.set_epoch(1)
    other = stream(d, 0)
    assert not torch.equal(other[0]["yaw"], alone[0]["yaw"])
    d.set_epoch(0)
    expect_equal_streams(alone, stream(d, 2))
    # Endless: as many batches as asked for, the same draws as the finite stream.
    endless = iter(RelightDataset(models, MAPS, batch_size=3, seed=4, rotation="sphere",
                                  exposure_jitter=1.0, sun="off"))
    for k in range(4):
        assert torch.equal(next(endless)["images"], alone[k]["images"])


def test_map_files_and_forked_workers_after_the_compiled_part_ran(models, tmp_path):
    # The main process integrates a map file through the compiled part (its
    # thread pools start), then workers fork: they must neither hang nor
    # differ (the files are read before the fork, workers integrate in torch).
    worlds = sorted(glob.glob("/usr/share/blender/datafiles/studiolights/world/*.exr"))[:1]
    cross = str(tmp_path / "cross.exr")
    subprocess.run([CLI, "envmap", "sky", "--cross", cross, "--out", str(tmp_path / "flat.exr"),
                    "--quiet"], check=True)
    maps = worlds + [cross, "sky"]

    def data():
        return RelightDataset(models[0], maps, batch_size=4, seed=2, draws=12,
                              rotation="sphere", labels=None, sun="off")
    alone = list(torch.utils.data.DataLoader(data(), batch_size=None, num_workers=0))
    forked = list(torch.utils.data.DataLoader(data(), batch_size=None, num_workers=2,
                                              timeout=120))
    assert len(alone) == len(forked) == 3
    for a, b in zip(alone, forked):
        assert torch.equal(a["draw"], b["draw"])
        error = (a["images"] - b["images"]).norm() / b["images"].norm()
        assert error <= 1e-6, float(error)  # compiled there, torch here: equal to rounding


@pytest.mark.parametrize("sun", ["off", "auto"])
def test_frames_labels_and_cameras_are_the_modules(models, sun):
    # sun="auto": the maps' suns lit exactly by the compiled part, as its own
    # relight lights them.
    data = RelightDataset(models, MAPS, batch_size=2, seed=3, draws=4, rotation="sphere",
                          exposure=0.5, exposure_jitter=1.0, background="env", sun=sun)
    for batch in data:
        r = ac.open(models[batch["view"]])
        for k in range(len(batch["draw"])):
            spec = MAPS[int(batch["map"][k])]
            theirs = r.relight(ac.Environment(spec), sun=sun, yaw=float(batch["yaw"][k]),
                               pitch=float(batch["pitch"][k]), roll=float(batch["roll"][k]),
                               exposure=float(batch["exposure"][k]), background="env")
            mine = batch["images"][k].permute(1, 2, 0).numpy()
            # (a sun behind the subject may leave a frame black)
            error = np.linalg.norm(mine - theirs) / max(np.linalg.norm(theirs), 1e-30)
            assert error <= 1e-6, (spec, error)
        for name, value in r.labels().items():
            mine = batch["labels"][name]
            mine = mine.permute(1, 2, 0) if mine.shape[0] == 3 else mine[0]
            assert np.array_equal(mine.numpy(), value), name
        info = ac.info(models[batch["view"]])
        assert batch["camera"]["fov_deg"].item() > 0 and info["width"] == 40
    # float16 frames are the float32 ones rounded; hwc is chw turned.
    half = next(iter(RelightDataset(models[0], MAPS, batch_size=2, seed=3, draws=2,
                                    dtype=torch.float16, layout="hwc")))
    full = next(iter(RelightDataset(models[0], MAPS, batch_size=2, seed=3, draws=2)))
    assert half["images"].dtype == torch.float16
    assert torch.equal(half["images"], full["images"].permute(0, 2, 3, 1).half())


def test_bad_arguments_are_refused(models, tmp_path):
    with pytest.raises(ValueError, match="sampled rotation 'tilt'"):
        RelightDataset(models, MAPS, rotation="tilt")
    with pytest.raises(ValueError, match="background 'grey'"):
        RelightDataset(models, MAPS, background="grey")
    with pytest.raises(ValueError, match="torch.float32 or torch.float16"):
        RelightDataset(models, MAPS, dtype=torch.float64)
    with pytest.raises(ValueError, match="holds no .exr/.hdr maps"):
        RelightDataset(models, [str(tmp_path)])
    with pytest.raises(TypeError, match="endless"):
        len(RelightDataset(models, MAPS))


def test_the_training_example_learns_sh9_from_relit_frames(models):
    done = subprocess.run([sys.executable, EXAMPLE, models[0], "--steps", "120", "--workers",
                           "2"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "last fifth" in done.stdout
