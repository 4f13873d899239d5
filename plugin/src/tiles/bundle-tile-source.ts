/**
 * A TileSource whose tiles are bundles of K plane images (one per plane group of a relight layer),
 * so OpenSeadragon's level choice, coverage, cache and abort apply to all planes in lockstep.
 */
import OpenSeadragon from 'openseadragon';
import { ImageInfoError } from '../iiif/errors';
import type { ImageGeometry } from '../iiif/image-info';
import { BUNDLE_DATA_TYPE, registerBundleType, type PlaneBundle } from './bundle';
import { fetchPlane } from './fetch-plane';
import { bundleKey } from './tile-key';

/** Constructor options of {@link BundleTileSource}. */
export interface BundleTileSourceOptions {
  /** The IIIF `info.json` documents, one per plane group, in plane order. */
  readonly infos: readonly Record<string, unknown>[];
  /** The common geometry of the plane groups (see `commonGeometry`). */
  readonly geometry: ImageGeometry;
  /** Tile format per plane group, e.g. `png`; overrides `preferredFormats`. */
  readonly formats?: readonly string[];
  /** Index of the plane group used for previews (the colour group). @default 0 */
  readonly previewIndex?: number;
  /** `fetch` credentials mode. @default 'same-origin' */
  readonly credentials?: RequestCredentials;
  /** Further attempts per plane after a network error or HTTP 408, 429 or 5xx. @default 2 */
  readonly retries?: number;
  /** Wait before a plane's first retry, doubled for each next one (ms). @default 500 */
  readonly retryDelayMs?: number;
  /**
   * The level {@link BundleTileSource.getClosestLevel} answers (OpenSeadragon's coverage cut-off),
   * for a tiling whose own answer would be wrong (whole levels). @default OpenSeadragon's answer
   */
  readonly cutoffLevel?: number;
}

/** Per-job state kept on the OSD ImageJob's userData. */
interface JobState {
  controller: AbortController;
  /** The job was finished, failed or aborted: later results are dropped. */
  settled: boolean;
}

interface TileJob {
  tile: { level: number; x: number; y: number };
  userData: Record<string, unknown>;
  /** OpenSeadragon's time limit for the job (ms; its `timeout` option). */
  timeout?: number;
  /** Null once OpenSeadragon completed the job itself (its time limit passed). */
  jobId?: unknown;
  finish(data: unknown, request: unknown, dataType: string): void;
  fail(message: string, request: unknown): void;
}

/**
 * How much sooner than OpenSeadragon's own time limit a bundle gives up (ms): OSD's `fail` is not
 * guarded against a second call, so the source must settle the job before OSD does.
 */
const DEADLINE_MARGIN_MS = 250;

/** A plane URL builder: OSD's own IIIF tile source, so URLs match what OSD would request. */
interface IIIFSource {
  getTileUrl(level: number, x: number, y: number): string;
  getTileWidth(level: number): number;
  getTileHeight(level: number): number;
  getLevelScale(level: number): number;
  getNumTiles(level: number): OpenSeadragon.Point;
  getTileAtPoint(level: number, point: OpenSeadragon.Point): OpenSeadragon.Point;
}

function makeIiifSource(info: Record<string, unknown>, format: string | undefined): IIIFSource {
  const Iiif = (OpenSeadragon as unknown as { IIIFTileSource: new (o: object) => IIIFSource }).IIIFTileSource;
  const proto = Iiif.prototype as unknown as { configure(d: object, u: string): object };
  const json: Record<string, unknown> = structuredClone(info);
  const options = proto.configure(json, `${String(json.id)}/info.json`) as Record<string, unknown>;
  if (format) {
    options.tileFormat = format;
  }
  return new Iiif(options);
}

/**
 * Tile source of one relightable layer. Geometry and URLs come from K `IIIFTileSource`s (one per
 * plane group); a tile's data is a {@link PlaneBundle} of type `lanternaBundle`.
 */
export class BundleTileSource extends OpenSeadragon.TileSource {
  /** URL builders, one per plane group (assigned after `super()`: TileSource deep-copies options). */
  declare planeSources: IIIFSource[];
  declare previewIndex: number;
  declare credentials: RequestCredentials;
  declare retries: number;
  declare retryDelayMs: number;
  declare cutoffLevel: number | undefined;

  constructor(options: BundleTileSourceOptions) {
    const g = options.geometry;
    const maxLevel = Math.round(Math.log2(Math.max(...g.scaleFactors)));
    super({
      width: g.width,
      height: g.height,
      tileWidth: g.tileWidth,
      tileHeight: g.tileHeight,
      tileOverlap: 0,
      minLevel: 0,
      maxLevel,
      ready: true,
    });
    if (options.infos.length === 0) {
      throw new ImageInfoError('a bundle tile source needs at least one info.json');
    }
    registerBundleType();
    this.planeSources = options.infos.map((info, i) => makeIiifSource(info, options.formats?.[i]));
    this.previewIndex = options.previewIndex ?? 0;
    this.credentials = options.credentials ?? 'same-origin';
    this.retries = options.retries ?? 2;
    this.retryDelayMs = options.retryDelayMs ?? 500;
    this.cutoffLevel = options.cutoffLevel;
  }

