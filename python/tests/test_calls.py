"""The Python module's calls against the CLI's: bad input refused in its
words, files of older versions, the GIL, warnings, long calls that stop
cleanly, and the examples.

Run by ctest (python_tests) as test_relight.py is.
"""

import _thread
import json
import os
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import adaptive_cpca as ac
from adaptive_cpca._contract import MODEL_VERSION
from relight_support import CLI, TRANSPORT, WORLD, cli, cli_error, write_pfm

MESH = os.path.join(os.path.dirname(__file__), "..", "..", "data", "meshes", "icosahedron.obj")
SCENE_WITH_MESH = """{"camera": {"eye": [0, 0, 4], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 40, "width": 16, "height": 16},
 "objects": [{"mesh": "ico.obj"}]}"""


def test_bad_input_raises_with_the_librarys_words(tmp_path, model):
    with pytest.raises(FileNotFoundError, match="nowhere.h5"):
        ac.Relighter(str(tmp_path / "nowhere.h5"))
    with pytest.raises(ac.Error, match="nowhere.h5"):  # MissingFileError is both
        ac.info(str(tmp_path / "nowhere.h5"))
    with pytest.raises(ac.Error, match="radiance must be finite"):
        ac.Environment.from_array(np.full((8, 16, 3), np.nan, np.float32))
    with pytest.raises(ValueError):
        ac.Environment.from_array(np.zeros((4,), np.float32))
    r = ac.Relighter(model)
    with pytest.raises(ac.Error, match="background"):
        r.relight(ac.Environment("sky"), background="purple")
    with pytest.raises(ac.Error, match="rank"):
        ac.Relighter(TRANSPORT).relight(ac.Environment("sky"), max_rank=3)
    with pytest.raises(ac.Error, match="rank"):
        r.relight(ac.Environment("sky"), max_rank="lots")
    with pytest.raises(ValueError, match="out must be"):
        r.relight(ac.Environment("sky"), out=np.empty((40, 40, 4), np.float32))
    with pytest.raises(ac.Error):
        ac.Environment("sun:1,2")
    assert issubclass(ac.Error, ValueError)



def test_numbers_are_refused_as_the_cli_refuses_them(model):
    r = ac.Relighter(model)
    sky = ac.Environment("sky")
    for kwargs in ({"yaw": float("nan")}, {"pitch": float("inf")}, {"roll": float("-inf")}):
        with pytest.raises(ac.Error, match="is not a finite number") as e:
            r.relight(sky, **kwargs)
        assert "internal" not in str(e.value)
    with pytest.raises(ac.Error, match="'nan' is not a finite number"):
        r.lighting(sky, yaw=float("nan"))
    with pytest.raises(ac.Error, match="'nan' is not a finite number"):
        r.relight_batch([sky], rotations=[(0, float("nan"), 0)])
    with pytest.raises(ac.Error, match="'inf' is not a finite number"):
        r.relight(sky, exposure=float("inf"))
    # The CLI's words for the same value, the flag in place of the parameter.
    assert "'nan' is not a finite number" in cli_error("relight", model, "--env", "sky", "--rotate",
                                                       "nan", "--out", "x.exr")


def test_out_is_written_in_place_or_refused(model):
    r = ac.Relighter(model)
    sky = ac.Environment("sky")
    big = np.zeros((40, 80, 3), np.float32)
    view = big[:, ::2, :]  # strided: results written to a copy would be lost
    with pytest.raises(ValueError, match="not C-contiguous"):
        r.relight(sky, out=view)
    assert not big.any()
    with pytest.raises(TypeError, match="float32"):
        r.relight(sky, out=np.zeros((40, 40, 3), np.float64))
    frozen = np.zeros((40, 40, 3), np.float32)
    frozen.flags.writeable = False
    with pytest.raises(ValueError, match="read-only"):
        r.relight(sky, out=frozen)
    with pytest.raises(ValueError, match="not C-contiguous"):
        r.relight_batch([sky], out=np.zeros((1, 40, 40, 3), np.float32, order="F"))
    exact = np.zeros((40, 40, 3), np.float32)
    assert np.shares_memory(r.relight(sky, out=exact), exact) and exact.any()


def test_missing_files_raise_file_not_found_in_the_clis_words(tmp_path):
    missing = str(tmp_path / "absent.h5")
    words = cli_error("info", missing)
    for call in (lambda: ac.Relighter(missing), lambda: ac.info(missing),
                 lambda: ac.compress(missing, str(tmp_path / "m.h5")),
                 lambda: ac.Environment(str(tmp_path / "absent.exr")),
                 lambda: ac.read_image(str(tmp_path / "absent.exr")),
                 lambda: ac.precompute(str(tmp_path / "absent.json"), str(tmp_path / "t.h5"))):
        with pytest.raises(FileNotFoundError):
            call()
    with pytest.raises(FileNotFoundError) as e:
        ac.Relighter(missing)
    assert str(e.value) == words


