"""The Python module against the CLI, files and its own promises.

Run by ctest (python_tests) with PYTHONPATH at the built module, ACPCA_CLI the
adaptive-cpca binary and ACPCA_FIXTURE_DIR the transports the build makes.
"""

import _thread
import json
import os
import shutil
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import adaptive_cpca as ac

CLI = os.environ["ACPCA_CLI"]
TRANSPORT = os.path.join(os.environ["ACPCA_FIXTURE_DIR"], "small-plant.h5")
WORLD = "/usr/share/blender/datafiles/studiolights/world"
MESH = os.path.join(os.path.dirname(__file__), "..", "..", "data", "meshes", "icosahedron.obj")
SCENE_WITH_MESH = """{"camera": {"eye": [0, 0, 4], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 40, "width": 16, "height": 16},
 "objects": [{"mesh": "ico.obj"}]}"""


def cli(*args):
    subprocess.run([CLI, *args, "--quiet"], check=True)


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    path = str(tmp_path_factory.mktemp("model") / "plant.h5")
    cli("compress", TRANSPORT, "--method", "adaptive-quad", "--coeffs", "f16", "--out", path)
    return path


def cli_image(tmp_path, source, *args):
    out = str(tmp_path / "cli.exr")
    cli("relight", source, "--exr-float", "--out", out, *args)
    return ac.read_image(out)


@pytest.mark.parametrize("background", ["env", "black", "alpha"])
def test_a_model_relights_as_the_cli_does_bit_for_bit(tmp_path, model, background):
    r = ac.Relighter(model)
    assert r.is_model and (r.height, r.width) == (40, 40)
    mine = r.relight(ac.Environment("sky"), yaw=30, pitch=10, background=background, exposure=1)
    theirs = cli_image(tmp_path, model, "--env", "sky", "--rotate", "30,10,0",
                       "--background", background, "--exposure", "1")
    assert mine.dtype == np.float32 and mine.shape == theirs.shape
    assert np.array_equal(mine, theirs)


def test_a_transport_relights_densely_as_the_cli_does(tmp_path):
    r = ac.open(TRANSPORT)
    assert not r.is_model and r.method == "dense"
    mine = r.relight(ac.Environment("sun:50,30,4,1000"), yaw=45, background="black")
    theirs = cli_image(tmp_path, TRANSPORT, "--env", "sun:50,30,4,1000", "--rotate", "45",
                       "--background", "black")
    assert np.array_equal(mine, theirs)


def test_a_maps_sun_is_lit_as_the_cli_lights_it(tmp_path, model):
    # sun= means what relight --sun means: 'auto' (the default) splits the
    # map's sun off and lights it by shadow rays from the camera samples, 'off'
    # leaves it on the lattice, K keeps at most K sources.
    sun = "sun:40,30,0.53,40000"
    for source in (model, TRANSPORT):
        r = ac.open(source)
        frames = {}
        for choice, flags in (("auto", []), ("off", ["--sun", "off"]), (1, ["--sun", "1"])):
            mine = r.relight(ac.Environment(sun), yaw=30, background="black", sun=choice)
            theirs = cli_image(tmp_path, source, "--env", sun, "--rotate", "30",
                               "--background", "black", *flags)
            assert np.array_equal(mine, theirs), (source, choice)  # bit for bit
            frames[choice] = mine
        # Lit exactly, the sun's shadow is not the lattice's; the light is the same.
        assert not np.array_equal(frames["auto"], frames["off"])
        assert abs(frames["auto"].sum() / frames["off"].sum() - 1) < 0.05
        # A batch lights each frame's sun as one relight does (a model's group
        # projection rounds apart from one frame's, in the last bits).
        envs = [ac.Environment(sun), ac.Environment("sky")]
        batch = r.relight_batch(envs, rotations=[(0, 0, 0), (30, 0, 0)], background="black")
        for k, (env, yaw) in enumerate([(e, y) for e in envs for y in (0, 30)]):
            one = r.relight(env, yaw=yaw, background="black")
            assert np.abs(batch[k] - one).max() <= 1e-6 * np.abs(one).max(), k
    with pytest.raises(ac.Error, match="sometimes"):
        ac.open(model).relight(ac.Environment(sun), sun="sometimes")