  override getClosestLevel(): number {
    return this.cutoffLevel ?? super.getClosestLevel();
  }

  private get primary(): IIIFSource {
    const p = this.planeSources[0];
    if (!p) {
      throw new ImageInfoError('no plane sources');
    }
    return p;
  }

  /** The K plane URLs of a tile, in plane order. */
  getPlaneUrls(level: number, x: number, y: number): string[] {
    return this.planeSources.map((s) => s.getTileUrl(level, x, y));
  }

  override getTileUrl(level: number, x: number, y: number): string {
    return this.primary.getTileUrl(level, x, y);
  }

  override getTileHashKey(level: number, x: number, y: number): string {
    return bundleKey(this.getPlaneUrls(level, x, y));
  }

  override getTileWidth(level: number): number {
    return this.primary.getTileWidth(level);
  }

  override getTileHeight(level: number): number {
    return this.primary.getTileHeight(level);
  }

  override getLevelScale(level: number): number {
    return this.primary.getLevelScale(level);
  }

  override getNumTiles(level: number): OpenSeadragon.Point {
    return this.primary.getNumTiles(level);
  }

  // The shipped typings say this returns a Tile; OSD really returns the tile's (x, y) as a Point.
  override getTileAtPoint(level: number, point: OpenSeadragon.Point): OpenSeadragon.Tile {
    return this.primary.getTileAtPoint(level, point) as unknown as OpenSeadragon.Tile;
  }

  override hasTransparency(): boolean {
    return false;
  }

  override equals(other: unknown): boolean {
    return other instanceof BundleTileSource
      && other.planeSources.length === this.planeSources.length
      && other.getPlaneUrls(0, 0, 0).join() === this.getPlaneUrls(0, 0, 0).join();
  }

  /**
   * Fetch the tile's K planes together. A plane that fails transiently is retried on its own (the
   * others are kept); if one still fails, or the bundle is not done shortly before OpenSeadragon's
   * time limit, the whole bundle fails (OpenSeadragon then keeps drawing the coarser level there).
   */
  override downloadTileStart(context: OpenSeadragon.ImageJob): void {
    const job = context as unknown as TileJob;
    const state: JobState = { controller: new AbortController(), settled: false };
    job.userData.lanterna = state;
    const { level, x, y } = job.tile;
    const urls = this.getPlaneUrls(level, x, y);
    const limit = job.timeout ?? 30000;
    let timedOut = false;
    const deadline = setTimeout(() => {
      timedOut = true;
      state.controller.abort(new Error('timed out'));
    }, Math.max(0, limit - DEADLINE_MARGIN_MS));
    const options = {
      credentials: this.credentials, signal: state.controller.signal, retries: this.retries,
      retryDelayMs: this.retryDelayMs,
    };
    void Promise.allSettled(urls.map((url) => fetchPlane(url, options))).then((results) => {
      clearTimeout(deadline);
      const bitmaps = results.flatMap((r) => (r.status === 'fulfilled' ? [r.value] : []));
      const index = results.findIndex((r) => r.status === 'rejected');
      const failed = results[index];
      const drop = (): void => { bitmaps.forEach((b) => { b.close(); }); };
      // Aborted by OpenSeadragon, or completed by its own time limit: it must not hear from us again.
      if (state.settled || job.jobId === null) {
        drop();
        return;
      }
      state.settled = true;
      const first = bitmaps[0];
      if (failed || !first || bitmaps.some((b) => b.width !== first.width || b.height !== first.height)) {
        // One missing or odd plane fails the whole bundle; free the planes that did arrive.
        drop();
        const why = timedOut ? `no answer from ${urls[index] ?? urls[0] ?? ''} within ${(limit / 1000).toFixed(1)} s`
          : bundleFailure(failed?.status === 'rejected' ? failed.reason : undefined, bitmaps, urls);
        job.fail(`[lanterna] tile ${level}/${x}_${y}: ${why}`, null);
        return;
      }
      const bundle: PlaneBundle = { bitmaps, previewIndex: this.previewIndex, width: first.width, height: first.height };
      job.finish(bundle, null, BUNDLE_DATA_TYPE);
    });
  }

  override downloadTileAbort(context: OpenSeadragon.ImageJob): void {
    const job = context as unknown as TileJob;
    const state = job.userData.lanterna as JobState | undefined;
    if (state) {
      state.settled = true; // OpenSeadragon fails the job itself right after this
      state.controller.abort(new Error('aborted'));
    }
  }
}

/** Why a bundle failed, for the `tile-load-failed` message. */
function bundleFailure(reason: unknown, bitmaps: readonly ImageBitmap[], urls: readonly string[]): string {
  if (reason !== undefined) {
    return reason instanceof Error ? reason.message : JSON.stringify(reason);
  }
  if (bitmaps.length === 0) {
    return `no planes (${urls.join(', ')})`;
  }
  const sizes = bitmaps.map((b, i) => `${urls[i] ?? '?'}: ${b.width}×${b.height}`);
  return `plane tiles differ in size (${sizes.join('; ')})`;
}
