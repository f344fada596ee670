// The 6 x R x R cube lattice of lighting directions (docs/design.md section 3,
// transport/cube_lattice.h): faces +X, -X, +Y, -Y, +Z, -Z, the OpenGL
// major-axis (s, t) table, texel j = (face R + row) R + col, and each texel's
// exact solid angle.

/** Solid angle of [0, x] x [0, y] on the plane at distance 1. */
function cornerArea(x, y) {
  return Math.atan2(x * y, Math.sqrt(x * x + y * y + 1));
}

/** Exact solid angle of the face-plane rectangle [x0, x1] x [y0, y1]. */
export function rectangleSolidAngle(x0, y0, x1, y1) {
  return cornerArea(x1, y1) - cornerArea(x0, y1) - cornerArea(x1, y0) + cornerArea(x0, y0);
}

/** Unnormalised direction of face coordinates (sc, tc) in [-1, 1]. */
export function faceDirection(face, sc, tc) {
  switch (face) {
    case 0: return [1, -tc, -sc];
    case 1: return [-1, -tc, sc];
    case 2: return [sc, 1, tc];
    case 3: return [sc, -1, -tc];
    case 4: return [sc, -tc, 1];
    default: return [-sc, -tc, -1];
  }
}

export class CubeLattice {
  constructor(resolution) {
    if (!(Number.isInteger(resolution) && resolution >= 1 && resolution <= 1024))
      throw new Error(`cube-map resolution ${resolution} is out of range 1..1024`);
    this.resolution = resolution;
    this.size = 6 * resolution * resolution;
    this.solidAngles = new Float64Array(this.size);
    const step = 2 / resolution;
    for (let j = 0; j < this.size; ++j) {
      const { row, col } = this.texelCoord(j);
      const s0 = -1 + col * step, t0 = -1 + row * step;
      this.solidAngles[j] = rectangleSolidAngle(s0, t0, s0 + step, t0 + step);
    }
  }

  texelCoord(j) {
    const r = this.resolution, r2 = r * r;
    return { face: Math.floor(j / r2), row: Math.floor((j % r2) / r), col: j % r };
  }

  /** The texel whose footprint holds direction (x, y, z), as texelOf does. */
  texelOf(x, y, z) {
    const ax = Math.abs(x), ay = Math.abs(y), az = Math.abs(z);
    let face, sc, tc, ma;
    if (ax >= ay && ax >= az) {
      ma = ax;
      face = x >= 0 ? 0 : 1;
      sc = x >= 0 ? -z : z;
      tc = -y;
    } else if (ay >= az) {
      ma = ay;
      face = y >= 0 ? 2 : 3;
      sc = x;
      tc = y >= 0 ? z : -z;
    } else {
      ma = az;
      face = z >= 0 ? 4 : 5;
      sc = z >= 0 ? x : -x;
      tc = -y;
    }
    const r = this.resolution;
    const cell = (c) => Math.min(r - 1, Math.max(0, Math.floor((c / ma + 1) * 0.5 * r)));
    return (face * r + cell(tc)) * r + cell(sc);
  }
}

/** R = Rz(roll) Rx(pitch) Ry(yaw), degrees (lighting/rotation.h), row-major. */
export function rotationMatrix(yaw, pitch = 0, roll = 0) {
  const rad = Math.PI / 180;
  const [cy, sy] = [Math.cos(yaw * rad), Math.sin(yaw * rad)];
  const [cp, sp] = [Math.cos(pitch * rad), Math.sin(pitch * rad)];
  const [cr, sr] = [Math.cos(roll * rad), Math.sin(roll * rad)];
  const ry = [cy, 0, sy, 0, 1, 0, -sy, 0, cy];
  const rx = [1, 0, 0, 0, cp, -sp, 0, sp, cp];
  const rz = [cr, -sr, 0, sr, cr, 0, 0, 0, 1];
  return multiply(rz, multiply(rx, ry));
}

export function multiply(a, b) {
  const out = new Array(9);
  for (let i = 0; i < 3; ++i)
    for (let j = 0; j < 3; ++j)
      out[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j];
  return out;
}

/** Unit direction of lat-long angles: theta from +Y, phi from -Z towards +X. */
export function directionFromAngles(theta, phi) {
  return [Math.sin(theta) * Math.sin(phi), Math.cos(theta), -Math.sin(theta) * Math.cos(phi)];
}