def test_an_output_that_is_the_input_is_refused(tmp_path):
    transport = tmp_path / "t.h5"
    transport.write_bytes(open(TRANSPORT, "rb").read())
    before = transport.read_bytes()
    link = tmp_path / "hard.h5"
    os.link(transport, link)
    symlink = tmp_path / "soft.h5"
    symlink.symlink_to(transport)
    for out in (transport, link, symlink):
        with pytest.raises(ac.Error, match="destroy the input"):
            ac.compress(str(transport), str(out), method="global")
    assert transport.read_bytes() == before
    # A scene file and the mesh it names are inputs of precompute.
    mesh = tmp_path / "ico.obj"
    mesh.write_bytes(open(MESH, "rb").read())
    scene = tmp_path / "scene.json"
    scene.write_text(SCENE_WITH_MESH)
    for out in (scene, mesh):
        kept = out.read_bytes()
        with pytest.raises(ac.Error, match="destroy the input"):
            ac.precompute(str(scene), str(out), size=(16, 16), cubemap=4)
        assert out.read_bytes() == kept


def test_models_of_the_previous_format_are_read_and_older_ones_refused(tmp_path, model):
    h5py = pytest.importorskip("h5py")
    # Compared on the lattice: a file without surfaces lights the sky's sun there.
    current = ac.Relighter(model).relight(ac.Environment("sky"), sun="off")
    with h5py.File(model, "r") as f:
        assert f.attrs["version"] == MODEL_VERSION
        assert f["lamp_sample_start"].shape == (f["albedo"].shape[0] + 1,)
        assert f["lamp_sample_tangent"].shape == f["lamp_sample_normal"].shape
        assert f["position"].shape == f["albedo"].shape == f["normal"].shape
        assert f["object"].shape == f["coverage"].shape
        assert "compress_seconds" not in f.attrs and "peak_memory_bytes" not in f.attrs
    # Version 7 had no tangents and four material columns: read as isotropic,
    # its lamps lit exactly as before, and the tangent label refused.
    old = tmp_path / "v4.h5"
    old.write_bytes(open(model, "rb").read())
    with h5py.File(old, "r+") as f:
        f.attrs["version"] = 7
        materials = f["lamp_materials"][:, :4]
        del f["lamp_sample_tangent"], f["lamp_materials"]
        f["lamp_materials"] = materials
    assert np.array_equal(ac.Relighter(str(old)).relight(ac.Environment("sky")),
                          ac.Relighter(model).relight(ac.Environment("sky")))
    with pytest.raises(ac.Error, match="'tangent' label.*compress"):
        ac.Relighter(str(old)).labels("tangent")
    # Version 6 had no lamp samples or surfaces: read and relit as before.
    with h5py.File(old, "r+") as f:
        f.attrs["version"] = 6
        for name in [n for n in f if n.startswith(("lamp_", "scene_"))]:
            del f[name]
        del f.attrs["lamp_ray_epsilon"]
    assert np.array_equal(ac.Relighter(str(old)).relight(ac.Environment("sky"), sun="off"),
                          current)
    # Version 5 could not hold a captured light set: a lattice model of it
    # reads as it did.
    with h5py.File(old, "r+") as f:
        f.attrs["version"] = 5
    assert np.array_equal(ac.Relighter(str(old)).relight(ac.Environment("sky"), sun="off"),
                          current)
    # Version 4 had no normals or objects: read and relit as before, and the
    # labels that need them are refused naming what to run again.
    with h5py.File(old, "r+") as f:
        f.attrs["version"] = 4
        del f["normal"], f["object"]
        del f.attrs["object_names"]
    assert np.array_equal(ac.Relighter(str(old)).relight(ac.Environment("sky"), sun="off"),
                          current)
    assert set(ac.Relighter(str(old)).labels("albedo,depth,mask")) == {"albedo", "depth", "mask"}
    for aov in ("normal", "object"):
        with pytest.raises(ac.Error, match=f"'{aov}' label.*compress"):
            ac.Relighter(str(old)).labels(aov)
    # Version 3 had no pixel positions either.
    with h5py.File(old, "r+") as f:
        f.attrs["version"] = 3
        del f["position"]
    assert np.array_equal(ac.Relighter(str(old)).relight(ac.Environment("sky"), sun="off"),
                          current)
    # Version 2 also held the compress's time and peak memory: read, those ignored.
    with h5py.File(old, "r+") as f:
        f.attrs["version"] = 2
        f.attrs["compress_seconds"] = 12.5
        f.attrs["peak_memory_bytes"] = 1 << 30
    assert np.array_equal(ac.Relighter(str(old)).relight(ac.Environment("sky"), sun="off"),
                          current)
    with h5py.File(old, "r+") as f:
        f.attrs["version"] = 1
    with pytest.raises(ac.Error, match="version 1.*compress"):
        ac.Relighter(str(old))


