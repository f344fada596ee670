// Maps integrated onto the lattice in the page, as the CLI integrates them
// (docs/lighting.md, "Integrating a map"; lighting/): radiance x exact solid
// angle per texel, RGB, in doubles, under R = Rz(roll) Rx(pitch) Ry(yaw).
// - constant: radiance x each texel's solid angle;
// - sun: the disc split into rings of equal solid angle, each sample adding
//   its share of the energy to the texel holding it;
// - sky: its smooth part on sub x sub exact-area cells per texel, and its sun;
// - lat-long maps: each pixel split into sub-cells at most 1/8 of a texel
//   across, each adding radiance x its exact solid angle to the texel that
//   holds its rotated centre.
// The numbers (the sky's colours, ring counts, sub-cells) come from the
// export's model.json, written from lighting/builtin_maps.h.
import { directionFromAngles, faceDirection, rectangleSolidAngle } from "./lattice.js";

const PI = Math.PI;

function parseNumbers(text, spec) {
  return text.split(",").map((part) => {
    const v = Number(part);
    if (part.trim() === "" || !Number.isFinite(v))
      throw new Error(`environment ${spec}: ${part} is not a finite number`);
    return v;
  });
}

/** R^T d for a row-major R. */
function inverseTurn(R, x, y, z) {
  return [R[0] * x + R[3] * y + R[6] * z, R[1] * x + R[4] * y + R[7] * z,
    R[2] * x + R[5] * y + R[8] * z];
}

export class ConstantMap {
  constructor(name, radiance) {
    this.name = name;
    this.radiance = radiance;
  }
  integrate(lattice) {
    const out = new Float64Array(3 * lattice.size);
    for (let j = 0; j < lattice.size; ++j)
      for (let c = 0; c < 3; ++c) out[3 * j + c] = this.radiance[c] * lattice.solidAngles[j];
    return out;
  }
}

export class SunMap {
  /** theta, phi, size in degrees; radiance RGB. */
  constructor(name, theta, phi, size, radiance, constants) {
    this.name = name;
    this.theta = theta;
    this.phi = phi;
    this.size = size;
    this.radiance = radiance;
    this.constants = constants;
    this.centre = directionFromAngles(theta * PI / 180, phi * PI / 180);
    this.cosHalf = Math.cos(0.5 * size * PI / 180);
  }
  /** Adds the disc's energy onto `out` under R. */
  addTo(lattice, R, out) {
    const k = this.constants;
    const texelAngle = 0.5 * PI / lattice.resolution;
    const rings = Math.min(k.max_disc_rings, Math.max(k.min_disc_rings,
      Math.ceil(k.disc_rings_per_texel * (this.size * PI / 180) / texelAngle)));
    const segments = 2 * rings;
    const c = this.centre;
    const axis = [0, 1, 2].map((i) => R[3 * i] * c[0] + R[3 * i + 1] * c[1] + R[3 * i + 2] * c[2]);
    const helper = Math.abs(axis[1]) < 0.9 ? [0, 1, 0] : [1, 0, 0];
    const u = normalize(cross(axis, helper)), v = cross(axis, u);
    const energy = 2 * PI * (1 - this.cosHalf) / (rings * segments);
    const share = this.radiance.map((r) => r * energy);
    for (let r = 0; r < rings; ++r) {
      const cosT = 1 - (r + 0.5) / rings * (1 - this.cosHalf);
      const sinT = Math.sqrt(Math.max(0, 1 - cosT * cosT));
      for (let s = 0; s < segments; ++s) {
        const phi = 2 * PI * (s + 0.5 * (r & 1)) / segments;
        const cp = Math.cos(phi), sp = Math.sin(phi);
        const j = lattice.texelOf(cosT * axis[0] + sinT * (cp * u[0] + sp * v[0]),
          cosT * axis[1] + sinT * (cp * u[1] + sp * v[1]),
          cosT * axis[2] + sinT * (cp * u[2] + sp * v[2]));
        for (let ch = 0; ch < 3; ++ch) out[3 * j + ch] += share[ch];
      }
    }
  }
  integrate(lattice, R) {
    const out = new Float64Array(3 * lattice.size);
    this.addTo(lattice, R, out);
    return out;
  }
}

function cross(a, b) {
  return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
}
function normalize(a) {
  const n = Math.hypot(a[0], a[1], a[2]);
  return [a[0] / n, a[1] / n, a[2] / n];
}

