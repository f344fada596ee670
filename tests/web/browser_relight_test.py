"""The web page in a real browser against the CLI (ctest -R 'Web|Browser').

  prepare WORK CLI        the 128x128 plant, its adaptive-quad model (f32) and an
                          adaptive-binary i8/f16 model, two maps, exported sites
  pixels WORK CLI SITE    the canvas against `relight --format png` (one code on
                          99.9% of pixels) and a float read-back against
                          `--format npy` (1e-3 relative L2): sky, a Blender world
                          map and a dropped .hdr, at yaw 0 and 137
  interaction WORK CLI    a drag of 90 degrees, exposure +1, the backgrounds, the
                          view in the URL, ui=0, keys; no console problem and no
                          request outside the site
  errors WORK CLI         a corrupt model, a missing file, a non-2:1 .hdr
  timing WORK CLI SITE    frames per second while dragging, measured in the page
"""

import os
import shutil
import subprocess
import sys
import time

import numpy as np
import OpenImageIO as oiio

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from chromium_pipe import Chromium, StaticServer  # noqa: E402

WORLD = "/usr/share/blender/datafiles/studiolights/world"
MAP = f"{WORLD}/courtyard.exr"      # a Blender world map, listed by the export
DROPPED = f"{WORLD}/forest.exr"     # written as .hdr and dropped on the page
# The plant at a quarter of its default pixels: its models compress in 45 s
# on two cores against 150 s at 256x256, over the full 6x32x32 lattice.
SIZE = 128
failures = []


def check(ok, text):
    print(("ok    " if ok else "FAIL  ") + text, flush=True)
    if not ok:
        failures.append(text)


def run(cli, *args):
    subprocess.run([cli, *args, "--quiet"], check=True)


def prepare(work, cli):
    """Made again whenever the CLI is newer than what it made, or made at another size."""
    shutil.rmtree(f"{work}/cli", ignore_errors=True)
    plant = f"{work}/plant.h5"
    stamp = f"{work}/size"
    made_for = ""
    if os.path.exists(stamp):
        with open(stamp) as f:
            made_for = f.read()
    if os.path.exists(plant) and (os.path.getmtime(plant) < os.path.getmtime(cli)
                                  or made_for != f"{SIZE}x{SIZE}"):
        shutil.rmtree(work)
    os.makedirs(work, exist_ok=True)
    if not os.path.exists(plant):
        run(cli, "precompute", "--scene", "plant", "--size", f"{SIZE}x{SIZE}", "--out", plant)
        with open(stamp, "w") as f:
            f.write(f"{SIZE}x{SIZE}")
    models = {"quad": ["--method", "adaptive-quad"],
              "binary": ["--method", "adaptive-binary", "--coeffs", "i8", "--bases", "f16"]}
    for name, flags in models.items():
        if not os.path.exists(f"{work}/{name}.h5"):
            run(cli, "compress", plant, *flags, "--out", f"{work}/{name}.h5")
        shutil.rmtree(f"{work}/site-{name}", ignore_errors=True)
        run(cli, "web", f"{work}/{name}.h5", "--env", "sky", "--env", MAP, "--out", f"{work}/site-{name}")
    subprocess.run(["oiiotool", DROPPED, "-o", f"{work}/forest.hdr"], check=True)
    subprocess.run(["oiiotool", DROPPED, "--resize", "300x200", "-o", f"{work}/wide.hdr"], check=True)