def test_a_rank_limit_is_the_clis(tmp_path, model):
    r = ac.Relighter(model)
    for limit, text in ((2, "2"), (0.5, "0.5"), ("25%", "25%")):
        mine = r.relight(ac.Environment("sky"), max_rank=limit)
        assert np.array_equal(mine, cli_image(tmp_path, model, "--env", "sky",
                                              "--max-rank", text))
    # No limit again: every basis, not the last limit's.
    assert np.array_equal(r.relight(ac.Environment("sky")),
                          cli_image(tmp_path, model, "--env", "sky"))


def test_local_lights_are_the_clis_alone_and_beside_an_environment(tmp_path, model):
    lamp = ac.SphereLight((1.2, 2.6, 1.4), 0.15, (300, 250, 200))
    spot = ac.SpotLight((0, 3.5, 2), (0, -2, -1), 30, 80)
    assert lamp.spec == "sphere:1.2,2.6,1.4,0.15,300,250,200" and lamp.kind == "sphere"
    assert spot.spec == "spot:0,3.5,2,0,-0.8944271909999159,-0.4472135954999579,30,80"
    assert ac.Light(spot.spec).spec == spot.spec
    flags = ["--light", lamp.spec, "--light", spot.spec]
    for source in (model, TRANSPORT):
        r = ac.Relighter(source)
        alone = r.relight(None, lights=[lamp, spot])
        assert np.array_equal(alone, cli_image(tmp_path, source, *flags))
        both = r.relight(ac.Environment("sky"), lights=[lamp, spot], exposure=1)
        assert np.array_equal(both, cli_image(tmp_path, source, "--env", "sky", "--exposure",
                                              "1", *flags))
        batch = r.relight_batch([ac.Environment("sky")], rotations=[(0, 0, 0), (90, 0, 0)],
                                lights=[lamp])
        single = cli_image(tmp_path, source, "--env", "sky", "--rotate", "90", "--light", lamp.spec)
        # A transport multiplies a batch's frames together: equal to rounding.
        assert np.allclose(batch[1], single, rtol=1e-6, atol=0) if source == TRANSPORT else \
            np.array_equal(batch[1], single)
    r = ac.Relighter(model)
    # A batch along a path: light_positions moves the lights frame by frame.
    path = np.array([[[-1.5, 2, 1.5]], [[0, 2.2, 1.8]], [[1.5, 2, 1.5]]])
    moved = r.relight_batch([ac.Environment("sky"), ac.Environment("constant:0.1")],
                            lights=[lamp], light_positions=path)
    assert moved.shape[0] == 3 * 2
    second = ac.SphereLight(tuple(path[1, 0]), 0.15, (300, 250, 200))
    assert np.array_equal(moved[2 * 1 + 1], r.relight(ac.Environment("constant:0.1"),
                                                       lights=[second]))
    with pytest.raises(ValueError, match="light_positions must be F x 1 x 3"):
        r.relight_batch([ac.Environment("sky")], lights=[lamp], light_positions=np.zeros((2, 2, 3)))
    exact = r.relight(None, lights=[lamp], anchor_spread=0)
    assert np.array_equal(exact, cli_image(tmp_path, model, "--light", lamp.spec,
                                           "--anchor-spread", "0"))
    with pytest.raises(ac.Error, match="give an environment, lights, or both"):
        r.relight(None)
    with pytest.raises(ac.Error, match="radius must be finite"):
        ac.SphereLight((0, 1, 0), -1, 5)
    with pytest.raises(ac.Error, match="direction DX,DY,DZ is zero"):
        ac.SpotLight((0, 1, 0), (0, 0, 0), 30, 5)
    with pytest.raises(ac.Error, match="has 3 numbers"):
        ac.Light("point:1,2,3")
    with pytest.raises(ac.Error, match="encloses"):
        r.relight(None, lights=[ac.SphereLight((0, 0.5, 0), 5, 1)])


