import { deflateSync, inflateSync } from 'node:zlib';
import { describe, expect, it } from 'vitest';
import {
  chunkBytes, crc32, encodePng, PNG_SIGNATURE, PngError, readChunks, readTexts, textChunk,
} from '../../../plugin/src/state/png';

const ascii = (s: string): Uint8Array => Uint8Array.from(s, (c) => c.charCodeAt(0));
const deflate = (b: Uint8Array): Promise<Uint8Array> => Promise.resolve(new Uint8Array(deflateSync(b)));

describe('crc32', () => {
  it('matches the standard check value and the IEND chunk', () => {
    expect(crc32(ascii('123456789'))).toBe(0xcbf43926); // the CRC-32 check value
    expect(crc32(ascii('IEND'))).toBe(0xae426082); // every PNG ends with this CRC
    expect(crc32(new Uint8Array(0))).toBe(0);
  });
});

describe('PNG chunks', () => {
  it('writes length, type, data and CRC', () => {
    const bytes = chunkBytes({ type: 'IEND', data: new Uint8Array(0) });
    expect([...bytes]).toEqual([0, 0, 0, 0, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82]);
  });

  it('encodes pixels that decode back, with the text chunks', async () => {
    const w = 5;
    const h = 3;
    const rgba = Uint8Array.from({ length: w * h * 4 }, (_, i) => (i * 37) % 256);
    const png = await encodePng(w, h, rgba, deflate, { Title: 'Tablette d’argile', 'Lanterna mode': 'specular' });
    expect([...png.subarray(0, 8)]).toEqual([...PNG_SIGNATURE]);
    const chunks = readChunks(png);
    expect(chunks.map((c) => c.type)).toEqual(['IHDR', 'iTXt', 'iTXt', 'IDAT', 'IEND']);
    const ihdr = new DataView(chunks[0]?.data.buffer ?? new ArrayBuffer(13));
    expect([ihdr.getUint32(0), ihdr.getUint32(4), ihdr.getUint8(8), ihdr.getUint8(9)]).toEqual([5, 3, 8, 6]);
    expect(readTexts(chunks)).toEqual({ Title: 'Tablette d’argile', 'Lanterna mode': 'specular' });
    const raw = inflateSync(chunks[3]?.data ?? new Uint8Array(0));
    for (let y = 0; y < h; y++) {
      expect(raw[y * (w * 4 + 1)]).toBe(0);
      expect([...raw.subarray(y * (w * 4 + 1) + 1, (y + 1) * (w * 4 + 1))]).toEqual([...rgba.subarray(y * w * 4, (y + 1) * w * 4)]);
    }
  });

  it('reads tEXt chunks too, the first of each keyword', () => {
    const tEXt = { type: 'tEXt', data: Uint8Array.from([...ascii('Author'), 0, ...ascii('Ana')]) };
    expect(readTexts([tEXt, textChunk('Author', 'Other'), textChunk('Note', 'é')])).toEqual({ Author: 'Ana', Note: 'é' });
  });

  it('rejects a bad CRC, a bad signature, truncation and bad keywords', async () => {
    const png = await encodePng(1, 1, Uint8Array.of(1, 2, 3, 4), deflate);
    const broken = png.slice();
    broken[20] = (broken[20] ?? 0) ^ 1; // inside IHDR
    expect(() => readChunks(broken)).toThrow(/bad CRC in the IHDR chunk/);
    expect(() => readChunks(png.subarray(1))).toThrow(PngError);
    expect(() => readChunks(png.subarray(0, png.length - 3))).toThrow(/truncated/);
    expect(() => textChunk('', 'x')).toThrow(PngError);
    expect(() => textChunk(' lead', 'x')).toThrow(PngError);
    expect(() => textChunk('x'.repeat(80), 'x')).toThrow(PngError);
    await expect(encodePng(2, 2, new Uint8Array(3), deflate)).rejects.toThrow(/3 bytes for 2×2/);
  });
});