def test_the_version_is_the_clis():
    r = subprocess.run([CLI, "--version"], capture_output=True, text=True, check=True)
    assert r.stdout.split() == ["adaptive-cpca", ac.__version__]
    assert ac.__version__.count(".") == 2


def test_the_gil_is_released_while_relighting():
    # With a switch interval far longer than the test, this thread gives the
    # GIL up only where the module releases it (or it blocks); the counting
    # thread yields it on every step. So the count moves during the call only
    # if the call runs without the GIL.
    r = ac.Relighter(TRANSPORT)
    envs = [ac.Environment(os.path.join(WORLD, "forest.exr"))] * 2
    count, stop = [0], threading.Event()

    def counter():
        while not stop.is_set():
            count[0] += 1
            time.sleep(0)

    interval = sys.getswitchinterval()
    sys.setswitchinterval(1000)
    thread = threading.Thread(target=counter)
    try:
        thread.start()
        before = count[0]
        # Pitched turns, each integrated cell by cell: long enough a call
        # (a yaw alone takes well under a millisecond) for the count to move.
        r.relight_batch(envs, rotations=[(y, 10, 0) for y in range(0, 360, 5)])
        during = count[0] - before
    finally:
        stop.set()
        thread.join()
        sys.setswitchinterval(interval)
    assert during > 100, during



def test_library_warnings_become_python_warnings(tmp_path):
    # Negative texels holding a ten-thousandth of a map: clamped with a warning.
    rgb = np.ones((8, 16, 3), np.float32)
    rgb[3, 5, 0] = -0.04
    write_pfm(tmp_path / "ringing.pfm", rgb)
    with pytest.warns(UserWarning, match="negative values clamped"):
        ac.Environment(str(tmp_path / "ringing.pfm"))


def test_debians_world_maps_load_without_warnings():
    # Their negative texels hold at most 6e-7 of their magnitude: clamped silently.
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for name in sorted(os.listdir(WORLD)):
            if name.endswith(".exr"):
                ac.Environment(os.path.join(WORLD, name))


def test_precompute_and_compress_make_the_clis_files(tmp_path):
    calls = []
    stats = ac.precompute("sphere", str(tmp_path / "py.h5"), size=(24, 16), cubemap=8,
                          progress=lambda done, total: calls.append((done, total)))
    cli("precompute", "--scene", "sphere", "--size", "24x16", "--cubemap", "8",
        "--out", str(tmp_path / "cli.h5"))
    assert stats["occupied_pixels"] == ac.info(str(tmp_path / "cli.h5"))["occupied_pixels"]
    assert calls and calls[-1][0] == calls[-1][1] == stats["occupied_pixels"]
    assert all(a[0] <= b[0] for a, b in zip(calls, calls[1:]))
    sky = ac.Environment("sky")
    assert np.array_equal(ac.Relighter(str(tmp_path / "py.h5")).relight(sky),
                          ac.Relighter(str(tmp_path / "cli.h5")).relight(sky))
    stages = []
    ac.compress(str(tmp_path / "py.h5"), str(tmp_path / "py-model.h5"), method="cpca",
                clusters=3, coeffs="f16", progress=stages.append)
    cli("compress", str(tmp_path / "cli.h5"), "--method", "cpca", "--clusters", "3",
        "--coeffs", "f16", "--out", str(tmp_path / "cli-model.h5"))
    assert any("global basis" in s for s in stages)
    assert np.array_equal(ac.Relighter(str(tmp_path / "py-model.h5")).relight(sky),
                          ac.Relighter(str(tmp_path / "cli-model.h5")).relight(sky))
    with pytest.raises(ac.Error, match="method"):
        ac.compress(str(tmp_path / "py.h5"), str(tmp_path / "x.h5"), method="zip")


def test_bounced_light_from_python_is_the_clis_with_rgb_rows(tmp_path):
    stats = ac.precompute("plant", str(tmp_path / "py.h5"), size=(16, 12), cubemap=4, spp=1,
                          bounces=1, indirect_samples=8)
    cli("precompute", "--scene", "plant", "--size", "16x12", "--cubemap", "4", "--spp", "1",
        "--bounces", "1", "--indirect-samples", "8", "--out", str(tmp_path / "cli.h5"))
    assert stats["channels"] == 3 and stats["path_rays"] > 0
    info = ac.info(str(tmp_path / "py.h5"))
    assert info["row_layout"] == "rgb" and info["bounces"] == 1
    assert info["indirect_samples"] == 8
    sky = ac.Environment("sky")
    assert np.array_equal(ac.Relighter(str(tmp_path / "py.h5")).relight(sky),
                          ac.Relighter(str(tmp_path / "cli.h5")).relight(sky))
    with pytest.raises(ac.Error, match="bounces"):
        ac.precompute("plant", str(tmp_path / "x.h5"), size=(4, 4), bounces=99)