class Page:
    def __init__(self, site, query="", flags=()):
        self.server = StaticServer(site)
        self.browser = Chromium(flags=flags)
        self.browser.navigate(f"{self.server.origin}/index.html{query}")
        self.browser.evaluate("window.acpcaPage.ready")

    def js(self, expression):
        return self.browser.evaluate(expression)

    def size(self):
        return self.js("[document.getElementById('canvas').width, document.getElementById('canvas').height]")

    def pixels8(self):
        w, h = self.size()
        return np.frombuffer(self.browser.bytes_of("window.acpcaPage.readPixels8()"), np.uint8).reshape(h, w, 4)

    def pixels_float(self):
        w, h = self.size()
        return np.frombuffer(self.browser.bytes_of("window.acpcaPage.readPixelsFloat()"),
                             np.float32).reshape(h, w, 4)

    def set_view(self, **view):
        args = ", ".join(f"{k}: {v!r}" if isinstance(v, str) else f"{k}: {v}" for k, v in view.items())
        self.js(f"window.acpcaPage.setView({{{args}}})")

    def messages(self):
        return self.js("window.acpcaPage.messages")

    def drop(self, path):
        box = self.js("(() => { const r = document.getElementById('canvas').getBoundingClientRect();"
                      " return [r.x + r.width / 2, r.y + r.height / 2]; })()")
        count = len(self.messages())
        before = self.js("window.acpcaPage.view().map")
        self.browser.drop_file(path, *box)
        deadline = time.time() + 60
        while time.time() < deadline:
            if self.js("window.acpcaPage.view().map") != before or len(self.messages()) > count:
                break
            time.sleep(0.1)
        time.sleep(0.5)  # the dropped map's first frame
        self.js("new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)))")

    def close(self):
        self.browser.close()
        self.server.close()


def cli_frame(cli, work, model, env, stem, *flags):
    """relight's PNG (8-bit) and npy (float, before exposure) of one view."""
    out = f"{work}/cli/{stem}"
    os.makedirs(f"{work}/cli", exist_ok=True)
    if not os.path.exists(f"{out}.png"):
        run(cli, "relight", model, "--env", env, "--sun", "off", *flags, "--format", "png", "--out", f"{out}.png")
    # The file's own bytes: OpenImageIO would multiply an RGBA PNG's colour by its alpha.
    config = oiio.ImageSpec()
    config.attribute("oiio:UnassociatedAlpha", 1)
    png = oiio.ImageBuf(f"{out}.png", 0, 0, config).get_pixels(oiio.UINT8)
    flags_without_exposure = [f for i, f in enumerate(flags)
                              if f != "--exposure" and (i == 0 or flags[i - 1] != "--exposure")]
    if not os.path.exists(f"{out}.npy"):
        run(cli, "relight", model, "--env", env, "--sun", "off", *flags_without_exposure,
            "--format", "npy", "--out", f"{out}.npy")
    return png, np.load(f"{out}.npy")


def compare8(page_rgba, png, what):
    channels = png.shape[2]
    diff = np.abs(page_rgba[..., :channels].astype(int) - png.astype(int)).max(axis=2)
    within = (diff <= 1).mean()
    check(within >= 0.999, f"{what}: {100 * within:.3f}% of pixels within one code "
          f"({100 * (diff == 0).mean():.3f}% equal, largest {diff.max()})")


def compare_float(page_rgba, npy, what):
    channels = npy.shape[2] if npy.ndim == 3 else 1
    got = page_rgba[..., :channels]
    error = np.linalg.norm(got - npy) / np.linalg.norm(npy)
    check(error <= 1e-3, f"{what}: float read-back {error:.2e} relative L2")


def pixels(work, cli, name):
    model = f"{work}/{name}.h5"
    page = Page(f"{work}/site-{name}")
    try:
        page.drop(f"{work}/forest.hdr")
        check(page.js("window.acpcaPage.view().map") == "forest", f"{name}: the dropped forest.hdr is the map")
        for env, map_name in (("sky", "sky"), (MAP, "courtyard"), (f"{work}/forest.hdr", "forest")):
            for yaw in (0, 137):
                page.set_view(map=map_name, yaw=yaw, pitch=0, exposure=0, background="env")
                png, npy = cli_frame(cli, work, model, env, f"{name}-{map_name}-y{yaw}", "--rotate", str(yaw))
                what = f"{name} under {map_name} at yaw {yaw}"
                compare8(page.pixels8(), png, what)
                compare_float(page.pixels_float(), npy, what)
        problems = page.browser.console_problems()
        check(not problems, f"{name}: no console error or warning ({problems[:3]})")
    finally:
        page.close()


