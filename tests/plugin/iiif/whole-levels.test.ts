import { describe, expect, it } from 'vitest';
import type { ImageGeometry } from '../../../plugin/src/iiif/image-info';
import { DEFAULT_WHOLE_LEVEL_MAX_SIDE, viewLevel, wholeLevelTiling } from '../../../plugin/src/iiif/whole-levels';
import { info } from '../fixtures';

/** An info.json of a W×H level-0 pyramid in 256² tiles, as the dataset writer makes it. */
function pyramid(width: number, height: number, extra: Record<string, unknown> = {}):
  { info: Record<string, unknown>; geometry: ImageGeometry } {
  const scaleFactors = [1];
  while (Math.max(width, height) / scaleFactors[scaleFactors.length - 1] > 256) {
    scaleFactors.push(2 * scaleFactors[scaleFactors.length - 1]);
  }
  const sizes = [...scaleFactors].reverse().map((f) => ({ width: Math.ceil(width / f), height: Math.ceil(height / f) }));
  return {
    info: info({ width, height, sizes, tiles: [{ width: 256, height: 256, scaleFactors }], ...extra }),
    geometry: { width, height, tileWidth: 256, tileHeight: 256, scaleFactors },
  };
}

describe('wholeLevelTiling', () => {
  it('tiles a small image one tile per level, keeping its levels', () => {
    const { info: i, geometry } = pyramid(900, 700);
    const whole = wholeLevelTiling([i, i], geometry, DEFAULT_WHOLE_LEVEL_MAX_SIDE);
    expect(whole?.geometry).toEqual({ ...geometry, tileWidth: 900, tileHeight: 900 });
    expect(whole?.infos).toHaveLength(2);
    expect(whole?.infos[0]?.tiles).toEqual([{ width: 900, height: 900, scaleFactors: [1, 2, 4] }]);
    expect(whole?.infos[0]?.sizes).toEqual(i.sizes);
    expect(i.tiles).toEqual([{ width: 256, height: 256, scaleFactors: [1, 2, 4] }]); // not changed
  });

  it('leaves an image over the limit, or any image when the limit is 0, on tiles', () => {
    const { info: i, geometry } = pyramid(1025, 600);
    expect(wholeLevelTiling([i], geometry, 1024)).toBeNull();
    expect(wholeLevelTiling([i], geometry, 1025)).not.toBeNull();
    const small = pyramid(600, 400);
    expect(wholeLevelTiling([small.info], small.geometry, 0)).toBeNull();
  });

  it('leaves an image that already fits one tile alone', () => {
    const { info: i, geometry } = pyramid(200, 150);
    expect(wholeLevelTiling([i], geometry, 1024)).toBeNull();
  });

  it('needs every reduced level in every group\'s sizes (its whole image may not exist otherwise)', () => {
    const { info: i, geometry } = pyramid(900, 700);
    const withoutQuarter = { ...i, sizes: (i.sizes as { width: number }[]).filter((s) => s.width !== 225) };
    expect(wholeLevelTiling([i, withoutQuarter], geometry, 1024)).toBeNull();
    const noSizes = { ...i };
    delete noSizes.sizes;
    expect(wholeLevelTiling([noSizes], geometry, 1024)).toBeNull();
    const withoutFull = { ...i, sizes: (i.sizes as { width: number }[]).filter((s) => s.width !== 900) };
    expect(wholeLevelTiling([withoutFull], geometry, 1024)).not.toBeNull(); // full/max serves level 0
  });

  it('needs scale factors 1, 2, 4, … and a full-resolution full/max', () => {
    const { info: i, geometry } = pyramid(900, 700);
    expect(wholeLevelTiling([i], { ...geometry, scaleFactors: [1, 4] }, 1024)).toBeNull();
    expect(wholeLevelTiling([{ ...i, maxWidth: 450, maxHeight: 350 }], geometry, 1024)).toBeNull();
  });
});

describe('the coverage cut-off of whole levels', () => {
  it('is the original tiling\'s one-tile level without a view (OpenSeadragon loads the same levels)', () => {
    const { info: i, geometry } = pyramid(1024, 1024); // 256², 512², 1024²: only the 256² level fits a tile
    expect(wholeLevelTiling([i], geometry, 1024)?.cutoffLevel).toBe(0);
    const wide = pyramid(900, 200); // 225×50 and 450×100 (two tiles wide) and 900×200
    expect(wholeLevelTiling([wide.info], wide.geometry, 1024)?.cutoffLevel).toBe(0);
  });

  it('is the level the opening view needs, given one', () => {
    const { info: i, geometry } = pyramid(1024, 1024);
    const at = (displayWidth: number) => wholeLevelTiling([i], geometry, 1024, { displayWidth, minPixelRatio: 0.75 })
      ?.cutoffLevel;
    expect([at(1080), at(768), at(767), at(480), at(384), at(100)]).toEqual([2, 2, 1, 1, 1, 0]);
  });
});

describe('viewLevel', () => {
  it('picks the finest level whose pixels are at least minPixelRatio CSS px wide', () => {
    expect(viewLevel(640, 640, 2, 0.5)).toBe(2);
    expect(viewLevel(319, 640, 2, 0.5)).toBe(1); // 319/640 < 0.5 ≤ 319/320
    expect(viewLevel(160, 640, 2, 1)).toBe(0);
    expect(viewLevel(10, 640, 2, 1)).toBe(0); // the coarsest, even when too big
    expect(viewLevel(641, 641, 0, 1)).toBe(0);
    expect(viewLevel(161, 641, 2, 1)).toBe(0); // level 1 is ceil(641/2) = 321 wide
  });
});
