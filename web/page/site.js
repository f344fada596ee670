// The export's files, loaded and checked: model.json (what the arrays are
// and the maps), model.bin (the arrays, each at a multiple of 8 bytes) and
// each lat-long map's pixels.
import { builtinMap, LatLongMap } from "./maps.js";

const kTypes = { f32: Float32Array, f16: Uint16Array, i8: Int8Array, i32: Int32Array };
const kArrays = ["seen_texels", "global_basis", "cluster_rank", "cluster_rows", "bases",
  "coefficient_scale", "coefficients", "row_pixel", "albedo", "coverage"];

async function fetchBytes(file) {
  let response;
  try {
    response = await fetch(file);
  } catch (e) {
    throw new Error(`${file} could not be loaded (${e.message})`);
  }
  if (!response.ok) throw new Error(`${file} could not be loaded (HTTP ${response.status})`);
  return response.arrayBuffer();
}

export async function loadSite() {
  let manifest;
  try {
    manifest = JSON.parse(new TextDecoder().decode(await fetchBytes("model.json")));
  } catch (e) {
    throw new Error(e.message.includes("could not be loaded") ? e.message
      : `model.json is not the export's manifest (${e.message}): run adaptive-cpca web again`);
  }
  if (manifest.format !== "adaptive-cpca web model" || manifest.version !== 1)
    throw new Error("model.json is not a version 1 web model: run adaptive-cpca web again");
  const bin = await fetchBytes("model.bin");
  const arrays = {};
  for (const name of kArrays.concat(manifest.has_mean ? ["means"] : [])) {
    const entry = manifest.arrays[name];
    const type = entry && kTypes[entry.type];
    if (!type || !(entry.offset % 8 === 0 && entry.offset + entry.count * type.BYTES_PER_ELEMENT <= bin.byteLength))
      throw new Error(`model.bin does not hold the array ${name} that model.json names: run adaptive-cpca web again`);
    arrays[name] = new type(bin, entry.offset, entry.count);
  }
  checkShapes(manifest, arrays);
  return {
    manifest,
    array: (name) => arrays[name],
    maps: manifest.maps.map((entry) => ({ ...entry })),
  };
}

function checkShapes(m, a) {
  const corrupt = (why) => { throw new Error(`model.bin is corrupt: ${why}; run adaptive-cpca web again`); };
  let rows = 0, bases = 0, coefficients = 0;
  for (let c = 0; c < a.cluster_rank.length; ++c) {
    if (a.cluster_rank[c] < 0 || a.cluster_rows[c] < 0) corrupt(`cluster ${c} has a negative size`);
    rows += a.cluster_rows[c];
    bases += a.cluster_rank[c];
    coefficients += a.cluster_rows[c] * a.cluster_rank[c];
  }
  const l = 6 * m.cubemap * m.cubemap, pixels = m.width * m.height;
  if (rows !== m.rows || a.row_pixel.length !== rows || a.albedo.length !== 3 * rows || a.coverage.length !== rows)
    corrupt("its rows do not add up");
  if (a.coefficient_scale.length !== bases || a.bases.length !== bases * m.global_bases)
    corrupt("its bases do not add up");
  if (a.coefficients.length !== coefficients) corrupt("its coefficients do not add up");
  if (a.global_basis.length !== m.global_bases * m.channels * a.seen_texels.length) corrupt("its global basis is cut short");
  if (a.seen_texels.some((j) => j < 0 || j >= l)) corrupt("a direction lies outside the lattice");
  if (a.row_pixel.some((p) => p < 0 || p >= pixels)) corrupt("a row's pixel lies outside the image");
  for (const name of ["global_basis", "albedo", "coverage", "coefficient_scale"])
    if (a[name].some((v) => !Number.isFinite(v))) corrupt(`${name} holds a value that is not finite`);
}

/** The map of a list entry, its pixels fetched when it is a file. */
export async function loadMap(entry, constants) {
  if (!entry.file) return builtinMap(entry.spec, entry.name, constants);
  const bytes = await fetchBytes(entry.file);
  if (bytes.byteLength !== 12 * entry.width * entry.height)
    throw new Error(`${entry.file} is not ${entry.width}x${entry.height} RGB floats: run adaptive-cpca web again`);
  return new LatLongMap(entry.name, entry.width, entry.height, new Float32Array(bytes), constants);
}