export class SkyMap {
  constructor(constants) {
    this.name = "sky";
    this.k = constants;
    const s = constants.sky_sun;
    this.sun = new SunMap("sky", s.theta, s.phi, s.size, s.radiance, constants);
    this.cells = new Map();
  }
  skyRadiance(x, y, z) {
    const k = this.k;
    if (y < 0) return k.sky_ground;
    const t = Math.pow(1 - y, k.sky_horizon_power);
    const c = this.sun.centre;
    const glow = k.sky_glow_strength * Math.exp(-k.sky_glow_sharpness *
      (1 - (x * c[0] + y * c[1] + z * c[2])));
    return [0, 1, 2].map((i) =>
      (1 - t) * k.sky_zenith[i] + t * k.sky_horizon[i] + glow * k.sky_glow_colour[i]);
  }
  /** Each texel's sub x sub cells: unit centre and exact solid angle. */
  cellsOf(lattice) {
    let cells = this.cells.get(lattice.resolution);
    if (cells) return cells;
    const sub = this.k.sky_sub_cells, step = 2 / lattice.resolution, cell = step / sub;
    cells = new Float64Array(lattice.size * sub * sub * 4);
    let at = 0;
    for (let j = 0; j < lattice.size; ++j) {
      const { face, row, col } = lattice.texelCoord(j);
      for (let a = 0; a < sub; ++a)
        for (let b = 0; b < sub; ++b) {
          const s0 = -1 + col * step + b * cell, t0 = -1 + row * step + a * cell;
          const w = normalize(faceDirection(face, s0 + 0.5 * cell, t0 + 0.5 * cell));
          cells.set([w[0], w[1], w[2], rectangleSolidAngle(s0, t0, s0 + cell, t0 + cell)], at);
          at += 4;
        }
    }
    this.cells.set(lattice.resolution, cells);
    return cells;
  }
  integrate(lattice, R) {
    const out = new Float64Array(3 * lattice.size);
    const cells = this.cellsOf(lattice), perTexel = this.k.sky_sub_cells ** 2;
    for (let j = 0; j < lattice.size; ++j) {
      const sum = [0, 0, 0];
      for (let q = 0; q < perTexel; ++q) {
        const at = 4 * (j * perTexel + q);
        const [x, y, z] = inverseTurn(R, cells[at], cells[at + 1], cells[at + 2]);
        const L = this.skyRadiance(x, y, z);
        for (let c = 0; c < 3; ++c) sum[c] += cells[at + 3] * L[c];
      }
      for (let c = 0; c < 3; ++c) out[3 * j + c] = sum[c];
    }
    this.sun.addTo(lattice, R, out);
    return out;
  }
}

/** A lat-long map: width x height RGB float32, row 0 at +Y. */
export class LatLongMap {
  constructor(name, width, height, rgb, constants) {
    this.name = name;
    this.width = width;
    this.height = height;
    this.rgb = rgb;
    this.constants = constants;
  }
  integrate(lattice, R) {
    const W = this.width, H = this.height, rgb = this.rgb;
    const texelAngle = 0.5 * PI / lattice.resolution;
    const sub = Math.max(1, Math.ceil(this.constants.map_sub_cells_per_texel * (PI / H) / texelAngle));
    const subW = W * sub, subH = H * sub;
    const sinPhi = new Float64Array(subW), cosPhi = new Float64Array(subW);
    for (let i = 0; i < subW; ++i) {
      const phi = 2 * PI * ((i + 0.5) / subW - 0.5);
      sinPhi[i] = Math.sin(phi);
      cosPhi[i] = Math.cos(phi);
    }
    const out = new Float64Array(3 * lattice.size);
    for (let r = 0; r < subH; ++r) {
      const theta0 = PI * r / subH, theta1 = PI * (r + 1) / subH, theta = 0.5 * (theta0 + theta1);
      const sinT = Math.sin(theta), cosT = Math.cos(theta);
      const omega = (Math.cos(theta0) - Math.cos(theta1)) * (2 * PI / subW);
      const rowStart = 3 * Math.floor(r / sub) * W;
      for (let i = 0; i < subW; ++i) {
        const p = rowStart + 3 * Math.floor(i / sub);
        const red = rgb[p], green = rgb[p + 1], blue = rgb[p + 2];
        if (red === 0 && green === 0 && blue === 0) continue;
        const dx = sinT * sinPhi[i], dz = -sinT * cosPhi[i];
        const j = 3 * lattice.texelOf(R[0] * dx + R[1] * cosT + R[2] * dz,
          R[3] * dx + R[4] * cosT + R[5] * dz, R[6] * dx + R[7] * cosT + R[8] * dz);
        out[j] += omega * red;
        out[j + 1] += omega * green;
        out[j + 2] += omega * blue;
      }
    }
    return out;
  }
}

/** A built-in map from its spec (sky, constant:..., sun:...). */
export function builtinMap(spec, name, constants) {
  if (spec === "sky") return new SkyMap(constants);
  if (spec.startsWith("constant:")) {
    const v = parseNumbers(spec.slice(9), spec);
    if (v.length !== 1 && v.length !== 3) throw new Error(`environment ${spec}: constant:V or constant:R,G,B`);
    return new ConstantMap(name, v.length === 1 ? [v[0], v[0], v[0]] : v);
  }
  if (spec.startsWith("sun:")) {
    const v = parseNumbers(spec.slice(4), spec);
    if (v.length !== 4) throw new Error(`environment ${spec}: sun:THETA,PHI,SIZE_DEG,INTENSITY`);
    return new SunMap(name, v[0], v[1], v[2], [v[3], v[3], v[3]], constants);
  }
  throw new Error(`environment ${spec}: not a built-in map`);
}

/** Refuses a map the CLI refuses: not 2:1 within the tolerance, or too large. */
export function checkLatLongSize(where, width, height, constants) {
  if (!(width > 0 && height > 0)) throw new Error(`${where}: the image has no pixels`);
  if (width * height > constants.max_map_pixels)
    throw new Error(`${where}: ${width}x${height} is larger than the largest map read`);
  const off = Math.abs(width - 2 * height) / (2 * height);
  if (off > constants.latlong_aspect_tolerance)
    throw new Error(`${where}: a ${width}x${height} image is not a lat-long map (2:1)`);
  return off > 0 ? `${where}: ${width}x${height} is not exactly 2:1; read as a lat-long map` : "";
}
