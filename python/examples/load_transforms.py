"""Reads a multi-view dataset through its transforms.json alone, as NeRF-style
training code does (docs/datasets.md, "Cameras"): each frame's image, its
camera's rays and its lighting. numpy and json only; frames written with
--format npy load with numpy, others with imageio where it is installed.

  /usr/bin/python3 python/examples/load_transforms.py DIR
"""

import argparse
import json
import os

import numpy as np


def read_picture(path):
    """An image as float32 (H, W, C): .npy linear as written, else through imageio."""
    if path.endswith(".npy"):
        return np.load(path)
    import imageio.v3 as iio  # PNG (sRGB codes 0-255) or EXR, where installed
    return np.asarray(iio.imread(path), dtype=np.float32)


def rays(camera, camera_to_world):
    """Every pixel centre's ray in world space: origins and unit directions
    (H, W, 3). transform_matrix is camera to world in OpenGL's axes (x
    right, y up, the camera looking down -z); pixel (x, y)'s centre is at
    (x + 0.5, y + 0.5), row 0 the top."""
    y, x = np.mgrid[0:camera["h"], 0:camera["w"]] + 0.5
    local = np.stack([(x - camera["cx"]) / camera["fl_x"], -(y - camera["cy"]) / camera["fl_y"],
                      -np.ones_like(x)], axis=-1)
    directions = local @ camera_to_world[:3, :3].T
    directions /= np.linalg.norm(directions, axis=-1, keepdims=True)
    return np.broadcast_to(camera_to_world[:3, 3], directions.shape), directions


def frames(directory):
    """Yields (image, origins, directions, frame) per frame: the frame's
    transforms.json entry holds its lighting (env, yaw, pitch, roll,
    exposure, sh9, lights) and view, and depth_file_path / mask_path where
    the batch wrote them."""
    with open(os.path.join(directory, "transforms.json")) as f:
        meta = json.load(f)
    for frame in meta["frames"]:
        camera = {k: frame.get(k, meta.get(k)) for k in ("fl_x", "fl_y", "cx", "cy", "w", "h")}
        origins, directions = rays(camera, np.array(frame["transform_matrix"]))
        image = read_picture(os.path.join(directory, frame["file_path"]))
        yield image, origins, directions, frame


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("directory")
    args = parser.parse_args()
    for image, origins, _, frame in frames(args.directory):
        print(f"frame {frame['frame']}: view {frame['view']}, {frame['file_path']} "
              f"{image.shape}, eye {origins[0, 0].round(3).tolist()}, {frame['env']} "
              f"at yaw {frame['yaw']}")


if __name__ == "__main__":
    main()
