import { describe, expect, it } from 'vitest';
import { HOME_MAX_PIXEL_RATIO, homeZoom } from '../../../plugin/src/math/home-zoom';

/** CSS px per image px at viewport zoom `z` (the image is one viewport unit wide). */
const pixelRatio = (z: number, containerWidth: number, imageWidth: number): number => (z * containerWidth) / imageWidth;

describe('homeZoom (at most HOME_MAX_PIXEL_RATIO CSS px per image px)', () => {
  it('keeps the fitting zoom of an image larger than the viewer', () => {
    // 1536×1152 in 1280×720: fitted by its height, zoom 720/1152·1536/1280 = 0.75, 0.625 CSS px per px
    expect(homeZoom({ fitZoom: 0.75, containerWidth: 1280, imagePxPerUnit: 1536 })).toBe(0.75);
  });

  it('caps a tiny image at 2 CSS px per image px', () => {
    // 64×43 in 1280×720: fitted by its height (zoom 720/43·64/1280 ≈ 0.837, 16.7 CSS px per px)
    const fit = (720 / 43) * (64 / 1280);
    const z = homeZoom({ fitZoom: fit, containerWidth: 1280, imagePxPerUnit: 64 });
    expect(z).toBeLessThan(fit);
    expect(pixelRatio(z, 1280, 64)).toBeCloseTo(HOME_MAX_PIXEL_RATIO, 12);
    expect(pixelRatio(homeZoom({ fitZoom: fit, containerWidth: 1280, imagePxPerUnit: 64, maxPixelRatio: 4 }),
      1280, 64)).toBeCloseTo(4, 12);
  });

  it('falls back to the fitting zoom on unusable sizes', () => {
    expect(homeZoom({ fitZoom: 3, containerWidth: 0, imagePxPerUnit: 64 })).toBe(3);
    expect(homeZoom({ fitZoom: 3, containerWidth: 100, imagePxPerUnit: Number.NaN })).toBe(3);
  });
});
