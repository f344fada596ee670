"""Environment images read into numpy, with or without the compiled part.

Every image goes through the compiled part where it loaded (the CLI's
reader, `adaptive_cpca.read_image`). Without it (or in a DataLoader worker),
Radiance .hdr (RGBE, flat or run-length scanlines) and .pfm are read here
(pure_read_image, tested equal to it), other formats (OpenEXR, TIFF) through
OpenImageIO's Python binding (Debian's python3-openimageio), OpenCV or
imageio, whichever is installed. Row 0 is the top of the image, as the CLI
reads maps.
"""

import json
import os
import struct

import numpy as np

from ._compiled import compiled_part, in_dataloader_worker

__all__ = ["read_image", "pure_read_image", "read_frame_metadata"]


def read_image(path):
    """float32 [H, W, C] of the image at path (C its channels, 1 to 4)."""
    core = compiled_part()
    if core is not None:
        try:
            return core.read_image(path)
        except core.Error as e:
            raise ValueError(str(e)) from None
    return pure_read_image(path)


def pure_read_image(path):
    """read_image without the compiled part."""
    ext = os.path.splitext(path)[1].lower()
    try:
        if ext == ".hdr":
            return _read_hdr(path)
        if ext == ".pfm":
            return _read_pfm(path)
    except (ValueError, IndexError, OSError) as e:
        raise ValueError(f"{path}: cannot read the environment map: {e}") from None
    return _read_with_a_library(path)


def _read_with_a_library(path):
    if in_dataloader_worker():
        # OpenImageIO's thread pool (in the compiled part and in its binding)
        # does not survive a fork.
        raise ValueError(f"{path}: a map file is read before the DataLoader forks its workers "
                         "(RelightDataset reads its maps when it is made)")
    try:
        import OpenImageIO as oiio
        image = oiio.ImageInput.open(path)
        if image is None:
            raise ValueError(f"{path}: cannot read the environment map: {oiio.geterror()}")
        try:
            pixels = image.read_image(oiio.FLOAT)
        finally:
            image.close()
        if pixels is None:
            raise ValueError(f"{path}: cannot read the environment map pixels")
        pixels = np.asarray(pixels, dtype=np.float32)
        return pixels if pixels.ndim == 3 else pixels.reshape(pixels.shape[0], -1, 1)
    except ImportError:
        pass
    try:
        os.environ.setdefault("OPENCV_IO_ENABLE_OPENEXR", "1")
        import cv2
        pixels = cv2.imread(path, cv2.IMREAD_ANYDEPTH | cv2.IMREAD_ANYCOLOR)
        if pixels is None:
            raise ValueError(f"{path}: cannot read the environment map (OpenCV)")
        pixels = pixels.astype(np.float32)
        if pixels.ndim == 2:
            return pixels[:, :, None]
        return pixels[:, :, [2, 1, 0] + list(range(3, pixels.shape[2]))]  # BGR to RGB
    except ImportError:
        pass
    try:
        import imageio
        return np.asarray(imageio.imread(path), dtype=np.float32)
    except ImportError:
        raise ValueError(f"{path}: reading this format needs OpenImageIO's Python binding "
                         "(python3-openimageio), OpenCV or imageio; .hdr and .pfm need none")


def _read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        if kind not in (b"PF", b"Pf"):
            raise ValueError("not a PFM file (no PF or Pf line)")
        width, height = (int(v) for v in f.readline().split())
        scale = float(f.readline())
        channels = 3 if kind == b"PF" else 1
        dtype = "<f4" if scale < 0 else ">f4"
        data = np.frombuffer(f.read(width * height * channels * 4), dtype=dtype)
    if data.size != width * height * channels:
        raise ValueError("the file is shorter than its header says")
    # Rows are stored bottom to top.
    return data.reshape(height, width, channels)[::-1].astype(np.float32)


def _read_hdr(path):
    with open(path, "rb") as f:
        data = f.read()
    if not data.startswith(b"#?"):
        raise ValueError("not a Radiance HDR file (no #? line)")
    end = data.index(b"\n\n") + 2
    header = data[:end].decode("ascii", "replace")
    if "FORMAT=" in header and "32-bit_rle_rgbe" not in header:
        raise ValueError("only 32-bit_rle_rgbe Radiance files are read")
    line_end = data.index(b"\n", end)
    size = data[end:line_end].split()
    if len(size) != 4 or size[0] != b"-Y" or size[2] != b"+X":
        raise ValueError(f"orientation {data[end:line_end]!r}: only -Y H +X W is read")
    height, width = int(size[1]), int(size[3])
    rgbe = _hdr_scanlines(np.frombuffer(data, np.uint8), line_end + 1, width, height)
    exponent = rgbe[..., 3].astype(np.int32)
    scale = np.where(exponent > 0, np.ldexp(1.0, exponent - 136), 0.0)
    return (rgbe[..., :3] * scale[..., None]).astype(np.float32)


