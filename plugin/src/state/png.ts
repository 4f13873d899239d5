/**
 * A tiny PNG writer and chunk reader: CRC-32, chunks, `iTXt` text, and the PNG of RGBA pixels given a
 * zlib compressor (the browser's `CompressionStream('deflate')`; Node's zlib in the tests). Pure:
 * no DOM. PNG: ISO/IEC 15948 (the W3C PNG specification).
 */

/** The eight bytes every PNG starts with. */
export const PNG_SIGNATURE = Uint8Array.of(0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a);

const CRC_TABLE = (() => {
  const table = new Uint32Array(256);
  for (let n = 0; n < 256; n++) {
    let c = n;
    for (let k = 0; k < 8; k++) {
      c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
    }
    table[n] = c >>> 0;
  }
  return table;
})();

/** CRC-32 (ISO 3309, the PNG and zlib polynomial) of `bytes`. */
export function crc32(bytes: Uint8Array): number {
  let c = 0xffffffff;
  for (const b of bytes) {
    c = (CRC_TABLE[(c ^ b) & 0xff] ?? 0) ^ (c >>> 8);
  }
  return (c ^ 0xffffffff) >>> 0;
}

/** One PNG chunk: its four-letter type and data. */
export interface PngChunk {
  readonly type: string;
  readonly data: Uint8Array;
}

const ascii = (text: string): Uint8Array => Uint8Array.from(text, (ch) => ch.charCodeAt(0) & 0xff);

function concat(parts: readonly Uint8Array[]): Uint8Array {
  const out = new Uint8Array(parts.reduce((n, p) => n + p.length, 0));
  let at = 0;
  for (const p of parts) {
    out.set(p, at);
    at += p.length;
  }
  return out;
}

/** A chunk's bytes: length, type, data, CRC of type + data. */
export function chunkBytes(chunk: PngChunk): Uint8Array {
  const out = new Uint8Array(12 + chunk.data.length);
  const view = new DataView(out.buffer);
  view.setUint32(0, chunk.data.length);
  out.set(ascii(chunk.type), 4);
  out.set(chunk.data, 8);
  view.setUint32(8 + chunk.data.length, crc32(out.subarray(4, 8 + chunk.data.length)));
  return out;
}

/** A malformed PNG (the reader's one error). */
export class PngError extends Error {}

/** The chunks of a PNG, each CRC checked. @throws {@link PngError} */
export function readChunks(png: Uint8Array): PngChunk[] {
  if (png.length < 8 || PNG_SIGNATURE.some((b, i) => png[i] !== b)) {
    throw new PngError('not a PNG (bad signature)');
  }
  const view = new DataView(png.buffer, png.byteOffset, png.byteLength);
  const chunks: PngChunk[] = [];
  let at = 8;
  while (at < png.length) {
    if (at + 12 > png.length) {
      throw new PngError(`truncated chunk at byte ${at}`);
    }
    const length = view.getUint32(at);
    const end = at + 12 + length;
    if (end > png.length) {
      throw new PngError(`truncated chunk at byte ${at}`);
    }
    const type = String.fromCharCode(...png.subarray(at + 4, at + 8));
    if (crc32(png.subarray(at + 4, at + 8 + length)) !== view.getUint32(at + 8 + length)) {
      throw new PngError(`bad CRC in the ${type} chunk at byte ${at}`);
    }
    chunks.push({ type, data: png.slice(at + 8, at + 8 + length) });
    at = end;
    if (type === 'IEND') {
      break;
    }
  }
  return chunks;
}

/**
 * An uncompressed `iTXt` chunk: `keyword` (1–79 Latin-1 characters) and UTF-8 `text`.
 * @throws {@link PngError} for a keyword PNG does not allow
 */
export function textChunk(keyword: string, text: string): PngChunk {
  if (!/^[\x20-\x7e\xa1-\xff]{1,79}$/.test(keyword) || /^ | $| {2}/.test(keyword)) {
    throw new PngError(`bad PNG text keyword ${JSON.stringify(keyword)}`);
  }
  // keyword \0, compression flag 0, method 0, no language tag \0, no translated keyword \0, text
  return { type: 'iTXt', data: concat([ascii(keyword), Uint8Array.of(0, 0, 0, 0, 0), new TextEncoder().encode(text)]) };
}

/** The text of every `tEXt` and uncompressed `iTXt` chunk, by keyword (the first of each). */
export function readTexts(chunks: readonly PngChunk[]): Record<string, string> {
  const out: Record<string, string> = {};
  for (const { type, data } of chunks) {
    const nul = data.indexOf(0);
    if (nul < 1 || (type !== 'tEXt' && type !== 'iTXt')) {
      continue;
    }
    const keyword = String.fromCharCode(...data.subarray(0, nul));
    let text: string | null;
    if (type === 'tEXt') {
      text = String.fromCharCode(...data.subarray(nul + 1));
    } else {
      const lang = data.indexOf(0, nul + 3);
      const translated = lang < 0 ? -1 : data.indexOf(0, lang + 1);
      text = data[nul + 1] === 0 && translated >= 0 ? new TextDecoder().decode(data.subarray(translated + 1)) : null;
    }
    if (text !== null && !(keyword in out)) {
      out[keyword] = text;
    }
  }
  return out;
}

/** Compresses bytes to a zlib stream (RFC 1950). */
export type Deflate = (bytes: Uint8Array) => Promise<Uint8Array>;

/**
 * The PNG of `width × height` RGBA pixels (8 bits, rows top-down, filter 0), with `texts`
 * (keyword → text) as `iTXt` chunks before the image data.
 */
export async function encodePng(width: number, height: number, rgba: Uint8Array, deflate: Deflate,
  texts: Readonly<Record<string, string>> = {}): Promise<Uint8Array> {
  if (rgba.length !== width * height * 4) {
    throw new PngError(`${rgba.length} bytes for ${width}×${height} RGBA pixels`);
  }
  const ihdr = new Uint8Array(13);
  const view = new DataView(ihdr.buffer);
  view.setUint32(0, width);
  view.setUint32(4, height);
  ihdr.set([8, 6, 0, 0, 0], 8); // 8 bits, RGBA, deflate, filter method 0, no interlace
  const row = width * 4;
  const raw = new Uint8Array((row + 1) * height);
  for (let y = 0; y < height; y++) {
    raw.set(rgba.subarray(y * row, (y + 1) * row), y * (row + 1) + 1); // filter type 0 (None)
  }
  const chunks: PngChunk[] = [
    { type: 'IHDR', data: ihdr },
    ...Object.entries(texts).map(([k, v]) => textChunk(k, v)),
    { type: 'IDAT', data: await deflate(raw) },
    { type: 'IEND', data: new Uint8Array(0) },
  ];
  return concat([PNG_SIGNATURE, ...chunks.map(chunkBytes)]);
}