def test_a_callback_error_or_ctrl_c_stops_the_work_and_leaves_no_file(tmp_path):
    out = tmp_path / "t.h5"

    def fail(done, total):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        ac.precompute("plant", str(out), size=(64, 64), cubemap=8, progress=fail)
    assert list(tmp_path.iterdir()) == []

    def ctrl_c(done, total):
        if done and not ctrl_c.sent:
            ctrl_c.sent = True
            _thread.interrupt_main()  # as if Ctrl-C reached the main thread
            time.sleep(0.5)  # Python's thread looks for signals every 50 ms meanwhile

    ctrl_c.sent = False
    with pytest.raises(KeyboardInterrupt):
        ac.precompute("plant", str(out), size=(64, 64), cubemap=8, progress=ctrl_c)
    assert ctrl_c.sent and list(tmp_path.iterdir()) == []


def test_the_dataset_example_writes_its_images_and_manifest(tmp_path, model):
    example = os.path.join(os.path.dirname(__file__), "..", "examples", "make_dataset.py")
    subprocess.run([sys.executable, example, model, str(tmp_path), "--count", "3", "--seed", "7"],
                   check=True, env={**os.environ, "PYTHONWARNINGS": "ignore"})
    rows = (tmp_path / "manifest.csv").read_text().splitlines()
    assert rows[0] == "file,env,yaw" and len(rows) == 4
    r = ac.Relighter(model)
    for row in rows[1:]:
        name, env, yaw = row.split(",")
        image = np.load(tmp_path / name)
        assert image.shape == (40, 40, 3) and image.dtype == np.float32
        expected = r.relight(ac.Environment(os.path.join(WORLD, env)), yaw=float(yaw))
        assert np.array_equal(image, expected)


def test_the_loader_example_reads_a_cli_batch_into_numpy_batches(tmp_path, model):
    out = tmp_path / "batch"
    cli("relight", model, "--env", "sky", "--env", "constant:1", "--rotate", "0:360:120",
        "--exr-float", "--out", str(out))
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "examples"))
    try:
        import load_dataset
    finally:
        sys.path.pop(0)
    frames = [json.loads(line) for line in (out / "manifest.jsonl").read_text().splitlines()]
    assert len(frames) == 6
    got = list(load_dataset.batches(str(out), 4))
    assert [len(images) for images, _ in got] == [4, 2]
    images = np.concatenate([i for i, _ in got])
    assert images.shape == (6, 40, 40, 3) and images.dtype == np.float32
    sh9 = np.concatenate([labels["sh9"] for _, labels in got])
    for k, frame in enumerate(frames):  # what the files and the manifest hold
        assert np.array_equal(images[k], ac.read_image(str(out / frame["outputs"][0]))[..., :3])
        assert np.array_equal(sh9[k], np.array(frame["sh9"]))
    # constant:1 frames: band 0 is 2 sqrt(pi), the rest zero.
    assert np.allclose(sh9[3:, 0], 2 * np.sqrt(np.pi), rtol=1e-12)
    assert np.allclose(sh9[3:, 1:], 0, atol=1e-12)
    assert [labels["yaw"].tolist() for _, labels in got] == [[0, 120, 240, 0], [120, 240]]
    assert load_dataset.view_labels(frames[0], str(out)) == {}
    assert "shading" not in got[0][1]
    # With --aov: the shading beside each frame, and the view's labels from
    # labels.exr or the .npy files alike.
    for label_format in ("exr", "npy"):
        labelled = tmp_path / label_format
        cli("relight", model, "--env", "sky", "--rotate", "0:360:180", "--background", "black",
            "--aov", "all", "--label-format", label_format, "--out", str(labelled))
        lines = load_dataset.read_manifest(str(labelled))
        (images, labels), = load_dataset.batches(str(labelled), 4)
        assert labels["shading"].shape == (2, 40, 40, 3)
        view = load_dataset.view_labels(lines[0], str(labelled))
        expected = ac.Relighter(model).labels()
        assert view.keys() == expected.keys()
        for name in view:
            assert view[name].dtype == expected[name].dtype, name
            assert np.array_equal(view[name], expected[name]), name
    # Shuffled: the same frames in another order, the same for the same seed.
    shuffled = [labels["frame"] for _, labels in load_dataset.batches(str(out), 6, True, 3)]
    assert sorted(shuffled[0]) == list(range(6)) and shuffled[0] != list(range(6))
    again = [labels["frame"] for _, labels in load_dataset.batches(str(out), 6, True, 3)]
    assert again == shuffled
