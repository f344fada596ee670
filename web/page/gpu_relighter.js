// The relighter on the GPU (WebGL2), in the algebra of relight/ and
// docs/formats.md ("Model file"): per frame
//   1. g = V_g^T L over the directions some pixel sees (N x RGB),
//   2. each cluster's W_c^T g times its bases' i8 steps, and mean_c . g,
//   3. each pixel albedo x (u_p . W_c^T g + mean_c . g), composed over the
//      background with its coverage, clamped at zero, exposed, tone mapped
//      and encoded to 8-bit sRGB by the thresholds of imageio's encoder.
// Arrays are 2D array textures of kWidth x kWidth texels a layer, indexed in
// order (a 1024x1024 model's bases are 276 M values); the passes' outputs are
// 2D textures of kWidth texels a row.
const kWidth = 4096;

const kHeader = `#version 300 es
precision highp float;
precision highp int;
precision highp sampler2D;
precision highp sampler2DArray;
precision highp isampler2DArray;
precision highp usampler2DArray;
const int kWidth = ${kWidth};
ivec2 at(int i) { return ivec2(i % kWidth, i / kWidth); }
ivec3 in3(int i) { return ivec3(i % kWidth, (i / kWidth) % kWidth, i / (kWidth * kWidth)); }
int indexOf(vec2 fragment) { return int(fragment.y) * kWidth + int(fragment.x); }
out vec4 result;
`;

const kVertex = `#version 300 es
void main() {
  vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}`;

// g[n] = sum over seen texels s (and channel blocks) of V[n][c S + s] L[s].
const kProject = `${kHeader}
uniform sampler2DArray basis, light;
uniform int count, seen, channels;
void main() {
  int n = indexOf(gl_FragCoord.xy);
  if (n >= count) { result = vec4(0.0); return; }
  int width = channels * seen, first = n * width;
  vec3 sum = vec3(0.0);
  for (int i = 0; i < width; ++i) {
    float v = texelFetch(basis, in3(first + i), 0).r;
    int s = i % seen;
    vec3 l = texelFetch(light, in3(s), 0).rgb;
    if (channels == 1) sum += v * l;
    else sum[i / seen] += v * l[i / seen];
  }
  result = vec4(sum, 0.0);
}`;

// Entries [0, bases): basis b's W^T g times its step; then one per cluster: mean_c . g.
const kTowards = `${kHeader}
uniform sampler2DArray bases, means, scale;
uniform sampler2D projected;
uniform int bases_count, clusters, globalBases, hasMean;
void main() {
  int b = indexOf(gl_FragCoord.xy);
  vec3 sum = vec3(0.0);
  if (b < bases_count) {
    for (int n = 0; n < globalBases; ++n)
      sum += texelFetch(bases, in3(b * globalBases + n), 0).r * texelFetch(projected, at(n), 0).rgb;
    sum *= texelFetch(scale, in3(b), 0).r;
  } else if (b < bases_count + clusters && hasMean == 1) {
    int c = b - bases_count;
    for (int n = 0; n < globalBases; ++n)
      sum += texelFetch(means, in3(c * globalBases + n), 0).r * texelFetch(projected, at(n), 0).rgb;
  }
  result = vec4(sum, 0.0);
}`;

