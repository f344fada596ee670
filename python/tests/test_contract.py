"""The generated contract (adaptive_cpca._contract) against what the C++
does, constant by constant, and the package's pure-Python side against it:
it copies none of the contract's values, and its copies of the lattice, the
SH means and the draws equal the compiled part's."""

import math
import os
import re
import shutil
import subprocess
import sys
import warnings

import h5py
import numpy as np
import pytest

import adaptive_cpca as ac
from adaptive_cpca import _contract as contract
from adaptive_cpca import sampling

CLI = os.environ["ACPCA_CLI"]
PLANT = os.path.join(os.environ["ACPCA_FIXTURE_DIR"], "small-plant.h5")
PACKAGE = os.path.dirname(ac.__file__)
SOURCE_PACKAGE = os.path.join(os.path.dirname(os.path.dirname(__file__)), "adaptive_cpca")


def refused(call, *args, **kwargs):
    """The message of the error `call` raises."""
    with pytest.raises((ac.Error, ValueError)) as caught:
        call(*args, **kwargs)
    return str(caught.value)


def with_version(tmp_path, source, name, version):
    path = str(tmp_path / name)
    shutil.copy(source, path)
    with h5py.File(path, "r+") as f:
        f.attrs["version"] = version
    return path


def check_file_versions(tmp_path):
    with h5py.File(PLANT) as f:
        assert int(f.attrs["version"]) == contract.TRANSPORT_VERSION
    model = str(tmp_path / "model.h5")
    subprocess.run([CLI, "compress", PLANT, "--method", "global", "--quiet", "--out", model],
                   check=True)
    with h5py.File(model) as f:
        assert int(f.attrs["version"]) == contract.MODEL_VERSION
    # The oldest version read is read; the one before it, and the one after
    # the newest, are refused, naming the range.
    reads = (f"reads {contract.OLDEST_TRANSPORT_VERSION} to {contract.TRANSPORT_VERSION}")
    for version in (contract.OLDEST_TRANSPORT_VERSION - 1, contract.TRANSPORT_VERSION + 1):
        path = with_version(tmp_path, PLANT, f"t{version}.h5", version)
        assert reads in refused(ac.open, path)
    reads = f"reads {contract.OLDEST_MODEL_VERSION} to {contract.MODEL_VERSION}"
    for version in (contract.OLDEST_MODEL_VERSION - 1, contract.MODEL_VERSION + 1):
        path = with_version(tmp_path, model, f"m{version}.h5", version)
        assert reads in refused(ac.open, path)
    assert ac.__version__ == contract.VERSION


def check_lattice():
    top = contract.MAX_CUBE_RESOLUTION
    directions, solid_angles = ac.cube_lattice(top)
    assert directions.shape == (contract.CUBE_FACES * top * top, 3)
    assert f"1..{top}" in refused(ac.cube_lattice, top + 1)
    assert math.isclose(solid_angles.sum(), 4 * math.pi, rel_tol=1e-12)
    # A light set's fine lattice: 331 lights give 64 (docs/formats.md).
    from adaptive_cpca.torch.domain import cell_lattice_resolution
    assert cell_lattice_resolution(331) == 64
    assert cell_lattice_resolution(1) == contract.MIN_CELL_LATTICE
    assert cell_lattice_resolution(10**6) == contract.MAX_CELL_LATTICE
    assert contract.CELL_SAMPLES_PER_FACE_SIDE % contract.MAX_CELL_LATTICE == 0


def check_cross_faces():
    # Each face's frame (right, down, centre) is orthonormal and right-handed, and
    # the six centres are the six axes.
    centres = set()
    for column, row, centre, right, down in contract.CROSS_FACES:
        c, r, d = (np.array(v) for v in (centre, right, down))
        assert abs(c @ r) + abs(c @ d) + abs(r @ d) == 0
        assert np.array_equal(np.cross(r, d), c)
        centres.add(tuple(centre))
        assert 0 <= column < 4 and 0 <= row < 3
    assert len(centres) == 6


