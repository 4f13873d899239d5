/**
 * Reading a layer's plane values at one image pixel from the planes themselves: the full-resolution
 * tile of each plane group holding the pixel (the URLs OpenSeadragon requests, so a tile already seen
 * comes from the browser cache), decoded unchanged (no colour conversion, no premultiplication),
 * then dequantised as the shader does (`v = (t − bias)·scale`, t = texel/255, in float32).
 */
import type { LoadedLayer } from '../iiif/load';
import { BundleTileSource } from '../tiles/bundle-tile-source';
import { fetchPlane } from '../tiles/fetch-plane';
import { groupValues } from './dequantise';

/** The RGBA bytes of one decoded tile. */
interface TilePixels {
  readonly width: number;
  readonly height: number;
  readonly data: Uint8ClampedArray;
}

/** Decoded tiles kept (each at most one tile of a plane group). */
export const TILE_CACHE_SIZE = 24;

/** Reads plane values at image pixels, keeping the last {@link TILE_CACHE_SIZE} decoded tiles. */
export class PlanePixels {
  readonly #tiles = new Map<string, Promise<TilePixels>>();
  readonly #sources = new WeakMap<LoadedLayer, BundleTileSource>();
  readonly #credentials: RequestCredentials;

  constructor(credentials: RequestCredentials = 'same-origin') {
    this.#credentials = credentials;
  }

  /**
   * Every channel of `layer` at image pixel (x, y) (integers inside the image), dequantised.
   *
   * @throws the tile's `FetchError` when a plane cannot be fetched or decoded
   */
  async valuesAt(layer: LoadedLayer, x: number, y: number): Promise<Record<string, number>> {
    const g = layer.geometry;
    const source = this.#sourceOf(layer);
    const level = Math.round(Math.log2(Math.max(...g.scaleFactors)));
    const tx = Math.floor(x / g.tileWidth);
    const ty = Math.floor(y / g.tileHeight);
    const urls = source.getPlaneUrls(level, tx, ty);
    const tiles = await Promise.all(urls.map((url) => this.#tile(url)));
    const out: Record<string, number> = {};
    layer.layer.planes.forEach((group, i) => {
      const tile = tiles[i];
      if (tile) {
        const offset = ((y - ty * g.tileHeight) * tile.width + (x - tx * g.tileWidth)) * 4;
        Object.assign(out, groupValues(group, tile.data, offset));
      }
    });
    return out;
  }

  /** Forget every decoded tile. */
  clear(): void {
    this.#tiles.clear();
  }

  #sourceOf(layer: LoadedLayer): BundleTileSource {
    let source = this.#sources.get(layer);
    if (!source) {
      source = new BundleTileSource({ infos: layer.infos, geometry: layer.geometry,
        formats: layer.layer.planes.map((p) => p.format) });
      this.#sources.set(layer, source);
    }
    return source;
  }

  #tile(url: string): Promise<TilePixels> {
    const cached = this.#tiles.get(url);
    if (cached) {
      this.#tiles.delete(url); // most recently used last
      this.#tiles.set(url, cached);
      return cached;
    }
    const pending = decodeTile(url, this.#credentials);
    pending.catch(() => { this.#tiles.delete(url); });
    this.#tiles.set(url, pending);
    while (this.#tiles.size > TILE_CACHE_SIZE) {
      const oldest = this.#tiles.keys().next().value;
      if (oldest === undefined) {
        break;
      }
      this.#tiles.delete(oldest);
    }
    return pending;
  }
}

async function decodeTile(url: string, credentials: RequestCredentials): Promise<TilePixels> {
  const bitmap = await fetchPlane(url, { credentials, signal: new AbortController().signal, retries: 1,
    retryDelayMs: 500 });
  try {
    const canvas = new OffscreenCanvas(bitmap.width, bitmap.height);
    const context = canvas.getContext('2d', { willReadFrequently: true });
    if (!context) {
      throw new Error('no 2D canvas context to read a plane tile');
    }
    context.drawImage(bitmap, 0, 0);
    const { data } = context.getImageData(0, 0, bitmap.width, bitmap.height);
    return { width: bitmap.width, height: bitmap.height, data };
  } finally {
    bitmap.close();
  }
}
