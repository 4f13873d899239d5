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

/** A patch PNG at `url`, drawn `width × height` pixels (its destination size), as a one-tile source. */
export class PatchTileSource extends OpenSeadragon.TileSource {
  declare patchUrl: string;
  declare patchWidth: number;
  declare patchHeight: number;

  constructor(url: string, width: number, height: number) {
    super({ width, height, tileWidth: width, tileHeight: height, tileOverlap: 0, minLevel: 0, maxLevel: 0,
      ready: true });
    registerBundleType();
    this.patchUrl = url;
    this.patchWidth = width;
    this.patchHeight = height;
  }

  override getTileUrl(): string {
    return this.patchUrl;
  }

  override getTileHashKey(): string {
    return `lanterna-patch|${this.patchUrl}`;
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
    return other instanceof PatchTileSource && other.patchUrl === this.patchUrl;
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
   * The bitmap, made no larger than the destination (resized, the original closed): a smaller one is
   * stretched over the tile by the overlay shader, which filters premultiplied colour.
   */
  async #sized(bitmap: ImageBitmap): Promise<ImageBitmap> {
    if (bitmap.width <= this.patchWidth && bitmap.height <= this.patchHeight) {
      return bitmap;
    }
    try {
      return await createImageBitmap(bitmap, { resizeWidth: this.patchWidth, resizeHeight: this.patchHeight,
        resizeQuality: 'medium', premultiplyAlpha: 'none', colorSpaceConversion: 'none' });
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