def interaction(work, cli):
    model = f"{work}/quad.h5"
    site = f"{work}/site-quad"
    page = Page(site)
    try:
        w, h = page.size()
        box = page.js("(() => { const r = document.getElementById('canvas').getBoundingClientRect();"
                      " return [r.x, r.y]; })()")
        per_pixel = page.js("window.acpcaPage.degreesPerPixel")
        x0, y0 = box[0] + 20, box[1] + h / 2
        steps = 10
        page.browser.mouse("mousePressed", x0, y0, buttons=1)
        for k in range(1, steps + 1):
            page.browser.mouse("mouseMoved", x0 + k * 90 / per_pixel / steps, y0, buttons=1)
        page.browser.mouse("mouseReleased", x0 + 90 / per_pixel, y0)
        page.js("new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)))")
        view = page.js("window.acpcaPage.view()")
        check(abs(view["yaw"] - 90) < 1e-9, f"a drag of {90 / per_pixel:.0f} px turns the yaw to {view['yaw']}")
        png, _ = cli_frame(cli, work, model, "sky", "quad-sky-y90", "--rotate", "90")
        compare8(page.pixels8(), png, "a drag of 90 degrees against --rotate 90")
        check("yaw=90" in page.js("location.search"), f"the URL keeps the view ({page.js('location.search')})")
        page.browser.page("Input.dispatchKeyEvent", type="keyDown", key="+", text="+")
        page.browser.page("Input.dispatchKeyEvent", type="keyUp", key="+")
        page.browser.page("Input.dispatchKeyEvent", type="keyDown", key="=", text="=")
        page.browser.page("Input.dispatchKeyEvent", type="keyUp", key="=")
        page.js("new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)))")
        check(page.js("window.acpcaPage.view().exposure") == 1, "two presses of + raise the exposure to 1")
        png, _ = cli_frame(cli, work, model, "sky", "quad-sky-y90-e1", "--rotate", "90", "--exposure", "1")
        compare8(page.pixels8(), png, "exposure +1 against --exposure 1")
        cli_text = page.js("document.getElementById('cli').textContent")
        check("--rotate 90" in cli_text and "--exposure 1" in cli_text, f"the CLI's arguments shown: {cli_text}")
        page.set_view(yaw=137, pitch=20, exposure=0, background="env")
        png, _ = cli_frame(cli, work, model, "sky", "quad-sky-y137-p20", "--rotate", "137,20,0")
        compare8(page.pixels8(), png, "yaw 137 and pitch 20 against --rotate 137,20,0")
        page.set_view(pitch=0)
        for background in ("black", "alpha"):
            page.set_view(yaw=137, exposure=0, background=background)
            png, _ = cli_frame(cli, work, model, "sky", f"quad-sky-y137-{background}", "--rotate", "137",
                               "--background", background)
            compare8(page.pixels8(), png, f"background {background}")
        problems = page.browser.console_problems()
        check(not problems, f"no console error or warning ({problems[:3]})")
        outside = [u for u in page.browser.requested_urls() if not u.startswith(page.server.origin + "/")]
        check(not outside, f"no request outside the site ({outside[:3]})")
        failed = [r for r in page.server.requests if r[1] != 200]
        check(not failed, f"every request the site answered ({failed[:3]})")
        page.set_view(yaw=137, exposure=0, background="env")
        page.browser.screenshot(f"{work}/web-page.png", {"x": 0, "y": 0, "width": 860, "height": 520})
    finally:
        page.close()
    # A view from the URL, controls hidden: the canvas alone at the top left.
    page = Page(site, "?map=courtyard&yaw=137&exposure=0.5&background=black&ui=0")
    try:
        rect = page.js("(() => { const r = document.getElementById('canvas').getBoundingClientRect();"
                       " return [r.x, r.y, r.width, r.height]; })()")
        check(rect == [0, 0, SIZE, SIZE], f"ui=0 shows the canvas alone at the top left ({rect})")
        check(page.js("getComputedStyle(document.getElementById('controls')).display") == "none",
              "ui=0 hides the controls")
        png, _ = cli_frame(cli, work, model, MAP, "quad-courtyard-y137-e05-black", "--rotate", "137",
                           "--exposure", "0.5", "--background", "black")
        compare8(page.pixels8(), png, "the URL's view against the CLI")
        page.browser.screenshot(f"{work}/web-bare.png", {"x": 0, "y": 0, "width": SIZE, "height": SIZE})
    finally:
        page.close()