def check_grammars():
    message = refused(ac.Environment, "no-such-map.exr")
    assert contract.ENVIRONMENT_GRAMMARS in message
    assert contract.ENVIRONMENT_GRAMMARS in ac.Environment.__init__.__doc__
    assert ", ".join(g for _, g in contract.ENVIRONMENT_SPECS) == contract.ENVIRONMENT_GRAMMARS
    for prefix, grammar in contract.ENVIRONMENT_SPECS:
        assert grammar.startswith(prefix)
        if prefix.endswith(":"):  # a spec of the prefix and too few numbers: its grammar named
            assert grammar in refused(ac.Environment, prefix + "1,2")
    for grammar in contract.LIGHT_GRAMMARS:
        kind = grammar.split(":")[0]
        assert grammar in refused(ac.Light, f"{kind}:1")
    kinds = refused(ac.Light, "bogus:1,2,3,4")
    assert kinds.endswith(", ".join(g.split(":")[0] for g in contract.LIGHT_GRAMMARS))
    r = ac.open(PLANT)
    assert ", ".join(contract.BACKGROUNDS) in refused(r.relight, ac.Environment("sky"),
                                                      background="bogus")


def check_map_files(tmp_path):
    # A directory given as --env relights the files with these extensions, in
    # any case, and nothing else (the maps are PFM inside whatever the name).
    folder = tmp_path / "maps"
    folder.mkdir()
    pfm = b"PF\n8 4\n-1.0\n" + np.ones((4, 8, 3), "<f4").tobytes()
    names = [f"m{i}{ext.upper() if i % 2 else ext}"
             for i, ext in enumerate(contract.MAP_FILE_EXTENSIONS + (".png", ".txt"))]
    for name in names:
        (folder / name).write_bytes(pfm)
    out = tmp_path / "frames"
    subprocess.run([CLI, "relight", PLANT, "--env", str(folder), "--out", str(out), "--quiet"],
                   check=True)
    relit = sorted(n.split("_")[1] for n in os.listdir(out) if n.endswith(".exr"))
    assert relit == [f"m{i}" for i in range(len(contract.MAP_FILE_EXTENSIONS))], relit


