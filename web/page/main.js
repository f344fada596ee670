// The page: loads the export, relights it on the GPU as the view changes, and
// keeps the view in the URL. Drag turns the map (yaw; pitch with Shift), keys
// do the same, a .hdr dropped on the page becomes a map in the picker.
import { GpuRelighter } from "./gpu_relighter.js";
import { readHdr } from "./hdr.js";
import { CubeLattice, rotationMatrix } from "./lattice.js";
import { checkLatLongSize, LatLongMap } from "./maps.js";
import { loadMap, loadSite } from "./site.js";
import { cliArguments, kBackgrounds, readView, viewQuery } from "./view_state.js";

/** Degrees the map turns per CSS pixel dragged. */
const kDegreesPerPixel = 0.5;
const $ = (id) => document.getElementById(id);

const page = {
  degreesPerPixel: kDegreesPerPixel,
  frameTimes: [],
  messages: [],
};
window.acpcaPage = page;

function say(text, kind = "note") {
  page.messages.push({ text, kind });
  const box = $("message");
  const line = document.createElement("p");
  line.className = kind;
  line.textContent = text;
  box.append(line);
  box.hidden = false;
}

class Page {
  constructor(site, relighter, view) {
    this.site = site;
    this.relighter = relighter;
    this.view = view;
    this.lattice = new CubeLattice(site.manifest.cubemap);
    this.entries = new Map(site.maps.map((e) => [e.name, e]));
    this.maps = new Map();
    this.lightingKey = "";
    this.pending = false;
  }

  async map(name) {
    if (!this.maps.has(name))
      this.maps.set(name, await loadMap(this.entries.get(name), this.site.manifest.lighting));
    return this.maps.get(name);
  }

  /** Draws the current view now. */
  async draw() {
    const v = this.view;
    const map = await this.map(v.map);
    const R = rotationMatrix(v.yaw, v.pitch, 0);
    const key = `${v.map}|${v.yaw}|${v.pitch}`;
    if (key !== this.lightingKey) {
      this.relighter.setLighting(map.integrate(this.lattice, R));
      if (this.relighter.map !== map) this.relighter.setMap(map);
      this.lightingKey = key;
    }
    this.relighter.render(this.renderView());
    page.frameTimes.push(performance.now());
    if (page.frameTimes.length > 1000) page.frameTimes.splice(0, 500);
    this.showView();
  }

  renderView() {
    const v = this.view;
    return { R: rotationMatrix(v.yaw, v.pitch, 0), exposure: v.exposure, tone: v.tone, background: v.background };
  }

  /** Asks for a frame at the next animation frame (one however many changes). */
  schedule() {
    if (this.pending) return;
    this.pending = true;
    requestAnimationFrame(() => {
      this.pending = false;
      this.draw().catch((e) => say(e.message, "error"));
    });
  }

  change(values) {
    Object.assign(this.view, values);
    this.view.yaw = wrapDegrees(this.view.yaw);
    this.view.pitch = Math.max(-90, Math.min(90, this.view.pitch));
    this.schedule();
  }

  showView() {
    const v = this.view, names = [...this.entries.keys()];
    history.replaceState(null, "", `${location.pathname}${viewQuery(v, names)}`);
    if (!v.ui) return;
    $("yaw").textContent = v.yaw.toFixed(1);
    $("pitch").textContent = v.pitch.toFixed(1);
    $("exposure").value = String(v.exposure);
    $("exposure-value").textContent = v.exposure.toFixed(1);
    $("map").value = v.map;
    $("background").value = v.background;
    $("cli").textContent = `adaptive-cpca relight ${this.site.manifest.source} --env ${this.entries.get(v.map).spec ?? v.map} ` +
      `${cliArguments(v)} --sun off --format png`.replace(/ +/g, " ");
  }

  addMap(name, map) {
    let unique = name, k = 2;
    while (this.entries.has(unique)) unique = `${name}-${k++}`;
    this.entries.set(unique, { name: unique, spec: `${name}.hdr` });
    this.maps.set(unique, map);
    const option = document.createElement("option");
    option.value = option.textContent = unique;
    $("map").append(option);
    this.change({ map: unique });
    return unique;
  }
}

function wrapDegrees(d) {
  const w = ((d + 180) % 360 + 360) % 360 - 180;
  return w === -180 ? 180 : w;
}

async function readDroppedMap(p, file) {
  if (!/\.hdr$/i.test(file.name)) throw new Error(`${file.name}: drop a Radiance .hdr map`);
  const { width, height, rgb } = readHdr(new Uint8Array(await file.arrayBuffer()), file.name);
  const note = checkLatLongSize(file.name, width, height, p.site.manifest.lighting);
  if (note) say(note);
  const name = file.name.replace(/\.hdr$/i, "");
  return p.addMap(name, new LatLongMap(name, width, height, rgb, p.site.manifest.lighting));
}