def errors(work, cli):
    site = f"{work}/site-errors"
    shutil.rmtree(site, ignore_errors=True)
    shutil.copytree(f"{work}/site-quad", site)
    page = Page(site, flags=("--disable-webgl2",))
    try:
        said = " ".join(m["text"] for m in page.messages())
        check("no WebGL2" in said, f"a browser without WebGL2: {said}")
    finally:
        page.close()
    page = Page(site)
    try:
        page.drop(f"{work}/wide.hdr")
        said = " ".join(m["text"] for m in page.messages())
        check("not a lat-long map" in said and "wide.hdr" in said, f"a 300x200 .hdr: {said}")
        os.remove(f"{site}/maps/map-1.bin")
        page.js("(() => { const s = document.getElementById('map'); s.value = 'courtyard';"
                " s.dispatchEvent(new Event('change')); })()")
        time.sleep(1)
        said = " ".join(m["text"] for m in page.messages())
        check("maps/map-1.bin could not be loaded" in said, f"a missing map file: {said}")
    finally:
        page.close()
    with open(f"{site}/model.bin", "r+b") as f:
        f.truncate(1000)
    page = Page(site)
    try:
        said = " ".join(m["text"] for m in page.messages())
        check("model.bin" in said and "web again" in said, f"a model.bin cut short: {said}")
    finally:
        page.close()
    os.remove(f"{site}/model.json")
    page = Page(site)
    try:
        said = " ".join(m["text"] for m in page.messages())
        check("model.json could not be loaded" in said, f"a missing model.json: {said}")
        problems = [p for p in page.browser.console_problems() if "model.json" not in p and "404" not in p]
        check(not problems, f"nothing else in the console ({problems[:3]})")
    finally:
        page.close()


def timing(work, cli, name):
    page = Page(f"{work}/site-{name}")
    try:
        page.js("window.acpcaPage.frameTimes.length = 0")
        box = page.js("(() => { const r = document.getElementById('canvas').getBoundingClientRect();"
                      " return [r.x + 10, r.y + r.height / 2]; })()")
        page.browser.mouse("mousePressed", *box, buttons=1)
        start = time.time()
        k = 0
        while time.time() - start < 5:
            k += 1
            page.browser.mouse("mouseMoved", box[0] + (k % 200), box[1], buttons=1)
            page.js("new Promise((done) => requestAnimationFrame(done))")
        page.browser.mouse("mouseReleased", *box)
        times = page.js("window.acpcaPage.frameTimes")
        fps = (len(times) - 1) / ((times[-1] - times[0]) / 1000) if len(times) > 1 else 0
        renderer = page.js("(() => { const gl = document.createElement('canvas').getContext('webgl2');"
                           " const i = gl.getExtension('WEBGL_debug_renderer_info');"
                           " return i ? gl.getParameter(i.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER); })()")
        w, h = page.size()
        print(f"timing: {name} model {w}x{h}: {fps:.1f} frames/s while dragging "
              f"({len(times)} frames), drawn by {renderer}", flush=True)
        check(fps > 0, "frames were drawn while dragging")
    finally:
        page.close()


def main():
    command, work, cli = sys.argv[1], os.path.abspath(sys.argv[2]), os.path.abspath(sys.argv[3])
    if command == "prepare":
        prepare(work, cli)
    elif command == "pixels":
        pixels(work, cli, sys.argv[4])
    elif command == "interaction":
        interaction(work, cli)
    elif command == "errors":
        errors(work, cli)
    elif command == "timing":
        timing(work, cli, sys.argv[4])
    if failures:
        print(f"{len(failures)} check(s) failed", flush=True)
        sys.exit(1)


if __name__ == "__main__":
    main()