function shadeSource(coefficientType) {
  const sampler = coefficientType === "i8" ? "isampler2DArray" : "sampler2DArray";
  return `${kHeader}
uniform ${sampler} coefficients;
uniform usampler2DArray pixelInfo;
uniform sampler2DArray albedoCoverage, thresholds, mapPixels, rays, rayAngles;
uniform sampler2D towards;
uniform int basesCount, width, height, background, mapKind, floatOut, tone;
uniform int mapWidth, mapHeight, yawOnly;
uniform float uShift;
uniform float exposureScale;
uniform mat3 inverseRotation;
uniform vec3 constantRadiance;
// The sky (mapKind 2) and a sun disc (2 and 3).
uniform vec3 sunCentre, sunRadiance, skyZenith, skyHorizon, skyGround, glowColour;
uniform float sunCosHalf, glowStrength, glowSharpness, horizonPower;
const float kPi = 3.14159265358979323846;

vec3 mapTexel(int x, int y) { return texelFetch(mapPixels, in3(y * mapWidth + x), 0).rgb; }
vec3 latLong(float u, float v) {
  float x = u * float(mapWidth) - 0.5;
  float y = clamp(v * float(mapHeight) - 0.5, 0.0, float(mapHeight - 1));
  float x0 = floor(x), y0 = floor(y);
  float fx = x - x0, fy = y - y0;
  int px0 = int(mod(x0, float(mapWidth))), px1 = int(mod(x0 + 1.0, float(mapWidth)));
  int py0 = int(y0), py1 = min(py0 + 1, mapHeight - 1);
  return (1.0 - fx) * (1.0 - fy) * mapTexel(px0, py0) + fx * (1.0 - fy) * mapTexel(px1, py0) +
         (1.0 - fx) * fy * mapTexel(px0, py1) + fx * fy * mapTexel(px1, py1);
}
// A pixel's ray: its lat-long (u, v) worked out once in doubles (a map turned
// by a yaw alone slides along u, as relight/image_composer.cpp finds it), or
// its direction turned and looked up here.
vec3 environment(ivec3 pixel) {
  if (mapKind == 1 && yawOnly == 1) {
    vec2 uv = texelFetch(rayAngles, pixel, 0).xy;
    return latLong(uv.x + uShift, uv.y);
  }
  vec3 d = normalize(inverseRotation * texelFetch(rays, pixel, 0).xyz);
  if (mapKind == 1)
    return latLong(0.5 + atan(d.x, -d.z) / (2.0 * kPi), acos(clamp(d.y, -1.0, 1.0)) / kPi);
  if (mapKind == 4) return constantRadiance;
  if (dot(d, sunCentre) >= sunCosHalf) return sunRadiance;
  if (mapKind == 3) return vec3(0.0);
  if (d.y < 0.0) return skyGround;
  float t = pow(1.0 - d.y, horizonPower);
  float glow = glowStrength * exp(-glowSharpness * (1.0 - dot(d, sunCentre)));
  return (1.0 - t) * skyZenith + t * skyHorizon + glow * glowColour;
}
int srgbCode(float scaled) {
  // The smallest code whose threshold lies above the value (255 steps).
  int lo = 0, hi = 255;
  while (lo < hi) {
    int mid = (lo + hi) / 2;
    if (texelFetch(thresholds, ivec3(mid, 0, 0), 0).r <= scaled) lo = mid + 1; else hi = mid;
  }
  return lo;
}
float encoded(float linear) {
  float v = linear * exposureScale;
  if (tone == 1 && v > 0.0) v = v * (2.51 * v + 0.03) / (v * (2.43 * v + 0.59) + 0.14);
  return float(srgbCode(v)) / 255.0;
}
void main() {
  int x = int(gl_FragCoord.x), y = height - 1 - int(gl_FragCoord.y);
  ivec3 pixel = in3(y * width + x);
  uvec4 info = texelFetch(pixelInfo, pixel, 0);
  vec4 ac = texelFetch(albedoCoverage, pixel, 0);
  float coverage = info.w > 0u ? ac.a : 0.0;
  vec3 colour = vec3(0.0);
  if (background == 0 && coverage < 1.0) colour = (1.0 - coverage) * environment(pixel);
  if (info.w > 0u) {
    int first = int(info.x), basis = int(info.y), rank = int(info.z);
    vec3 sum = texelFetch(towards, at(basesCount + int(info.w) - 1), 0).rgb;
    for (int k = 0; k < rank; ++k)
      sum += float(texelFetch(coefficients, in3(first + k), 0).r) *
             texelFetch(towards, at(basis + k), 0).rgb;
    colour += coverage * (ac.rgb * sum);
  }
  colour = max(colour, vec3(0.0));
  float alpha = background == 2 ? coverage : 1.0;
  if (floatOut == 1) { result = vec4(colour, alpha); return; }
  result = vec4(encoded(colour.r), encoded(colour.g), encoded(colour.b), alpha);
}`;
}

