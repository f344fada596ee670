"""A model's pinhole camera, as transport/camera.h makes its rays and
transport/camera.cpp its OpenEXR matrices, in float64 numpy.

camera: the dict a model file's camera_eye, camera_target, camera_up and
camera_fov_deg attributes make (fov_deg the vertical field of view).
"""

import math

import numpy as np


def camera_axes(camera):
    """The camera's unit view direction, image right and image up."""
    eye, target, up = (np.asarray(camera[k], dtype=np.float64) for k in ("eye", "target", "up"))
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    return forward, right, np.cross(right, forward)


def _tan_half_fov(camera):
    return math.tan(0.5 * math.radians(float(camera["fov_deg"])))


def transforms_fields(camera, width, height):
    """The camera as a batch's transforms.json holds it (docs/datasets.md,
    "Cameras"): transform_matrix (4x4 camera to world, OpenGL axes) and
    fl_x, fl_y, cx, cy, w, h in pixels."""
    forward, right, true_up = camera_axes(camera)
    matrix = np.eye(4)
    matrix[:3, 0], matrix[:3, 1], matrix[:3, 2] = right, true_up, -forward
    matrix[:3, 3] = camera["eye"]
    focal = 0.5 * height / _tan_half_fov(camera)
    return {"transform_matrix": matrix, "fl_x": focal, "fl_y": focal, "cx": 0.5 * width,
            "cy": 0.5 * height, "w": width, "h": height}


def world_to_camera_and_ndc(camera, width, height):
    """OpenEXR's worldToCamera (x right, y up, z forward; p M) and worldToNDC
    ((0, 0) top left, (1, 1) bottom right after the divide)."""
    forward, right, true_up = camera_axes(camera)
    eye = np.asarray(camera["eye"], dtype=np.float64)
    to_camera = np.zeros((4, 4))
    for j, axis in enumerate((right, true_up, forward)):
        to_camera[:3, j] = axis
        to_camera[3, j] = -eye @ axis
    to_camera[3, 3] = 1
    scale = 2 * _tan_half_fov(camera) / height
    projection = np.zeros((4, 4))
    projection[0, 0] = 1 / (scale * width)
    projection[1, 1] = -1 / (scale * height)
    projection[2, 0] = projection[2, 1] = 0.5
    projection[2, 3] = 1
    projection[3, 2] = 1
    return to_camera, to_camera @ projection


def pixel_rays(camera, width, height):
    """Each pixel centre's unit camera ray, row by row: [H W, 3]."""
    forward, right, true_up = camera_axes(camera)
    tan_half = _tan_half_fov(camera)
    x = (2 * (np.arange(width) + 0.5) / width - 1) * tan_half * (width / height)
    y = (1 - 2 * (np.arange(height) + 0.5) / height) * tan_half
    rays = forward + x[None, :, None] * right + y[:, None, None] * true_up
    rays /= np.linalg.norm(rays, axis=-1, keepdims=True)
    return rays.reshape(-1, 3)
