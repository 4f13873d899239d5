/**
 * A TileSource of one patch image (`docs/annotations.md`, "Individual annotations in the viewer"): a
 * single level and a single tile, the PNG decoded like every overlay tile (straight alpha, no colour
 * conversion) into a one-plane `lanternaBundle`, so the drawer's overlay pass draws it exactly as a
 * level tile. An image that is not its destination size (a file dropped into the store) is drawn
 * stretched to it: magnified by the overlay shader (bilinear on premultiplied colour, like the
 * tiler), reduced by the browser first (`createImageBitmap`, bilinear on straight alpha).
 */
import OpenSeadragon from 'openseadragon';
import { BUNDLE_DATA_TYPE, registerBundleType, type PlaneBundle } from '../tiles/bundle';
import type { PixelBox } from '../annotations/draw-plan';
import { fetchPlane } from '../tiles/fetch-plane';

/** What OpenSeadragon hands to `downloadTileStart` (typed locally: the shipped types omit it). */
interface TileJob {
  userData: Record<string, unknown>;
  jobId?: unknown;
  finish(data: unknown, request: unknown, dataType: string): void;
  fail(message: string, request: unknown): void;
}

interface JobState {
  controller: AbortController;
  settled: boolean;
}

/** What {@link PatchTileSource} draws: a patch PNG, its destination size and the part of it shown. */
export interface PatchImage {
  readonly url: string;
  /** The destination size in level pixels: the image is drawn stretched to it. */
  readonly width: number;
  readonly height: number;
  /** The part of the destination-size image that is drawn (inside the level image). */
  readonly crop: PixelBox;
}

/** A patch PNG as a one-tile source of its cropped destination size. */
export class PatchTileSource extends OpenSeadragon.TileSource {
  declare patch: PatchImage;

  constructor(patch: PatchImage) {
    const { width, height } = patch.crop;
    super({ width, height, tileWidth: width, tileHeight: height, tileOverlap: 0, minLevel: 0, maxLevel: 0,
      ready: true });
    registerBundleType();
    this.patch = patch;
  }

  private get patchUrl(): string {
    return this.patch.url;
  }

  override getTileUrl(): string {
    return this.patchUrl;
  }

  override getTileHashKey(): string {
    const { width, height, crop } = this.patch;
    return `lanterna-patch|${this.patchUrl}|${width}x${height}|${crop.x},${crop.y},${crop.width},${crop.height}`;
  }

  override getLevelScale(): number {
    return 1;
  }

  override getNumTiles(): OpenSeadragon.Point {
    return new OpenSeadragon.Point(1, 1);
  }

  // The shipped typings say this returns a Tile; OSD really returns the tile's (x, y) as a Point.
  override getTileAtPoint(): OpenSeadragon.Tile {
    return new OpenSeadragon.Point(0, 0) as unknown as OpenSeadragon.Tile;
  }

  override hasTransparency(): boolean {
    return true;
  }

  override equals(other: unknown): boolean {
    return other instanceof PatchTileSource && other.getTileHashKey() === this.getTileHashKey();
  }

  override downloadTileStart(context: OpenSeadragon.ImageJob): void {
    const job = context as unknown as TileJob;
    const state: JobState = { controller: new AbortController(), settled: false };
    job.userData.lanterna = state;
    fetchPlane(this.patchUrl, { credentials: 'same-origin', signal: state.controller.signal, retries: 2,
      retryDelayMs: 500 }).then((decoded) => this.#sized(decoded)).then((bitmap) => {
      if (state.settled || job.jobId === null) {
        bitmap.close();
        return;
      }
      state.settled = true;
      const bundle: PlaneBundle = { bitmaps: [bitmap], previewIndex: 0, width: bitmap.width, height: bitmap.height };
      job.finish(bundle, null, BUNDLE_DATA_TYPE);
    }, (error: unknown) => {
      if (state.settled || job.jobId === null) {
        return;
      }
      state.settled = true;
      job.fail(`[lanterna] patch ${this.patchUrl}: ${error instanceof Error ? error.message : String(error)}`, null);
    });
  }

  /**
   * The bitmap's part that is drawn (the crop, in its own pixels), made no larger than the drawn size
   * (the original closed). A smaller one is stretched over the tile by the overlay shader, which
   * filters premultiplied colour.
   */
  async #sized(bitmap: ImageBitmap): Promise<ImageBitmap> {
    const { width, height, crop } = this.patch;
    const whole = crop.x === 0 && crop.y === 0 && crop.width === width && crop.height === height;
    if (whole && bitmap.width <= width && bitmap.height <= height) {
      return bitmap;
    }
    const sx = bitmap.width / width;
    const sy = bitmap.height / height;
    const x = Math.round(crop.x * sx);
    const y = Math.round(crop.y * sy);
    const w = Math.max(1, Math.round((crop.x + crop.width) * sx) - x);
    const h = Math.max(1, Math.round((crop.y + crop.height) * sy) - y);
    const plain = { premultiplyAlpha: 'none', colorSpaceConversion: 'none' } as const;
    try {
      return await createImageBitmap(bitmap, x, y, w, h, w > crop.width || h > crop.height
        ? { ...plain, resizeWidth: crop.width, resizeHeight: crop.height, resizeQuality: 'medium' } : plain);
    } finally {
      bitmap.close();
    }
  }

  override downloadTileAbort(context: OpenSeadragon.ImageJob): void {
    const state = (context as unknown as TileJob).userData.lanterna as JobState | undefined;
    if (state) {
      state.settled = true;
      state.controller.abort(new Error('aborted'));
    }
  }
}