function wire(p) {
  const canvas = $("canvas");
  let drag = null;
  canvas.addEventListener("pointerdown", (e) => {
    drag = { x: e.clientX, y: e.clientY, yaw: p.view.yaw, pitch: p.view.pitch };
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener("pointermove", (e) => {
    if (!drag) return;
    const turn = (e.clientX - drag.x) * kDegreesPerPixel;
    if (e.shiftKey) p.change({ pitch: drag.pitch - (e.clientY - drag.y) * kDegreesPerPixel });
    else p.change({ yaw: drag.yaw + turn });
  });
  const end = () => { drag = null; };
  canvas.addEventListener("pointerup", end);
  canvas.addEventListener("pointercancel", end);
  window.addEventListener("keydown", (e) => {
    if (e.target instanceof HTMLInputElement || e.target instanceof HTMLSelectElement) return;
    const step = e.shiftKey ? 1 : 5, v = p.view;
    const names = [...p.entries.keys()];
    const actions = {
      ArrowLeft: () => p.change({ yaw: v.yaw - step }),
      ArrowRight: () => p.change({ yaw: v.yaw + step }),
      ArrowUp: () => p.change({ pitch: v.pitch + step }),
      ArrowDown: () => p.change({ pitch: v.pitch - step }),
      "+": () => p.change({ exposure: v.exposure + 0.5 }),
      "=": () => p.change({ exposure: v.exposure + 0.5 }),
      "-": () => p.change({ exposure: v.exposure - 0.5 }),
      b: () => p.change({ background: kBackgrounds[(kBackgrounds.indexOf(v.background) + 1) % 3] }),
      m: () => p.change({ map: names[(names.indexOf(v.map) + 1) % names.length] }),
      r: () => p.change({ yaw: 0, pitch: 0, exposure: 0 }),
    };
    if (actions[e.key]) {
      actions[e.key]();
      e.preventDefault();
    }
  });
  $("exposure").addEventListener("input", (e) => p.change({ exposure: Number(e.target.value) }));
  $("map").addEventListener("change", (e) => p.change({ map: e.target.value }));
  $("background").addEventListener("change", (e) => p.change({ background: e.target.value }));
  $("copy").addEventListener("click", () => {
    const text = $("cli").textContent;
    navigator.clipboard?.writeText(text).then(() => say("copied"), () => say(`copy this: ${text}`));
  });
  const open = (file) => readDroppedMap(p, file).catch((e) => say(e.message, "error"));
  $("file").addEventListener("change", (e) => { if (e.target.files[0]) open(e.target.files[0]); });
  window.addEventListener("dragover", (e) => e.preventDefault());
  window.addEventListener("drop", (e) => {
    e.preventDefault();
    if (e.dataTransfer.files[0]) open(e.dataTransfer.files[0]);
  });
}

function fillControls(p) {
  for (const name of p.entries.keys()) {
    const option = document.createElement("option");
    option.value = option.textContent = name;
    $("map").append(option);
  }
  for (const b of kBackgrounds) {
    const option = document.createElement("option");
    option.value = option.textContent = b;
    $("background").append(option);
  }
}

/** Test and automation hooks: set a view and wait for its frame; read it back. */
function hooks(p) {
  const base64 = (bytes) => {
    let text = "";
    for (let i = 0; i < bytes.length; i += 0x8000) text += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
    return btoa(text);
  };
  page.setView = async (values) => {
    Object.assign(p.view, values);
    await p.draw();
  };
  page.view = () => ({ ...p.view });
  page.readPixels8 = () => base64(p.relighter.readPixels8());
  page.readPixelsFloat = () => {
    const f = p.relighter.readPixelsFloat(p.renderView());
    p.relighter.render(p.renderView());
    return base64(new Uint8Array(f.buffer));
  };
  page.addMap = (name, width, height, rgb) => p.addMap(name, new LatLongMap(name, width, height, rgb, p.site.manifest.lighting));
}

async function start() {
  let site;
  try {
    site = await loadSite();
  } catch (e) {
    say(e.message, "error");
    return;
  }
  document.title = site.manifest.title;
  $("title").textContent = site.manifest.title;
  const { view, problems } = readView(location.search, site.maps.map((m) => m.name));
  problems.forEach((text) => say(`${text}: the default is shown`, "error"));
  if (!view.ui) document.body.classList.add("bare");
  let relighter;
  try {
    relighter = new GpuRelighter($("canvas"), site);
  } catch (e) {
    say(e.message, "error");
    return;
  }
  const p = new Page(site, relighter, view);
  fillControls(p);
  wire(p);
  hooks(p);
  await p.draw();
}

page.ready = start().catch((e) => say(e.message, "error"));