def _hdr_scanlines(raw, pos, width, height):
    out = np.empty((height, width, 4), np.uint8)
    for y in range(height):
        run_length = 8 <= width < 32768 and raw[pos] == 2 and raw[pos + 1] == 2 and raw[pos + 2] < 128
        if not run_length:  # flat RGBE pixels
            out[y] = raw[pos:pos + 4 * width].reshape(width, 4)
            pos += 4 * width
            continue
        if (int(raw[pos + 2]) << 8 | int(raw[pos + 3])) != width:
            raise ValueError(f"scanline {y}: its length does not match the width")
        pos += 4
        for channel in range(4):
            x = 0
            while x < width:
                count = int(raw[pos])
                if count > 128:  # a run of one value
                    count -= 128
                    out[y, x:x + count, channel] = raw[pos + 1]
                    pos += 2
                else:
                    out[y, x:x + count, channel] = raw[pos + 1:pos + 1 + count]
                    pos += 1 + count
                if count == 0 or x + count > width:
                    raise ValueError(f"scanline {y}: a bad run")
                x += count
    return out


def read_frame_metadata(path):
    """What a frame file (OpenEXR or PNG) says of itself (docs/formats.md,
    "Frame metadata"): a dict of its lighting and source fields (the
    `acpca:` attributes without the prefix, or the PNG's `acpca` iTXt JSON),
    with `colorInteropID`, `worldToCamera` and `worldToNDC` (16 floats, row
    by row), and an EXR's `chromaticities` or a PNG's `cICP` and `sRGB`.
    Pure Python: no library reads it. Empty for a file that says nothing."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] == b"\x76\x2f\x31\x01":
        return _exr_metadata(data, path)
    if data[:8] == b"\x89PNG\r\n\x1a\n":
        return _png_metadata(data, path)
    raise ValueError(f"{path}: neither OpenEXR nor PNG (only they carry a frame's header)")


def _field_of_text(text):
    if text[:1] in ("[", "{"):
        try:
            return json.loads(text)
        except ValueError:
            pass
    return text


def _exr_metadata(data, path):
    fields, at, prefix = {}, 8, "acpca:"
    while True:
        end = data.index(b"\0", at)
        if end == at:  # the header's closing NUL
            return fields
        name = data[at:end].decode("utf-8", "replace")
        type_end = data.index(b"\0", end + 1)
        kind = data[end + 1:type_end].decode("ascii", "replace")
        size = struct.unpack_from("<i", data, type_end + 1)[0]
        value = data[type_end + 5:type_end + 5 + size]
        at = type_end + 5 + size
        field = name.startswith(prefix)
        key = name[len(prefix):] if field else name
        if kind == "chromaticities" and name == "chromaticities":
            fields[key] = list(struct.unpack("<8f", value))
        elif kind == "m44f" and name in ("worldToCamera", "worldToNDC"):
            fields[key] = list(struct.unpack("<16f", value))
        elif kind == "string" and (field or name == "colorInteropID"):
            text = value.decode("utf-8", "replace")
            fields[key] = _field_of_text(text) if field else text
        elif field and kind == "double":
            fields[key] = struct.unpack("<d", value)[0]
        elif field and kind == "floatvector":
            fields[key] = list(struct.unpack(f"<{size // 4}f", value))
        if at >= len(data):
            raise ValueError(f"{path}: the OpenEXR header is cut short")


def _png_metadata(data, path):
    fields, at = {}, 8
    while at + 12 <= len(data):
        length, kind = struct.unpack_from(">I4s", data, at)
        body = data[at + 8:at + 8 + length]
        if kind == b"cICP" and length == 4:
            fields["cICP"] = list(body)
        elif kind == b"sRGB" and length == 1:
            fields["sRGB"] = body[0]
        elif kind == b"iTXt" and body.startswith(b"acpca\0"):
            keyword_end = body.index(b"\0")
            if body[keyword_end + 1] != 0:
                raise ValueError(f"{path}: its acpca text is compressed")
            language_end = body.index(b"\0", keyword_end + 3)
            translated_end = body.index(b"\0", language_end + 1)
            fields.update(json.loads(body[translated_end + 1:].decode("utf-8")))
        elif kind == b"IEND":
            break
        at += 12 + length
    return fields