def test_a_numpy_lat_long_map_equals_the_same_map_read_from_its_file():
    path = os.path.join(WORLD, "forest.exr")
    array = ac.read_image(path)[..., :3]
    from_file, from_array = ac.Environment(path), ac.Environment.from_array(array)
    r = ac.Relighter(TRANSPORT)
    assert np.array_equal(r.relight(from_file, yaw=20), r.relight(from_array, yaw=20))


def test_a_batch_is_its_frames_and_out_is_filled_in_place(model):
    r = ac.Relighter(model)
    envs = [ac.Environment("sky"), ac.Environment("sun:40,100,6,500")]
    rotations = [(0, 0, 0), (90, 0, 0), (200, 15, 5)]
    batch = r.relight_batch(envs, rotations=rotations, background="alpha")
    assert batch.shape == (6, 40, 40, 4)
    for i, env in enumerate(envs):
        for k, (yaw, pitch, roll) in enumerate(rotations):
            frame = r.relight(env, yaw=yaw, pitch=pitch, roll=roll, background="alpha")
            assert np.array_equal(batch[i * len(rotations) + k], frame)
    out = np.empty((40, 40, 3), np.float32)
    returned = r.relight(envs[0], out=out)
    assert np.shares_memory(returned, out)
    assert np.array_equal(out, r.relight(envs[0]))
    # A dense batch (one pass over T per 32 frames) equals its frames too.
    dense = ac.Relighter(TRANSPORT)
    frames = dense.relight_batch(envs, rotations=rotations)
    assert np.array_equal(frames[4], dense.relight(envs[1], yaw=90))


def test_coverage_and_info_describe_the_file(model):
    r = ac.Relighter(model)
    cov = r.coverage
    assert cov.shape == (40, 40) and cov.min() >= 0 and cov.max() <= 1
    info = r.info
    assert info["kind"] == "model" and info["width"] == 40
    assert info == ac.info(model)
    assert ac.info(TRANSPORT)["kind"] == "transport"
    assert int((cov > 0).sum()) == ac.info(TRANSPORT)["occupied_pixels"]


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


def cli_error(*args):
    """The CLI's error message for args (it must fail as a user error)."""
    r = subprocess.run([CLI, *args], capture_output=True, text=True)
    assert r.returncode == 1, r.stderr
    return r.stderr.strip().split("error: ", 1)[1]


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
        assert f.attrs["version"] == 7
        assert f["lamp_sample_start"].shape == (f["albedo"].shape[0] + 1,)
        assert f["position"].shape == f["albedo"].shape == f["normal"].shape
        assert f["object"].shape == f["coverage"].shape
        assert "compress_seconds" not in f.attrs and "peak_memory_bytes" not in f.attrs
    # Version 6 had no lamp samples or surfaces: read and relit as before.
    old = tmp_path / "v4.h5"
    old.write_bytes(open(model, "rb").read())
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


def write_pfm(path, rgb):
    """A portable float map (rows stored bottom to top), as OpenImageIO reads it."""
    height, width, _ = rgb.shape
    with open(path, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (width, height))
        f.write(np.ascontiguousarray(rgb[::-1], dtype="<f4").tobytes())


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


def test_a_lighting_made_once_relights_as_the_environment_does(model):
    r = ac.Relighter(model)
    env = ac.Environment("sun:40,100,6,500")
    light = r.lighting(env, yaw=70)
    assert np.array_equal(r.relight(light, background="alpha"),
                          r.relight(env, yaw=70, background="alpha"))
    # Integrated energy-exactly: a constant map holds 4 pi per channel.
    assert np.allclose(r.lighting(ac.Environment("constant:1")).energy, 4 * np.pi, rtol=1e-9)
    other = ac.Relighter(TRANSPORT)  # the same 6x8x8 lattice: accepted
    assert other.relight(light).shape == (40, 40, 3)