/** The 255 smallest float values whose 8-bit sRGB code steps up, as
 * imageio's SrgbEncoder finds them: code(x) = round(255 linearToSrgb(x)). */
function srgbThresholds() {
  const code = (x) => Math.round(255 * (x <= 0.0031308 ? 12.92 * x : 1.055 * Math.pow(x, 1 / 2.4) - 0.055));
  const f = new Float32Array(1), bits = new Uint32Array(f.buffer);
  const floatOf = (b) => { bits[0] = b; return f[0]; };
  const thresholds = new Float32Array(256).fill(Infinity);
  f[0] = 1;
  const one = bits[0];
  for (let c = 0; c < 255; ++c) {
    let lo = 0, hi = one;  // the smallest float bits with code > c
    while (lo < hi) {
      const mid = lo + Math.floor((hi - lo) / 2);
      if (code(floatOf(mid)) > c) hi = mid; else lo = mid + 1;
    }
    thresholds[c] = floatOf(lo);
  }
  return thresholds;
}

export class GpuRelighter {
  /** site: { manifest, array(name) } as site.js loads it. */
  constructor(canvas, site) {
    const gl = canvas.getContext("webgl2", {
      antialias: false, premultipliedAlpha: false, preserveDrawingBuffer: true, alpha: true,
    });
    if (!gl) throw new Error("this browser has no WebGL2: the page relights on the GPU through WebGL2");
    if (!gl.getExtension("EXT_color_buffer_float"))
      throw new Error("this browser's WebGL2 cannot render to float textures (EXT_color_buffer_float)");
    this.gl = gl;
    this.site = site;
    const m = site.manifest;
    this.width = m.width;
    this.height = m.height;
    canvas.width = m.width;
    canvas.height = m.height;
    const limit = gl.getParameter(gl.MAX_TEXTURE_SIZE);
    if (limit < kWidth) throw new Error(`this GPU's textures are at most ${limit} texels wide`);
    this.maxRows = limit;
    this.maxLayers = gl.getParameter(gl.MAX_ARRAY_TEXTURE_LAYERS);
    this.programs = {
      project: this.program(kProject),
      towards: this.program(kTowards),
      shade: this.program(shadeSource(m.arrays.coefficients.type)),
    };
    this.upload();
  }

