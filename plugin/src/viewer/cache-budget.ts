/**
 * How many tile bundles OpenSeadragon's tile cache keeps: sized by the view, capped by bytes
 * (docs/rendering.md, "Tile cache"). Pure: no DOM, no GL.
 *
 * A bundle holds one decoded 256² RGBA plane (256 KiB) per plane group, and once drawn a GPU
 * texture of the same size: a 3-plane PTM tile is 0.75 MiB (+0.75 on the GPU), a 16-plane HSH tile
 * 4 MiB (+4). The cache keeps the tiles of three views (the active layer, the layer switched away
 * from, the lens layer) plus a quarter for panning, so switching layers A→B→A fetches nothing
 * again; but no more than {@link CACHE_BYTES} of decoded planes, unless one view of the heaviest
 * layer alone needs more (the tiles being drawn are never evicted anyway).
 */

/** Decoded plane bytes the cache may hold beyond one view (the GPU textures are as much again). */
export const CACHE_BYTES = 768 * 1024 * 1024;

/** Views the cache holds: the active layer, the one switched away from, the lens layer. */
export const CACHE_VIEWS = 3;

/** Extra share for panning and zooming around the view. */
export const CACHE_MARGIN = 1.25;

/** The tile size the counts assume (the tiler's default). */
export const CACHE_TILE_SIZE = 256;

/**
 * Tiles of one layer an OpenSeadragon view of `width` × `height` CSS px can draw, at most: every
 * level from the finest one drawn (up to 1 / `minPixelRatio` image px per screen px) to the one
 * that fits in a tile, each with a partial tile at both edges.
 */
export function viewTileCount(width: number, height: number, minPixelRatio: number, tileSize = CACHE_TILE_SIZE): number {
  let span = tileSize * minPixelRatio; // screen px covered by one tile of the finest level
  let count = 0;
  for (;;) {
    const across = Math.ceil(width / span);
    const down = Math.ceil(height / span);
    count += (across + 1) * (down + 1);
    if (across <= 1 && down <= 1) {
      return count;
    }
    span *= 2;
  }
}

/** Options of {@link cacheTileCount}. */
export interface CacheBudgetOptions {
  /** The viewer's size in CSS px. */
  readonly width: number;
  readonly height: number;
  /** OpenSeadragon's `minPixelRatio` (0.5: its full detail). */
  readonly minPixelRatio: number;
  /** Plane groups of the heaviest layer (the most planes per bundle). */
  readonly planes: number;
}

/** The tile cache's size, in bundles (OpenSeadragon's `maxImageCacheCount`). */
export function cacheTileCount(options: CacheBudgetOptions): number {
  const view = viewTileCount(Math.max(1, options.width), Math.max(1, options.height), options.minPixelRatio);
  const bundleBytes = Math.max(1, options.planes) * CACHE_TILE_SIZE * CACHE_TILE_SIZE * 4;
  const byBytes = Math.floor(CACHE_BYTES / bundleBytes);
  return Math.max(view, Math.min(Math.ceil(view * CACHE_VIEWS * CACHE_MARGIN), byBytes));
}
