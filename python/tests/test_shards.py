"""Sharded batches (--shard-size): a 1,000-frame batch killed at random
points leaves only whole tars, every sample equal to the unsharded batch's
files; a rerun finishes it, byte for byte as one run makes it; Python's
tarfile reads every shard and the loader example reads shards as it reads
directories."""

import json
import os
import random
import signal
import subprocess
import sys
import tarfile
import time

import numpy as np

CLI = os.environ["ACPCA_CLI"]
TRANSPORT = os.path.join(os.environ["ACPCA_FIXTURE_DIR"], "small-plant.h5")
# 2 maps x 500 yaws: 1,000 frames of 40x40, shards of 64 (the last of 40).
BATCH = [TRANSPORT, "--env", "sky", "--env", "constant:1", "--rotate", "0:360:0.72",
         "--aov", "mask,shading", "--quiet"]


def run(out, *extra):
    subprocess.run([CLI, "relight", *BATCH, *extra, "--out", str(out)], check=True)


def shards_of(directory):
    name = os.path.basename(directory)
    return sorted(f for f in os.listdir(directory)
                  if f.startswith(name + "-") and f.endswith(".tar"))


def check_whole_shards(directory, plain, manifest):
    """Every tar in place is whole: its samples are its frames' files, equal
    to the unsharded batch's, with the view's labels once."""
    for shard in shards_of(str(directory)):
        first = int(shard[-10:-4]) * 64
        with tarfile.open(os.path.join(directory, shard)) as tar:
            names = tar.getnames()
            count = min(64, 1000 - first)
            assert names[:2] == ["labels.exr", "labels_mask.png"], shard
            assert len(names) == 2 + 3 * count, shard
            for k in range(first, first + count):
                key = f"{k:05d}"
                frame, shading = manifest[k]["outputs"][0], manifest[k]["shading"][0]
                assert tar.extractfile(key + ".exr").read() == (plain / frame).read_bytes()
                assert (tar.extractfile(key + ".shading.exr").read()
                        == (plain / shading).read_bytes())
                line = json.loads(tar.extractfile(key + ".json").read())
                assert line["frame"] == k and line["yaw"] == manifest[k]["yaw"]
                assert line["sh9"] == manifest[k]["sh9"]
            for member in tar.getmembers():
                assert (member.mtime, member.uid, member.gid, member.mode) == (0, 0, 0, 0o644)


def test_a_killed_sharded_batch_leaves_whole_tars_and_a_rerun_finishes_it(tmp_path):
    plain = tmp_path / "plain"
    run(plain)
    manifest = [json.loads(line) for line in (plain / "manifest.jsonl").read_text().splitlines()]
    assert len(manifest) == 1000
    once = tmp_path / "once" / "train"
    once.parent.mkdir()
    start = time.monotonic()
    run(once, "--shard-size", "64")
    seconds = time.monotonic() - start
    assert len(shards_of(str(once))) == 16
    check_whole_shards(once, plain, manifest)

    killed = tmp_path / "killed" / "train"
    rng = random.Random(46)
    for attempt in range(4):
        process = subprocess.Popen([CLI, "relight", *BATCH, "--shard-size", "64",
                                    "--out", str(killed)])
        time.sleep(rng.uniform(0.05, 1.2) * seconds)
        process.send_signal(signal.SIGKILL)
        process.wait()
        if killed.exists():
            check_whole_shards(killed, plain, manifest)
    run(killed, "--shard-size", "64")
    for name in os.listdir(once):
        assert (killed / name).read_bytes() == (once / name).read_bytes(), name
    assert not [f for f in os.listdir(killed) if f.endswith(".partial")]
    index = json.loads((killed / "train-shards.json").read_text())
    assert index["samples"] == 1000 and len(index["shards"]) == 16
    assert [s["samples"] for s in index["shards"]] == [64] * 15 + [40]


def test_the_loader_reads_shards_as_it_reads_directories(tmp_path):
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "examples"))
    try:
        import load_dataset
    finally:
        sys.path.pop(0)
    batch = [TRANSPORT, "--env", "sky", "--rotate", "0:360:45", "--aov", "mask,shading",
             "--quiet"]
    subprocess.run([CLI, "relight", *batch, "--out", str(tmp_path / "files")], check=True)
    subprocess.run([CLI, "relight", *batch, "--shard-size", "3", "--out", str(tmp_path / "tars")],
                   check=True)
    from_files = list(load_dataset.batches(str(tmp_path / "files"), 5))
    from_tars = list(load_dataset.batches(str(tmp_path / "tars"), 5))
    assert len(from_tars) == 2
    for (images, labels), (tar_images, tar_labels) in zip(from_files, from_tars):
        assert np.array_equal(images, tar_images)
        assert np.array_equal(labels["shading"], tar_labels["shading"])
        assert np.array_equal(labels["sh9"], tar_labels["sh9"])
    samples = list(load_dataset.shard_samples(str(tmp_path / "tars")))
    keys = [key for key, _ in samples if key.isdigit()]
    assert keys == [f"{k:05d}" for k in range(8)]
    assert [key for key, _ in samples[:2]] == ["labels", "labels_mask"]
    assert set(samples[2][1]) == {"exr", "shading.exr", "json"}


def refused(args, needle):
    r = subprocess.run([CLI, "relight", *map(str, args)], capture_output=True, text=True)
    assert r.returncode != 0 and needle in r.stderr, r.stderr


def test_bad_shard_requests_are_refused_naming_the_flag_or_file(tmp_path):
    out = tmp_path / "set"
    batch = [TRANSPORT, "--env", "sky", "--rotate", "0:360:90"]
    for size in ("0", "-2"):
        refused([*batch, "--shard-size", size, "--out", out], f"--shard-size '{size}': must be")
    refused([TRANSPORT, "--env", "sky", "--shard-size", 4, "--out", tmp_path / "one.exr"],
            "shards a batch's frames")
    assert not out.exists() and not (tmp_path / "one.exr").exists()
    # A directory with another batch's shards: refused, nothing in it changed.
    subprocess.run([CLI, "relight", *batch, "--shard-size", "2", "--quiet", "--out", str(out)],
                   check=True)
    before = {f: (out / f).read_bytes() for f in os.listdir(out)}
    refused([*batch, "--out", out], "holds another dataset")
    refused([*batch, "--shard-size", 3, "--out", out], "holds another dataset (shard_size")
    (out / "dataset.json").unlink()
    refused([*batch, "--shard-size", 2, "--out", out],
            f"{out}/set-000000.tar: a shard no dataset.json in its directory claims")
    del before["dataset.json"]
    assert {f: (out / f).read_bytes() for f in os.listdir(out)} == before