def test_labels_are_the_clis_files_and_the_files_own_pixels(tmp_path, model):
    h5py = pytest.importorskip("h5py")
    out = tmp_path / "ds"
    cli("relight", model, "--env", "sky", "--rotate", "0", "--rotate", "40", "--background",
        "black", "--exr-float", "--aov", "all", "--label-format", "both", "--out", str(out))
    r = ac.Relighter(model)
    labels = r.labels()
    assert list(labels) == ["albedo", "normal", "depth", "position", "mask", "object"]
    for name, array in labels.items():
        on_disk = np.load(out / f"labels_{name}.npy")
        assert on_disk.dtype == array.dtype and np.array_equal(on_disk, array), name
    assert labels["object"].dtype == np.int32
    # The same numbers in the EXR, channel by channel (float: exact).
    exr = ac.read_image(str(out / "labels.exr"))
    assert exr.shape == (40, 40, 12)
    # Against the model file itself, read by h5py.
    with h5py.File(model, "r") as f:
        pixels = f["pixels"][:]
        coverage, albedo = f["coverage"][:], f["albedo"][:]
        raw = f.attrs["object_names"]  # a fixed-length string: bytes in h5py
        names = (raw.decode() if isinstance(raw, bytes) else raw).split("\n")
        ys, xs = np.divmod(pixels, 40)
        assert np.array_equal(labels["mask"][ys, xs], coverage)
        assert np.array_equal(labels["albedo"][ys, xs], albedo * coverage[:, None])
        assert np.array_equal(labels["normal"][ys, xs], f["normal"][:])
        assert np.array_equal(labels["object"][ys, xs], f["object"][:])
    assert r.object_names == names and "ground" in names
    background = np.ones((40, 40), bool)
    background[ys, xs] = False
    assert (labels["object"][background] == -1).all() and (labels["mask"][background] == 0).all()
    n = labels["normal"][ys, xs]
    assert np.allclose(np.linalg.norm(n, axis=1), 1, atol=1e-5)
    # Shading: the CLI's files, and shading x albedo is the frame.
    lines = [json.loads(line) for line in open(out / "manifest.jsonl")]
    assert [len(line["shading"]) for line in lines] == [2, 2]
    for line, yaw in zip(lines, (0, 40)):
        frame = r.relight(ac.Environment("sky"), yaw=yaw, background="black")
        shading = r.shading(frame)
        assert np.array_equal(shading, np.load(out / line["shading"][1]))
        assert np.array_equal(frame, ac.read_image(str(out / line["outputs"][0])))
        assert np.allclose(shading * labels["albedo"], frame, rtol=1e-6, atol=0)
        assert "labels.exr" in line["labels"]


def test_drawn_lightings_are_the_clis_and_relight_to_its_frames(tmp_path, model):
    maps = ["sky", "sun:50,30,4,1000", "constant:1"]
    out = tmp_path / "sampled"
    cli("relight", model, *[a for m in maps for a in ("--env", m)], "--env-sample", "5",
        "--seed", "99", "--sample-rotation", "sphere", "--exposure-jitter", "0.5",
        "--exposure", "1", "--exr-float", "--out", str(out))
    lines = [json.loads(line) for line in open(out / "manifest.jsonl")]
    draws = ac.draw_lightings(len(maps), 5, seed=99, rotation="sphere", exposure_jitter=0.5)
    assert len(draws) == len(lines) == 5
    r = ac.Relighter(model)
    for (index, yaw, pitch, roll, offset), line in zip(draws, lines):
        assert line["env"] == maps[index] and line["sample"] == lines.index(line)
        assert (line["yaw"], line["pitch"], line["roll"]) == (yaw, pitch, roll)
        assert line["exposure"] == 1 + offset and abs(offset) <= 0.5
        image = r.relight(ac.Environment(maps[index]), yaw=yaw, pitch=pitch, roll=roll,
                          exposure=1 + offset)
        assert np.array_equal(image, ac.read_image(str(out / line["outputs"][0])))
    assert ac.draw_lightings(3, 5, seed=100) != ac.draw_lightings(3, 5, seed=99)
    with pytest.raises(ac.Error, match="environment samples"):
        ac.draw_lightings(3, 0)


