"""Frames that describe themselves (docs/formats.md, "Frame metadata"), read
by the package's pure-Python reader: a batch's EXR and PNG frames say what
its manifest says of them, the PNG holds its sRGB chunks, and a browser's
decoding of the PNG (sRGB to linear) gives the EXR's values through the
clamp tone curve."""

import json
import os

import numpy as np
import pytest

from adaptive_cpca.io import read_frame_metadata, read_image
from relight_support import TRANSPORT, WORLD, cli

SHARED = ("env", "env_sha256", "yaw", "pitch", "roll", "exposure", "lights", "sources", "frame")


def srgb_to_linear(code):
    c = code / 255.0
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def test_frames_say_what_the_manifest_says(tmp_path):
    out = tmp_path / "set"
    cli("relight", TRANSPORT, "--env", "sky", "--rotate", "0:360:120", "--exposure", "0.5",
        "--light", "point:0.5,1.5,0.5,3", "--format", "exr,png", "--exr-float", "--out", str(out))
    with open(out / "manifest.jsonl") as f:
        lines = [json.loads(line) for line in f]
    assert len(lines) == 3
    for line in lines:
        exr, png = (str(out / name) for name in line["outputs"])
        for path in (exr, png):
            header = read_frame_metadata(path)
            for key in SHARED:
                if line[key] is None and path.endswith(".exr"):
                    assert key not in header
                else:
                    assert header[key] == line[key], (path, key)
            assert header["colorInteropID"] == "lin_rec709_scene"
            assert len(header["worldToNDC"]) == 16
        assert np.allclose(read_frame_metadata(exr)["sh9"], np.ravel(line["sh9"]), rtol=1e-6)
        assert read_frame_metadata(png)["sh9"] == line["sh9"]
        assert read_frame_metadata(png)["cICP"] == [1, 13, 0, 1]
        assert read_frame_metadata(exr)["chromaticities"][6:] == [np.float32(0.3127),
                                                                  np.float32(0.3290)]
        # The browser's view of the PNG: its 8-bit codes are the EXR's values
        # (written times 2^exposure too) through the clamp curve and the sRGB
        # transfer function, so decoding them (sRGB to linear) gives the EXR
        # back to within one code's step.
        linear = np.clip(read_image(exr)[..., :3], 0, 1)
        codes = np.round(read_image(png)[..., :3] * 255)
        expected = np.round(linear_to_code(linear))
        assert np.abs(codes - expected).max() <= 1
        assert (codes == expected).mean() > 0.999
        step = srgb_to_linear(np.minimum(codes + 1, 255)) - srgb_to_linear(np.maximum(codes - 1, 0))
        assert np.all(np.abs(srgb_to_linear(codes) - linear) <= step)


def linear_to_code(linear):
    return 255 * np.where(linear <= 0.0031308, 12.92 * linear,
                          1.055 * np.power(linear, 1 / 2.4) - 0.055)


def test_torch_frame_fields_are_the_cli_frames_header(model, tmp_path):
    """TorchRelighter.frame_fields says what the CLI's frame of the same view
    says in its header: lighting, sh9, camera and source."""
    torch_module = __import__("adaptive_cpca.torch", fromlist=["TorchRelighter"])
    world = os.path.join(WORLD, "courtyard.exr")
    frame = str(tmp_path / "f.exr")
    cli("relight", model, "--env", world, "--rotate", "137", "--exposure", "1", "--sun", "off",
        "--out", frame)
    header = read_frame_metadata(frame)
    fields = torch_module.TorchRelighter(model).frame_fields(world, yaw=137, exposure=1)
    for key in ("env_sha256", "yaw", "pitch", "roll", "exposure", "lights", "source",
                "source_sha256", "method", "version", "colorInteropID"):
        assert fields[key] == header[key], key
    assert fields["env"] == header["env"] == world
    assert np.allclose(np.ravel(fields["sh9"]), header["sh9"], rtol=1e-5, atol=1e-7)
    assert fields["cost_per_pixel"] == pytest.approx(header["cost_per_pixel"], rel=1e-12)
    for key in ("worldToCamera", "worldToNDC"):
        assert np.allclose(fields[key], header[key], rtol=1e-6, atol=1e-6), key
