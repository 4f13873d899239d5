import { describe, expect, it } from 'vitest';
import {
  CACHE_BYTES, CACHE_MARGIN, CACHE_TILE_SIZE, CACHE_VIEWS, cacheTileCount, viewTileCount,
} from '../../../plugin/src/viewer/cache-budget';

/** Brute force: the tiles of every level an axis-aligned view can touch, worst placement. */
function bruteViewTiles(width: number, height: number, ratio: number, tile: number): number {
  let count = 0;
  for (let span = tile * ratio; ; span *= 2) {
    const worst = (px: number): number => {
      let most = 0;
      for (let offset = 0; offset < span; offset += span / 16) {
        most = Math.max(most, Math.floor((offset + px - 1e-9) / span) + 1);
      }
      return most;
    };
    count += worst(width) * worst(height);
    if (width <= span && height <= span) {
      return count;
    }
  }
}

describe('the tile cache budget', () => {
  it('counts at least the tiles of every level a view can touch', () => {
    for (const [w, h] of [[640, 480], [1920, 1080], [300, 2000]] as const) {
      for (const ratio of [0.5, 0.75, 1]) {
        expect(viewTileCount(w, h, ratio)).toBeGreaterThanOrEqual(bruteViewTiles(w, h, ratio, CACHE_TILE_SIZE));
      }
    }
  });

  it('needs more tiles at full detail than with coarser levels', () => {
    expect(viewTileCount(1920, 1080, 0.5)).toBeGreaterThan(viewTileCount(1920, 1080, 0.75));
  });

  it('holds three views and a margin for light layers', () => {
    const view = viewTileCount(1920, 1080, 0.5);
    expect(cacheTileCount({ width: 1920, height: 1080, minPixelRatio: 0.5, planes: 1 }))
      .toBe(Math.ceil(view * CACHE_VIEWS * CACHE_MARGIN));
  });

  it('caps heavy layers by bytes, but never below one view', () => {
    const bundle = (planes: number): number => planes * CACHE_TILE_SIZE * CACHE_TILE_SIZE * 4;
    const view = viewTileCount(1920, 1080, 0.5);
    const nine = cacheTileCount({ width: 1920, height: 1080, minPixelRatio: 0.5, planes: 9 });
    expect(nine * bundle(9)).toBeLessThanOrEqual(CACHE_BYTES);
    expect(nine).toBeGreaterThanOrEqual(view);
    expect(cacheTileCount({ width: 1920, height: 1080, minPixelRatio: 0.5, planes: 64 })).toBe(view);
  });
});