  program(fragment) {
    const gl = this.gl;
    const compile = (type, source) => {
      const s = gl.createShader(type);
      gl.shaderSource(s, source);
      gl.compileShader(s);
      if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
      return s;
    };
    const p = gl.createProgram();
    gl.attachShader(p, compile(gl.VERTEX_SHADER, kVertex));
    gl.attachShader(p, compile(gl.FRAGMENT_SHADER, fragment));
    gl.linkProgram(p);
    if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(p));
    return p;
  }

  /** A 2D array texture of `count` texels of `components` values (kWidth
   * a row, kWidth rows a layer), uploaded a layer at a time from views of
   * `values` (no copy but the last row's padding). */
  texture(kind, values, count, components) {
    const gl = this.gl;
    const formats = {
      f32: [[gl.R32F, gl.RED], [], [], [gl.RGBA32F, gl.RGBA]], f16: [[gl.R16F, gl.RED]],
      i8: [[gl.R8I, gl.RED_INTEGER]], u32: [[], [], [], [gl.RGBA32UI, gl.RGBA_INTEGER]],
    };
    const types = { f32: gl.FLOAT, f16: gl.HALF_FLOAT, i8: gl.BYTE, u32: gl.UNSIGNED_INT };
    const [internal, format] = formats[kind][components - 1];
    count = Math.max(1, count);
    const rows = Math.ceil(count / kWidth), w = Math.min(count, kWidth);
    const h = Math.min(rows, kWidth), layers = Math.ceil(rows / kWidth);
    if (layers > this.maxLayers) throw new Error(`the model's ${count} values do not fit this GPU's textures`);
    const t = gl.createTexture();
    const target = gl.TEXTURE_2D_ARRAY;
    gl.bindTexture(target, t);
    for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(target, p, gl.NEAREST);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    gl.texStorage3D(target, 1, internal, w, h, layers);
    const full = Math.floor(Math.min(count, values.length / components) / w);  // whole rows held
    for (let row = 0; row < rows; row += h) {
      const n = Math.min(h, full - row);
      if (n > 0)
        gl.texSubImage3D(target, 0, 0, 0, row / h, w, n, 1, format, types[kind],
          values.subarray(row * w * components, (row + n) * w * components));
    }
    if (full < rows) {
      // The last row, padded.
      const last = new values.constructor(w * components);
      last.set(values.subarray(full * w * components, Math.min(values.length, count * components)));
      gl.texSubImage3D(target, 0, 0, full % h, Math.floor(full / h), w, 1, 1, format, types[kind], last);
    }
    return { texture: t };
  }

  /** A float render target of `count` RGBA texels, kWidth a row. */
  target(count) {
    const gl = this.gl;
    const w = Math.max(1, Math.min(count, kWidth)), h = Math.max(1, Math.ceil(count / kWidth));
    if (h > this.maxRows) throw new Error(`${count} values do not fit a texture of this GPU`);
    const t = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, t);
    for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D, p, gl.NEAREST);
    gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA32F, w, h);
    const fb = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, t, 0);
    if (gl.checkFramebufferStatus(gl.FRAMEBUFFER) !== gl.FRAMEBUFFER_COMPLETE)
      throw new Error("this browser cannot render to a float texture");
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    return { texture: t, width: w, height: h, framebuffer: fb, is2D: true };
  }

  upload() {
    const m = this.site.manifest, a = (name) => this.site.array(name);
    const ranks = a("cluster_rank"), rows = a("cluster_rows");
    this.clusters = ranks.length;
    this.seen = a("seen_texels");
    this.basesCount = a("coefficient_scale").length;
    const types = m.arrays;
    this.t = {
      basis: this.texture("f32", a("global_basis"), a("global_basis").length, 1),
      bases: this.texture(types.bases.type, a("bases"), a("bases").length, 1),
      means: m.has_mean ? this.texture(types.means.type, a("means"), a("means").length, 1)
        : this.texture("f32", new Float32Array(1), 1, 1),
      scale: this.texture("f32", a("coefficient_scale"), this.basesCount, 1),
      coefficients: this.texture(types.coefficients.type, a("coefficients"), a("coefficients").length, 1),
      thresholds: this.texture("f32", srgbThresholds(), 256, 1),
      map: this.texture("f32", new Float32Array(4), 1, 4),
    };
    // Each pixel: where its coefficients and its cluster's entries start, its
    // rank and cluster + 1 (0: background); its albedo and coverage.
    const pixels = this.width * this.height;
    const info = new Uint32Array(4 * pixels), albedoCoverage = new Float32Array(4 * pixels);
    const rowPixel = a("row_pixel"), albedo = a("albedo"), coverage = a("coverage");
    let row = 0, coefficient = 0, basis = 0;
    for (let c = 0; c < this.clusters; ++c) {
      for (let k = 0; k < rows[c]; ++k, ++row) {
        const p = rowPixel[row];
        info.set([coefficient, basis, ranks[c], c + 1], 4 * p);
        albedoCoverage.set([albedo[3 * row], albedo[3 * row + 1], albedo[3 * row + 2], coverage[row]], 4 * p);
        coefficient += ranks[c];
      }
      basis += ranks[c];
    }
    this.t.pixelInfo = this.texture("u32", info, pixels, 4);
    this.uploadRays();
    this.t.albedoCoverage = this.texture("f32", albedoCoverage, pixels, 4);
    this.projected = this.target(m.global_bases);
    this.towards = this.target(this.basesCount + this.clusters);
    this.image = this.target(pixels);
    this.imageTarget = this.floatImageTarget();
  }

  /** Each pixel's camera ray through its centre, and its lat-long (u, v), in
   * doubles as transport/camera.cpp and lighting/ find them. */
  uploadRays() {
    const w = this.width, h = this.height, c = this.camera();
    const rays = new Float32Array(4 * w * h), angles = new Float32Array(4 * w * h);
    for (let y = 0; y < h; ++y)
      for (let x = 0; x < w; ++x) {
        const sx = (2 * (x + 0.5) / w - 1) * c.tanHalf * (w / h), sy = (1 - 2 * (y + 0.5) / h) * c.tanHalf;
        const d = [0, 1, 2].map((i) => c.forward[i] + sx * c.right[i] + sy * c.up[i]);
        const n = Math.hypot(d[0], d[1], d[2]), at = 4 * (y * w + x);
        rays.set([d[0] / n, d[1] / n, d[2] / n, 0], at);
        angles[at] = 0.5 + Math.atan2(d[0] / n, -d[2] / n) / (2 * Math.PI);
        angles[at + 1] = Math.acos(Math.max(-1, Math.min(1, d[1] / n))) / Math.PI;
      }
    this.t.rays = this.texture("f32", rays, w * h, 4);
    this.t.rayAngles = this.texture("f32", angles, w * h, 4);
  }

  /** An RGBA32F target the image's size, for float read-back. */
  floatImageTarget() {
    const gl = this.gl;
    const t = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, t);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, this.width, this.height, 0, gl.RGBA, gl.FLOAT, null);
    const fb = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, t, 0);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    return fb;
  }

  /** The lattice lighting (3 l doubles) of the next frames. */
  setLighting(lighting) {
    const light = new Float32Array(4 * this.seen.length);
    this.seen.forEach((j, s) => light.set([lighting[3 * j], lighting[3 * j + 1], lighting[3 * j + 2], 0], 4 * s));
    if (this.t.light) this.gl.deleteTexture(this.t.light.texture);
    this.t.light = this.texture("f32", light, this.seen.length, 4);
    this.lightingChanged = true;
  }

  /** What the background shows: a lat-long map's pixels, or a built-in map. */
  setMap(map) {
    this.map = map;
    if (map.rgb) {
      const n = map.width * map.height, rgba = new Float32Array(4 * n);
      for (let i = 0; i < n; ++i) rgba.set(map.rgb.subarray(3 * i, 3 * i + 3), 4 * i);
      this.gl.deleteTexture(this.t.map.texture);
      this.t.map = this.texture("f32", rgba, n, 4);
    }
  }

  bindTextures(program, named) {
    const gl = this.gl;
    Object.entries(named).forEach(([name, t], unit) => {
      gl.activeTexture(gl.TEXTURE0 + unit);
      gl.bindTexture(t.is2D ? gl.TEXTURE_2D : gl.TEXTURE_2D_ARRAY, t.texture);
      gl.uniform1i(gl.getUniformLocation(program, name), unit);
    });
  }

  pass(program, target, uniforms, textures) {
    const gl = this.gl;
    gl.useProgram(program);
    gl.bindFramebuffer(gl.FRAMEBUFFER, target ? target.framebuffer : null);
    gl.viewport(0, 0, target ? target.width : this.width, target ? target.height : this.height);
    this.bindTextures(program, textures);
    for (const [name, [kind, ...v]] of Object.entries(uniforms)) {
      const at = gl.getUniformLocation(program, name);
      if (kind === "i") gl.uniform1i(at, v[0]);
      else if (kind === "f") gl.uniform1f(at, v[0]);
      else if (kind === "v3") gl.uniform3fv(at, v[0]);
      else if (kind === "m3") gl.uniformMatrix3fv(at, false, v[0]);
    }
    gl.drawArrays(gl.TRIANGLES, 0, 3);
  }

  /** Draws a frame: view = { R (row-major), exposure, tone, background }. */
  render(view, floatOut = false) {
    const m = this.site.manifest, p = this.programs;
    if (this.lightingChanged) {
      this.pass(p.project, this.projected,
        { count: ["i", m.global_bases], seen: ["i", this.seen.length], channels: ["i", m.channels] },
        { basis: this.t.basis, light: this.t.light });
      this.pass(p.towards, this.towards,
        { bases_count: ["i", this.basesCount], clusters: ["i", this.clusters],
          globalBases: ["i", m.global_bases], hasMean: ["i", m.has_mean ? 1 : 0] },
        { bases: this.t.bases, means: this.t.means, scale: this.t.scale, projected: this.projected });
      this.lightingChanged = false;
    }
    const backgrounds = { env: 0, black: 1, alpha: 2 };
    const map = this.map;
    const R = view.R;
    const yawOnly = R[4] === 1 && R[1] === 0 && R[3] === 0 && R[5] === 0 && R[7] === 0;
    const sun = map.sun || map;
    const k = m.lighting;
    const uniforms = {
      basesCount: ["i", this.basesCount], width: ["i", this.width], height: ["i", this.height],
      background: ["i", backgrounds[view.background]], floatOut: ["i", floatOut ? 1 : 0],
      tone: ["i", view.tone === "aces" ? 1 : 0], exposureScale: ["f", Math.pow(2, view.exposure)],
      mapKind: ["i", map.rgb ? 1 : map.sun ? 2 : map.centre ? 3 : 4],
      mapWidth: ["i", map.width || 1], mapHeight: ["i", map.height || 1],
      inverseRotation: ["m3", new Float32Array(R)], yawOnly: ["i", yawOnly ? 1 : 0],
      uShift: ["f", Math.atan2(R[2], R[0]) / (2 * Math.PI)],
      constantRadiance: ["v3", map.radiance && !map.centre ? map.radiance : [0, 0, 0]],
      sunCentre: ["v3", sun.centre || [0, 1, 0]], sunRadiance: ["v3", sun.radiance || [0, 0, 0]],
      sunCosHalf: ["f", sun.cosHalf === undefined ? 2 : sun.cosHalf],
      skyZenith: ["v3", k.sky_zenith], skyHorizon: ["v3", k.sky_horizon], skyGround: ["v3", k.sky_ground],
      glowColour: ["v3", k.sky_glow_colour], glowStrength: ["f", k.sky_glow_strength],
      glowSharpness: ["f", k.sky_glow_sharpness], horizonPower: ["f", k.sky_horizon_power],
    };
    const target = floatOut ? { framebuffer: this.imageTarget, width: this.width, height: this.height } : null;
    this.pass(p.shade, target, uniforms, {
      coefficients: this.t.coefficients, pixelInfo: this.t.pixelInfo,
      albedoCoverage: this.t.albedoCoverage, towards: this.towards,
      thresholds: this.t.thresholds, mapPixels: this.t.map, rays: this.t.rays, rayAngles: this.t.rayAngles,
    });
  }

  camera() {
    const c = this.site.manifest.camera;
    const sub = (a, b) => a.map((v, i) => v - b[i]);
    const norm = (a) => { const n = Math.hypot(...a); return a.map((v) => v / n); };
    const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
    const forward = norm(sub(c.target, c.eye));
    const right = norm(cross(forward, c.up));
    return { forward, right, up: cross(right, forward), tanHalf: Math.tan(0.5 * c.fov_degrees * Math.PI / 180) };
  }

  /** The canvas's 8-bit RGBA, rows from the top. */
  readPixels8() {
    const gl = this.gl, w = this.width, h = this.height;
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    const bottomUp = new Uint8Array(4 * w * h);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, bottomUp);
    return flipRows(bottomUp, w, h);
  }

  /** The frame's linear RGBA floats (before exposure), rows from the top. */
  readPixelsFloat(view) {
    const gl = this.gl, w = this.width, h = this.height;
    this.render(view, true);
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.imageTarget);
    const bottomUp = new Float32Array(4 * w * h);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.FLOAT, bottomUp);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    return flipRows(bottomUp, w, h);
  }
}

function flipRows(bottomUp, w, h) {
  const out = new bottomUp.constructor(bottomUp.length);
  for (let y = 0; y < h; ++y) out.set(bottomUp.subarray(4 * w * (h - 1 - y), 4 * w * (h - y)), 4 * w * y);
  return out;
}