def test_a_scene_of_several_views_is_precomputed_one_view_per_call(tmp_path):
    scene = tmp_path / "orbit.json"
    scene.write_text("""{"cameras": {"orbit": {"target": [0, 0.5, 0], "radius": 5,
        "elevation_deg": 20, "count": 2, "fov": 30, "width": 16, "height": 12}},
        "objects": [{"shape": "sphere", "center": [0, 0.6, 0], "radius": 0.6,
                     "material": {"type": "diffuse", "albedo": [0.7, 0.3, 0.2]}}]}""")
    cli("precompute", "--scene", str(scene), "--cubemap", "4", "--spp", "1",
        "--out", str(tmp_path / "t.h5"))
    with pytest.raises(ac.Error, match="2 views: give view=0..1"):
        ac.precompute(str(scene), str(tmp_path / "p.h5"), cubemap=4, spp=1)
    with pytest.raises(ac.Error, match="view '2'"):
        ac.precompute(str(scene), str(tmp_path / "p.h5"), cubemap=4, spp=1, view=2)
    ac.precompute(str(scene), str(tmp_path / "p.h5"), cubemap=4, spp=1, view=1)
    mine, theirs = ac.Relighter(str(tmp_path / "p.h5")), ac.Relighter(str(tmp_path / "t_v01.h5"))
    assert mine.info["camera"] == theirs.info["camera"]
    sky = ac.Environment("sky")
    assert np.array_equal(mine.relight(sky), theirs.relight(sky))


def test_frames_carry_no_negative_light_unless_asked_as_the_cli_writes_them(tmp_path, model):
    r = ac.Relighter(model)
    # A point lamp lit exactly never goes below zero; through the lattice it
    # reads single entries of the model's reconstruction of T, which
    # undershoots where the transport is zero or small.
    point = ac.Light("point:0,3,2,40")
    assert r.light_mode == "exact"
    assert r.relight(None, lights=[point], background="black", keep_negative=True).min() >= 0
    r.light_mode = "lattice"
    assert (r.relight(None, lights=[point], background="black", keep_negative=True) < 0).any()
    with pytest.raises(ac.Error, match="light mode 'sharp'"):
        r.light_mode = "sharp"
    r.light_mode = "exact"
    # So does a sphere lamp: exact, never below zero; through the lattice,
    # the model's undershoot, clamped unless asked.
    lamp = ac.Light("sphere:0,3,2,0.05,1600")
    assert r.relight(None, lights=[lamp], background="black", keep_negative=True).min() >= 0
    r.light_mode = "lattice"
    raw = r.relight(None, lights=[lamp], background="black", keep_negative=True)
    assert (raw < 0).sum() > 0, "this lamp no longer shows the model's undershoot"
    clamped = r.relight(None, lights=[lamp], background="black")
    assert np.array_equal(clamped, np.maximum(raw, 0))
    # The penumbra's rays: 64 by default, any square from 4 to 256.
    r.light_mode = "exact"
    assert r.lamp_rays == 64
    r.lamp_rays = 16
    assert r.relight(None, lights=[lamp], background="black").min() >= 0
    with pytest.raises(ac.Error, match="lamp rays '50'"):
        r.lamp_rays = 50
    assert r.lamp_rays == 16
    r.lamp_rays = 64
    r.light_mode = "lattice"
    batch = r.relight_batch([ac.Environment("sky")], lights=[lamp], background="alpha")
    assert batch.min() >= 0
    assert (r.shading(raw, keep_negative=True) < 0).any() and r.shading(raw).min() >= 0
    # The CLI's frame, exposure and all: the same values.
    out = tmp_path / "lamp.exr"
    cli("relight", model, "--light", "sphere:0,3,2,0.05,1600", "--light-mode", "lattice",
        "--background", "black", "--exposure", "1", "--exr-float", "--out", str(out))
    assert np.array_equal(ac.read_image(str(out)),
                          r.relight(None, lights=[lamp], background="black", exposure=1))