def check_map_limits():
    def share(negative):
        m = np.ones((16, 32, 3), np.float32)
        m[0, 0, 0] = -negative * (m.size - 1) / (1 - negative)  # that share of the magnitude
        return m

    assert "not ringing" in refused(ac.Environment.from_array, share(1.5 * contract.MAX_NEGATIVE_SHARE))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ac.Environment.from_array(share(0.5 * contract.MAX_NEGATIVE_SHARE))
        assert any("clamped" in str(w.message) for w in caught)
        caught.clear()
        ac.Environment.from_array(share(0.5 * contract.SILENT_NEGATIVE_SHARE))
        assert not any("clamped" in str(w.message) for w in caught)
        # Off 2:1 by less than the tolerance: read with a warning; by more: refused.
        off = contract.LATLONG_ASPECT_TOLERANCE
        ac.Environment.from_array(np.ones((100, round(200 * (1 + 0.5 * off)), 3), np.float32))
        assert any("not quite 2:1" in str(w.message) for w in caught)
    wide = np.ones((100, round(200 * (1 + 2 * off)), 3), np.float32)
    assert "neither a lat-long map" in refused(ac.Environment.from_array, wide)
    # Too many pixels, refused before a byte is read: a header claiming them.
    side = math.isqrt(contract.MAX_MAP_PIXELS // 2)
    big = os.path.join(os.environ.get("TMPDIR", "/tmp"), f"acpca-contract-{os.getpid()}.pfm")
    try:
        for width in (2 * side, 2 * side + 2):
            with open(big, "wb") as f:
                f.write(b"PF\n%d %d\n-1.0\n" % (width, width // 2))
            message = refused(ac.Environment, big)
            assert ("out of range" in message) == (width * (width // 2) > contract.MAX_MAP_PIXELS)
    finally:
        os.remove(big)
    # Sub-cells: a map of one pixel per texel is cut into 8 x 8 (lattice of 8:
    # a texel spans pi/16; a 64 x 32 map's pixel pi/32, so 4 x 4 per pixel).
    from adaptive_cpca.torch.lattice import CubeLattice
    from adaptive_cpca.torch.map_cells import latlong_cells
    import torch
    directions, _ = latlong_cells(torch.ones(32, 64, 3), CubeLattice(8))
    per_side = contract.MAP_SUB_CELLS_PER_TEXEL // 2
    assert directions.shape[0] == 32 * 64 * per_side ** 2


def check_builtin_maps():
    # docs/lighting.md states the sky's numbers; the contract holds them.
    docs = os.path.join(os.path.dirname(__file__), "..", "..", "docs", "lighting.md")
    with open(docs) as f:
        text = " ".join(f.read().split())

    def written(v):
        return "(" + ", ".join(f"{x:.2f}" if x < 10 else f"{x:g}" for x in v) + ")"

    for name in ("SKY_ZENITH", "SKY_HORIZON", "SKY_GROUND", "SKY_SUN_RADIANCE"):
        assert written(getattr(contract, name)) in text, name
    glow = (f"{contract.SKY_GLOW_STRENGTH:g} exp(-{contract.SKY_GLOW_SHARPNESS:g} (1 - cos gamma)) "
            f"{written(contract.SKY_GLOW_COLOUR).replace('1.00', '1.0').replace('0.90', '0.9')}")
    assert glow.replace("0.70", "0.7") in text, glow
    assert f"(1 - y)^{contract.SKY_HORIZON_POWER}" in text
    theta, phi, size = contract.SKY_SUN
    assert f"{size:g} degrees wide at THETA = {theta:g}, PHI = {phi:g}" in text
    # The torch sky and discs from the contract equal the compiled part's,
    # on lattices where the rings are clamped at either end and where not.
    import torch

    from adaptive_cpca.torch.lattice import CubeLattice
    from adaptive_cpca.torch.lighting import Environment
    for spec, resolution in (("sky", 8), ("sun:30,40,0.5,100", 2), ("sun:30,40,60,1", 64),
                             ("sun:30,40,5,1", 16)):
        same = torch.eye(3, dtype=torch.float64)[None]
        mine = Environment(spec).integrate(CubeLattice(resolution), same)[0].numpy()
        theirs = ac.Environment(spec).lattice_lightings(resolution, [(0.0, 0.0, 0.0)])[0]
        assert np.allclose(mine, theirs, rtol=1e-12, atol=1e-12), spec
    rings = [math.ceil(contract.DISC_RINGS_PER_TEXEL * math.radians(size) / (math.pi / 2 / r))
             for size, r in ((0.5, 2), (60, 64))]
    assert rings[0] < contract.MIN_DISC_RINGS and rings[1] > contract.MAX_DISC_RINGS
    assert contract.SKY_SUB_CELLS >= 1


def check_sh9():
    # c0 .. c4: sqrt(1/4pi), sqrt(3/4pi), sqrt(15/4pi), sqrt(5/16pi), sqrt(15/16pi).
    expected = [math.sqrt(k / (m * math.pi)) for k, m in ((1, 4), (3, 4), (15, 4), (5, 16),
                                                          (15, 16))]
    assert np.allclose(contract.SH9_NORMALISATIONS, expected, rtol=1e-15, atol=0)


def check_sampling():
    # SplitMix64's published outputs for seed 0 (Vigna's splitmix64.c).
    reference = [0xE220A8397B1DCDAF, 0x6E789E6AA1B965F4, 0x06C45D188009454F]
    assert [sampling._output(0, k) for k in range(3)] == reference
    assert contract.SAMPLED_ROTATIONS == ("yaw", "sphere")
    assert "0..20 stops" in refused(ac.draw_lightings, 2, 3, exposure_jitter=21)
    assert math.isclose(contract.MAX_EXPOSURE_JITTER, 20)
    too_many = contract.MAX_LIGHTING_SAMPLES + 1
    assert f"1..{contract.MAX_LIGHTING_SAMPLES}" in refused(ac.draw_lightings, 2, too_many)
    # Angles come rounded to 1 / DRAW_ROUNDING_STEPS, from UNIFORMS_PER_DRAW uniforms a draw.
    for d in ac.draw_lightings(3, 50, seed=7, rotation="sphere", exposure_jitter=3):
        for v in d[1:]:
            assert v * contract.DRAW_ROUNDING_STEPS == pytest.approx(
                round(v * contract.DRAW_ROUNDING_STEPS), abs=1e-6)
    first = ac.draw_lightings(1, 2, seed=3)
    u = (sampling._output(3, contract.UNIFORMS_PER_DRAW + 1) >> 11) * 2.0 ** -53  # draw 1's yaw
    assert first[1][1] == round(360 * u * 1e6) / 1e6


CHECKS = {
    "file versions": (("VERSION", "MODEL_VERSION", "OLDEST_MODEL_VERSION", "TRANSPORT_VERSION",
                       "OLDEST_TRANSPORT_VERSION"), check_file_versions),
    "lattice": (("CUBE_FACES", "MAX_CUBE_RESOLUTION", "CELL_LATTICE_STEP", "MIN_CELL_LATTICE",
                 "MAX_CELL_LATTICE", "CELL_SAMPLES_PER_FACE_SIDE"), check_lattice),
    "cross": (("CROSS_FACES",), check_cross_faces),
    "grammars": (("ENVIRONMENT_GRAMMARS", "ENVIRONMENT_SPECS", "LIGHT_GRAMMARS",
                  "BACKGROUNDS"), check_grammars),
    "map files": (("MAP_FILE_EXTENSIONS",), check_map_files),
    "map limits": (("MAX_NEGATIVE_SHARE", "SILENT_NEGATIVE_SHARE", "LATLONG_ASPECT_TOLERANCE",
                    "MAX_MAP_PIXELS", "MAP_SUB_CELLS_PER_TEXEL"), check_map_limits),
    "built-in maps": (("SKY_SUN", "SKY_SUN_RADIANCE", "SKY_ZENITH", "SKY_HORIZON", "SKY_GROUND",
                       "SKY_GLOW_COLOUR", "SKY_GLOW_STRENGTH", "SKY_GLOW_SHARPNESS",
                       "SKY_HORIZON_POWER", "SKY_SUB_CELLS", "DISC_RINGS_PER_TEXEL",
                       "MIN_DISC_RINGS", "MAX_DISC_RINGS"), check_builtin_maps),
    "sh9": (("SH9_NORMALISATIONS",), check_sh9),
    "sampling": (("SPLITMIX_INCREMENT", "SPLITMIX_MIXES", "SPLITMIX_LAST_SHIFT",
                  "UNIFORMS_PER_DRAW", "DRAW_ROUNDING_STEPS", "MAX_LIGHTING_SAMPLES",
                  "MAX_EXPOSURE_JITTER", "SAMPLED_ROTATIONS"), check_sampling),
}


def test_every_constant_of_the_contract_has_a_check():
    names = {n for n in vars(contract) if n.isupper()}
    checked = {n for group, _ in CHECKS.values() for n in group}
    assert names == checked, (sorted(names - checked), sorted(checked - names))


@pytest.mark.parametrize("group", sorted(CHECKS))
def test_the_contract_is_what_the_cpp_does(group, tmp_path):
    check = CHECKS[group][1]
    if "tmp_path" in check.__code__.co_varnames[:check.__code__.co_argcount]:
        check(tmp_path)
    else:
        check()


def contract_literals():
    """The contract's values as a copy would write them: numbers of three or
    more significant digits (and hex), grammars; small ones (8, 0.5, "yaw")
    are too common in code to tell a copy from a coincidence."""
    def items(v):
        return [x for item in v for x in items(item)] if isinstance(v, tuple) else [v]

    out = set()
    for name, value in vars(contract).items():
        if not name.isupper():
            continue
        for v in items(value):
            if isinstance(v, str) and ":" in v and not v.endswith(":"):  # a grammar, not a prefix
                out.add(v)
            elif isinstance(v, int) and abs(v) >= 100:
                out.update({str(v), hex(v), f"{v:#X}".replace("0X", "0x")})
            elif isinstance(v, float) and (len(f"{abs(v):.15g}".replace(".", "").strip("0")) >= 2
                                           or (v == int(v) and abs(v) >= 100)):
                out.update({repr(v), f"{v:g}"})
    return out


def test_the_pure_python_side_copies_no_constant_of_the_cpp():
    literals = contract_literals()
    assert {"0x9E3779B97F4A7C15", "0.28209479177387814", "2000.0", "0.16"} <= literals
    version = re.compile(r"[A-Z_]*VERSION[A-Z_]*\s*(,\s*[A-Z_]+\s*)*=\s*[\d(]|version\s*[<>=!]=?\s*\d")
    for folder, _, files in os.walk(SOURCE_PACKAGE):
        for name in files:
            if not name.endswith(".py"):
                continue
            path = os.path.join(folder, name)
            with open(path) as f:
                code = f.read()
            assert not version.search(code), (path, version.search(code).group(0))
            numbers = set(re.findall(r"(?<![\w.])(?:0x[0-9A-Fa-f]+|\d+\.?\d*(?:e[-+]?\d+)?)", code))
            copied = sorted(v for v in literals if v in numbers or (":" in v and v in code))
            assert not copied, (path, copied)


def test_the_pure_python_copies_equal_the_compiled_part(tmp_path):
    import torch

    from adaptive_cpca.io import pure_read_image, read_image

    from adaptive_cpca.torch.domain import pure_texel_sh9_means, texel_sh9_means
    from adaptive_cpca.torch.lattice import CubeLattice
    for resolution in (1, 3, 32):
        lattice = CubeLattice(resolution)
        solid_angles, directions = lattice.pure_texels()
        assert torch.allclose(lattice.directions, directions, rtol=0, atol=1e-15)
        assert torch.allclose(lattice.solid_angles, solid_angles, rtol=1e-13, atol=0)
        assert torch.allclose(texel_sh9_means(lattice), pure_texel_sh9_means(lattice),
                              rtol=0, atol=1e-13)
        # Each texel's mean of Y(0,0) is c0 itself.
        assert torch.allclose(texel_sh9_means(lattice)[:, 0],
                              torch.full((lattice.size,), contract.SH9_NORMALISATIONS[0],
                                         dtype=torch.float64), rtol=1e-14, atol=0)
    # Maps: a .pfm, and a run-length .hdr where OpenImageIO's binding writes one.
    rng = np.random.default_rng(3)
    pixels = rng.gamma(0.5, 1.0, size=(32, 64, 3)).astype(np.float32)
    pfm = str(tmp_path / "map.pfm")
    with open(pfm, "wb") as f:
        f.write(b"PF\n64 32\n-1.0\n" + np.ascontiguousarray(pixels[::-1]).astype("<f4").tobytes())
    maps = [pfm]
    try:
        import OpenImageIO as oiio
        hdr = str(tmp_path / "map.hdr")
        out = oiio.ImageOutput.create(hdr)
        out.open(hdr, oiio.ImageSpec(64, 32, 3, oiio.FLOAT))
        out.write_image(pixels)
        out.close()
        maps.append(hdr)
    except ImportError:
        pass
    for path in maps:
        assert np.array_equal(read_image(path), pure_read_image(path)), path
    # The draws: equal to the bit (test_torch_dataset holds the streams equal too).
    for i in (0, 1, 999, 10**9):
        for rotation in contract.SAMPLED_ROTATIONS:
            assert sampling.draw(i, 4, 5, rotation, 1.0) == sampling.pure_draw(i, 4, 5, rotation,
                                                                                1.0)


def test_the_package_is_laid_out_as_users_import_it():
    code = """
import warnings
from adaptive_cpca.torch import TorchRelighter, RelightDataset, Environment
from adaptive_cpca.torch import relighter, model, lighting, domain, dataset
from adaptive_cpca import io, sampling, _core
import adaptive_cpca.torch as t
assert t.TorchRelighter is relighter.TorchRelighter and t.RelightDataset is dataset.RelightDataset
old = {"torch_lighting": lighting, "torch_model": model, "torch_domain": domain,
       "torch_dataset": dataset, "image_reading": io}
for name, new in old.items():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        module = __import__("adaptive_cpca." + name, fromlist=["x"])
    assert module is new, (name, module)
    assert [w.category for w in caught] == [DeprecationWarning], (name, caught)
    assert "adaptive_cpca." + name in str(caught[0].message), caught[0].message
print("ok")
"""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env=os.environ)
    assert done.returncode == 0 and done.stdout.strip() == "ok", done.stderr


def test_no_python_or_binding_file_is_over_450_lines():
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    long = []
    for folder in ("python", "scripts"):
        for where, _, files in os.walk(os.path.join(root, folder)):
            for name in files:
                if name.endswith((".py", ".cpp", ".h")):
                    with open(os.path.join(where, name)) as f:
                        lines = sum(1 for _ in f)
                    if lines > 450:
                        long.append((os.path.relpath(os.path.join(where, name), root), lines))
    assert not long, long
