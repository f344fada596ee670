// Radiance RGBE (.hdr) files read in the page: the header, then scanlines flat
// or run-length encoded (the "new" RLE of Ward's format), each pixel
// m x 2^(e - 136) per channel, as OpenImageIO reads them for the CLI.

function fail(name, why) {
  throw new Error(`${name}: ${why}`);
}

/** { width, height, rgb: Float32Array } of an .hdr file's bytes. */
export function readHdr(bytes, name) {
  let at = 0;
  const line = () => {
    const start = at;
    while (at < bytes.length && bytes[at] !== 10) ++at;
    if (at >= bytes.length) fail(name, "the header ends before the image size");
    return new TextDecoder("latin1").decode(bytes.subarray(start, at++));
  };
  const magic = line();
  if (!magic.startsWith("#?")) fail(name, "not a Radiance .hdr file (no #? signature)");
  for (let text = line(); text !== ""; text = line())
    if (text.startsWith("FORMAT=") && text !== "FORMAT=32-bit_rle_rgbe")
      fail(name, `${text.slice(7)} is not RGBE`);
  const size = line().match(/^-Y (\d+) \+X (\d+)$/);
  if (!size) fail(name, "only top-down, left-to-right images (-Y H +X W) are read");
  const height = Number(size[1]), width = Number(size[2]);
  if (!(width > 0 && height > 0)) fail(name, "the image has no pixels");
  const rgb = new Float32Array(width * height * 3);
  const scan = new Uint8Array(width * 4);
  for (let y = 0; y < height; ++y) {
    at = readScanline(bytes, at, width, scan, name);
    for (let x = 0; x < width; ++x) {
      const e = scan[4 * x + 3];
      const f = e ? Math.pow(2, e - 136) : 0;
      for (let c = 0; c < 3; ++c) rgb[3 * (y * width + x) + c] = scan[4 * x + c] * f;
    }
  }
  return { width, height, rgb };
}

/** One scanline into scan (RGBE bytes per pixel); returns the next offset. */
function readScanline(bytes, at, width, scan, name) {
  const need = (n) => { if (at + n > bytes.length) fail(name, "the file ends inside the image"); };
  need(4);
  const rle = width >= 8 && width < 32768 && bytes[at] === 2 && bytes[at + 1] === 2 &&
    !(bytes[at + 2] & 0x80);
  if (!rle) {
    // Flat pixels (old-style runs are not written by today's tools).
    need(4 * width);
    scan.set(bytes.subarray(at, at + 4 * width));
    return at + 4 * width;
  }
  if (((bytes[at + 2] << 8) | bytes[at + 3]) !== width) fail(name, "a scanline's length is wrong");
  at += 4;
  for (let c = 0; c < 4; ++c)
    for (let x = 0; x < width;) {
      need(1);
      let count = bytes[at++];
      if (count > 128) {
        count -= 128;
        need(1);
        if (x + count > width) fail(name, "a run passes the end of its scanline");
        const v = bytes[at++];
        for (let k = 0; k < count; ++k) scan[4 * x++ + c] = v;
      } else {
        if (count === 0 || x + count > width) fail(name, "a run passes the end of its scanline");
        need(count);
        for (let k = 0; k < count; ++k) scan[4 * x++ + c] = bytes[at++];
      }
    }
  return at;
}
