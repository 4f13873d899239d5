import { describe, expect, it } from 'vitest';
import {
  imageRectToViewport, isViewport, sameViewport, viewportToImageRect,
} from '../../../plugin/src/mirador/viewport-map';

const canvas = { width: 900, height: 700 };

describe('Mirador viewport ↔ Lanterna image rectangle', () => {
  it('reads Mirador\'s viewport as a centre and 1 / the view width in canvas pixels', () => {
    // the whole canvas width in a 3:2 viewer: centre (450, 350), 900 px wide, 600 px high
    const rect = viewportToImageRect({ x: 450, y: 350, zoom: 1 / 900 }, canvas, canvas, 1.5);
    expect(rect[0]).toBeCloseTo(0, 9);
    expect(rect[1]).toBeCloseTo(50, 9);
    expect(rect[2]).toBeCloseTo(900, 9);
    expect(rect[3]).toBeCloseTo(600, 9);
  });

  it('zooming in twice as much halves the rectangle about the same centre', () => {
    const v = { x: 300, y: 200, zoom: 0.004 };
    const [x, y, w, h] = viewportToImageRect(v, canvas, canvas, 4 / 3);
    const [x2, y2, w2, h2] = viewportToImageRect({ ...v, zoom: v.zoom * 2 }, canvas, canvas, 4 / 3);
    expect(w2).toBeCloseTo(w / 2, 9);
    expect(h2).toBeCloseTo(h / 2, 9);
    expect(x2 + w2 / 2).toBeCloseTo(x + w / 2, 9);
    expect(y2 + h2 / 2).toBeCloseTo(y + h / 2, 9);
  });

  it('goes back and forth without change, also when the image is not the canvas\'s size', () => {
    const image = { width: 1800, height: 1400 };
    for (const v of [{ x: 10, y: 20, zoom: 0.5 }, { x: 450, y: 350, zoom: 1 / 1200 }, { x: -40, y: 900, zoom: 3 }]) {
      const rect = viewportToImageRect(v, canvas, image, 1.25);
      expect(rect[2] / rect[3]).toBeCloseTo(1.25, 9);
      const back = imageRectToViewport(rect, canvas, image);
      expect(back.x).toBeCloseTo(v.x, 9);
      expect(back.y).toBeCloseTo(v.y, 9);
      expect(back.zoom).toBeCloseTo(v.zoom, 12);
      expect(sameViewport(back, v)).toBe(true);
    }
  });

  it('scales image pixels to canvas pixels', () => {
    const back = imageRectToViewport([0, 0, 1800, 1000], canvas, { width: 1800, height: 1400 });
    expect(back.x).toBeCloseTo(450, 9);
    expect(back.zoom).toBeCloseTo(1 / 900, 12);
  });

  it('tells a usable viewport from an unset or broken one', () => {
    expect(isViewport({ x: 1, y: 2, zoom: 0.1 })).toBe(true);
    expect(isViewport(null)).toBe(false);
    expect(isViewport({ x: 1, y: 2 })).toBe(false);
    expect(isViewport({ x: 1, y: 2, zoom: Number.NaN })).toBe(false);
    expect(isViewport({ x: 1, y: 2, zoom: 0 })).toBe(false);
    expect(isViewport({ zoom: 2 })).toBe(false);
  });

  it('calls viewports the same only within the tolerance of the view', () => {
    const v = { x: 450, y: 350, zoom: 1 / 900 };
    expect(sameViewport(v, { ...v, x: v.x + 0.5 })).toBe(true);
    expect(sameViewport(v, { ...v, x: v.x + 5 })).toBe(false);
    expect(sameViewport(v, { ...v, zoom: v.zoom * 1.0005 })).toBe(true);
    expect(sameViewport(v, { ...v, zoom: v.zoom * 2 })).toBe(false);
  });
});
