"""The Python module against the CLI, files and its own promises.

Run by ctest (python_tests) with PYTHONPATH at the built module, ACPCA_CLI the
adaptive-cpca binary and ACPCA_FIXTURE_DIR the transports the build makes.
"""

import json
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

import adaptive_cpca as ac
from relight_support import CLI, TRANSPORT, WORLD, cli, cli_image


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
    assert list(labels) == ["albedo", "normal", "tangent", "depth", "position", "mask", "object"]
    for name, array in labels.items():
        on_disk = np.load(out / f"labels_{name}.npy")
        assert on_disk.dtype == array.dtype and np.array_equal(on_disk, array), name
    assert labels["object"].dtype == np.int32
    # The same numbers in the EXR, channel by channel (float: exact).
    exr = ac.read_image(str(out / "labels.exr"))
    assert exr.shape == (40, 40, 15)
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
        first = f["lamp_sample_start"][:-1]  # each row's first traced camera sample
        assert np.array_equal(labels["tangent"][ys, xs], f["lamp_sample_tangent"][:][first])
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