def test_a_dataset_moved_elsewhere_loads_from_any_working_directory(tmp_path, model):
    made = tmp_path / "made"
    cli("relight", model, "--env", "sky", "--env", "constant:1", "--rotate", "0:360:180",
        "--aov", "all", "--exr-float", "--out", str(made))
    moved = tmp_path / "elsewhere" / "moved"
    moved.parent.mkdir()
    shutil.move(str(made), str(moved))
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "examples"))
    try:
        import load_dataset
    finally:
        sys.path.pop(0)
    here = os.getcwd()
    os.chdir(tmp_path)
    try:
        (images, labels), = load_dataset.batches("elsewhere/moved", 4)
        view = load_dataset.view_labels(load_dataset.read_manifest("elsewhere/moved")[0],
                                        "elsewhere/moved")
    finally:
        os.chdir(here)
    assert images.shape == (4, 40, 40, 3) and labels["shading"].shape == (4, 40, 40, 3)
    assert np.array_equal(images[1], ac.Relighter(model).relight(ac.Environment("sky"), yaw=180))
    assert view.keys() == ac.Relighter(model).labels().keys()


def test_the_import_loads_no_image_codecs_until_the_first_image(tmp_path):
    # A fresh interpreter: this one has read images already.
    script = """
import sys, numpy as np, adaptive_cpca as ac
def mapped(name):
    with open("/proc/self/maps") as maps:
        return any(name in line for line in maps)
assert not mapped("libOpenImageIO") and not mapped("libacpca_image_codecs"), "loaded at import"
ac.Environment.from_array(np.ones((8, 16, 3), np.float32), "flat")  # no file: none yet
assert not mapped("libOpenImageIO")
with open(sys.argv[1], "wb") as ppm:
    ppm.write(b"P6 2 1 255\\n" + bytes([255, 0, 0, 0, 0, 255]))
assert ac.read_image(sys.argv[1]).shape == (1, 2, 3)
assert mapped("libOpenImageIO") and mapped("libacpca_image_codecs")
"""
    subprocess.run([sys.executable, "-c", script, str(tmp_path / "x.ppm")], check=True)


def test_openblas_generic_kernels_loaded_by_numpy_first_are_not_asked(tmp_path):
    # numpy loads OpenBLAS before adaptive_cpca can choose its kernels; under
    # the generic ones that Debian 12's OpenBLAS falls back to on CPUs newer
    # than it, Eigen answers every eigenproblem (with one warning) and the
    # model is as good as the CLI's under the CPU's own kernels.
    script = (
        "import json, warnings, numpy, adaptive_cpca as ac\n"
        "with warnings.catch_warnings(record=True) as seen:\n"
        "    warnings.simplefilter('always')\n"
        f"    ac.compress({TRANSPORT!r}, {str(tmp_path / 'py.h5')!r}, method='adaptive-binary',\n"
        "                clusters=4)\n"
        "print(json.dumps({'linear_algebra': ac.linear_algebra(),\n"
        "                  'warnings': [str(w.message) for w in seen]}))\n")
    env = {k: v for k, v in os.environ.items() if not k.startswith("OPENBLAS_")}
    run = subprocess.run([sys.executable, "-c", script], env=dict(env, OPENBLAS_CORETYPE="PRESCOTT"),
                         capture_output=True, text=True, check=True)
    report = json.loads(run.stdout.splitlines()[-1])
    assert report["linear_algebra"]["blas_core"] == "Prescott"
    assert report["linear_algebra"]["blas_core_chosen_by"] == "OPENBLAS_CORETYPE"
    with open("/proc/cpuinfo") as cpuinfo:
        flags = next(line for line in cpuinfo if line.startswith("flags")).split()
    unsuited = "avx2" in flags and "fma" in flags
    assert report["linear_algebra"]["eigensolver"] == ("Eigen" if unsuited else "LAPACK")
    assert any("OPENBLAS_CORETYPE=" in w for w in report["warnings"]) == unsuited
    subprocess.run([CLI, "compress", TRANSPORT, "--method", "adaptive-binary", "--clusters", "4",
                    "--quiet", "--out", str(tmp_path / "cli.h5")], env=env, check=True)
    ours, theirs = ac.info(str(tmp_path / "py.h5")), ac.info(str(tmp_path / "cli.h5"))
    assert ours["settings"]["eigensolver"] == report["linear_algebra"]["eigensolver"]
    assert theirs["settings"]["eigensolver"] == "LAPACK"
    assert ours["transport_error"] == pytest.approx(theirs["transport_error"], rel=0.02)
    assert ours["cost_per_pixel"] == pytest.approx(theirs["cost_per_pixel"], rel=0.05)
