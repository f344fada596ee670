"""A multi-view batch read through transforms.json alone
(python/examples/load_transforms.py): every covered pixel's ray passes
through its position label at its depth label's distance along the view
axis, and every frame's image is the one the manifest lists; PyTorch's relighter reports the same camera."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

CLI = os.environ["ACPCA_CLI"]

SCENE = {
    "cameras": {"orbit": {"target": [0, 0.5, 0], "radius": 5, "elevation_deg": 25, "count": 3,
                          "fov": 35, "width": 28, "height": 20}},
    "objects": [
        {"shape": "sphere", "center": [0, 0.6, 0], "radius": 0.6,
         "material": {"type": "diffuse", "albedo": [0.7, 0.3, 0.2]}},
        {"shape": "plane", "center": [0, 0, 0], "normal": [0, 1, 0], "size": 4,
         "material": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}}],
}


def cli(*args):
    subprocess.run([CLI, *map(str, args), "--quiet"], check=True)


def test_the_transforms_loader_reads_a_multi_view_dataset(tmp_path):
    (tmp_path / "orbit.json").write_text(json.dumps(SCENE))
    cli("build", "--scene", tmp_path / "orbit.json", "--cubemap", 4, "--spp", 1,
        "--out", tmp_path / "t.h5")
    views = [tmp_path / f"t_v0{k}.h5" for k in range(3)]
    out = tmp_path / "set"
    cli("relight", *views, "--env", "sky", "--rotate", "0:360:180", "--format", "npy",
        "--aov", "position,depth,mask", "--label-format", "npy", "--out", out)
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "examples"))
    try:
        import load_transforms
    finally:
        sys.path.pop(0)
    manifest = [json.loads(line) for line in (out / "manifest.jsonl").read_text().splitlines()]
    seen, cameras = 0, {}
    for image, origins, directions, frame in load_transforms.frames(str(out)):
        line = manifest[frame["frame"]]
        assert frame["view"] == line["view"] and frame["yaw"] == line["yaw"]
        assert frame["sh9"] == line["sh9"]
        assert np.array_equal(image, np.load(out / line["outputs"][0]))
        assert image.shape == (20, 28, 3)
        stem = os.path.join(out, f"labels_v0{frame['view']}")
        position = np.load(stem + "_position.npy")
        depth = np.load(out / frame["depth_file_path"])
        covered = np.load(stem + "_mask.npy") > 0
        assert covered.sum() > 100
        # The ray through each covered pixel's centre meets its position.
        offset = (position - origins)[covered]
        along = np.sum(offset * directions[covered], axis=-1)
        miss = np.linalg.norm(offset - along[:, None] * directions[covered], axis=-1)
        assert np.all(along > 0) and miss.max() < 1e-4 * along.max()
        # Depth is planar: along the camera's -z axis, not along the ray.
        axis = -np.array(frame["transform_matrix"])[:3, 2]
        assert np.allclose(offset @ axis, depth[covered], rtol=1e-5)
        seen += 1
        cameras[frame["view"]] = frame
    assert seen == len(manifest) == 6
    # PyTorch's relighter gives each model's camera as the file holds it.
    torch = pytest.importorskip("torch")
    from adaptive_cpca.torch import TorchRelighter
    meta = json.loads((out / "transforms.json").read_text())
    for view, frame in cameras.items():
        camera = TorchRelighter(str(views[view]), device="cpu").camera
        assert np.allclose(camera["transform_matrix"], frame["transform_matrix"], rtol=0,
                           atol=1e-12)
        for key in ("fl_x", "fl_y", "cx", "cy", "w", "h"):
            assert camera[key] == pytest.approx(meta[key], rel=1e-14), key
