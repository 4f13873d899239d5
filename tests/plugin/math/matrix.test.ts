import { describe, expect, it } from 'vitest';
import { modelMatrix, multiply, rotationAbout, transformPoint, viewMatrix } from '../../../plugin/src/math/matrix';

describe('tile matrices', () => {
  const bounds = { x: 0.25, y: 0.1, width: 0.5, height: 0.375 };
  const view = viewMatrix(bounds);

  it('maps the visible viewport rectangle onto clip space, y up', () => {
    const [x0, y0] = transformPoint(view, 0.25, 0.1);
    expect(x0).toBeCloseTo(-1, 12);
    expect(y0).toBeCloseTo(1, 12);
    const [x, y] = transformPoint(view, 0.75, 0.475);
    expect(x).toBeCloseTo(1, 12);
    expect(y).toBeCloseTo(-1, 12);
  });

  it('maps a tile quad to its rectangle', () => {
    const tile = { x: 0.5, y: 0.2, width: 0.125, height: 0.0625 };
    const m = multiply(view, modelMatrix(tile));
    const [x0, y0] = transformPoint(m, 0, 0);
    const [ex, ey] = transformPoint(view, 0.5, 0.2);
    expect(x0).toBeCloseTo(ex, 12);
    expect(y0).toBeCloseTo(ey, 12);
    const [x1, y1] = transformPoint(m, 1, 1);
    const [fx, fy] = transformPoint(view, 0.625, 0.2625);
    expect(x1).toBeCloseTo(fx, 12);
    expect(y1).toBeCloseTo(fy, 12);
  });

  it('mirrors a flipped tile', () => {
    const m = modelMatrix({ x: 1, y: 2, width: 3, height: 4 }, true);
    expect(transformPoint(m, 0, 0)).toEqual([4, 2]);
    expect(transformPoint(m, 1, 1)).toEqual([1, 6]);
  });

  it('mirrors the view when flipped and rotates about the centre', () => {
    const f = viewMatrix(bounds, 0, true);
    expect(transformPoint(f, 0.25, 0.1)[0]).toBeCloseTo(1, 12);
    const r = viewMatrix({ x: -1, y: -1, width: 2, height: 2 }, Math.PI / 2);
    const [x, y] = transformPoint(r, 1, 0);
    expect(Math.abs(x) + Math.abs(y)).toBeCloseTo(1, 12);
    expect(x).toBeCloseTo(0, 12);
  });
});

describe('rotationAbout', () => {
  it('keeps the centre fixed and turns a point about it by the item rotation', () => {
    const m = rotationAbout(90, { x: 1, y: 1 });
    const [cx, cy] = transformPoint(m, 1, 1);
    expect(cx).toBeCloseTo(1, 12);
    expect(cy).toBeCloseTo(1, 12);
    const [x, y] = transformPoint(m, 2, 1);
    expect(x).toBeCloseTo(1, 12);
    expect(y).toBeCloseTo(0, 12);
  });

  it('is the identity for a full turn', () => {
    rotationAbout(360, { x: 0.3, y: 0.7 }).forEach((v, i) => {
      expect(v).toBeCloseTo([1, 0, 0, 0, 1, 0, 0, 0, 1][i] ?? NaN, 12);
    });
  });
});
