import { describe, expect, it } from 'vitest';
import {
  lightAngles, lightFromAngles, lightFromPointer, lightFromProjection, nudgeLight, OVERHEAD_LIGHT,
} from '../../../plugin/src/math/light';

describe('lightFromPointer', () => {
  it('maps the element centre to the overhead light', () => {
    const l = lightFromPointer(320, 240, 640, 480);
    expect(l.lu).toBe(0);
    expect(l.lv).toBe(0);
    expect(l.lz).toBe(1);
  });
  it('puts the right edge at lu > 0 and the top edge at lv > 0', () => {
    expect(lightFromPointer(640, 240, 640, 480).lu).toBe(1);
    expect(lightFromPointer(0, 240, 640, 480).lu).toBe(-1);
    expect(lightFromPointer(320, 0, 640, 480).lv).toBe(1);
    expect(lightFromPointer(320, 480, 640, 480).lv).toBe(-1);
    const q = lightFromPointer(480, 120, 640, 480);
    expect(q.lu).toBe(0.5);
    expect(q.lv).toBe(0.5);
    expect(q.lz).toBeCloseTo(Math.sqrt(0.5), 12);
  });
  it('clamps corners to the unit circle, keeping the direction', () => {
    const l = lightFromPointer(640, 0, 640, 480);
    expect(Math.hypot(l.lu, l.lv)).toBeCloseTo(1, 12);
    expect(l.lu).toBeCloseTo(Math.SQRT1_2, 12);
    expect(l.lv).toBeCloseTo(Math.SQRT1_2, 12);
    expect(l.lz).toBeCloseTo(0, 6);
  });
  it('clamps positions outside the element', () => {
    const l = lightFromPointer(-1000, 240, 640, 480);
    expect(l.lu).toBe(-1);
    expect(l.lv).toBe(0);
  });
  it('returns the overhead light for an empty element', () => {
    expect(lightFromPointer(1, 1, 0, 0)).toEqual(OVERHEAD_LIGHT);
  });
});

describe('lightFromProjection', () => {
  it('keeps points inside the disk and completes lz', () => {
    const l = lightFromProjection(0.6, 0);
    expect(l.lu).toBe(0.6);
    expect(l.lz).toBeCloseTo(0.8, 12);
  });
  it('treats NaN as 0', () => {
    expect(lightFromProjection(Number.NaN, 0.5).lu).toBe(0);
  });
});

describe('nudgeLight', () => {
  it('moves right, up, and stays in the disk', () => {
    expect(nudgeLight(OVERHEAD_LIGHT, 'right', 0.1).lu).toBeCloseTo(0.1, 12);
    expect(nudgeLight(OVERHEAD_LIGHT, 'up', 0.1).lv).toBeCloseTo(0.1, 12);
    expect(nudgeLight(OVERHEAD_LIGHT, 'down', 0.1).lv).toBeCloseTo(-0.1, 12);
    const edge = nudgeLight(lightFromProjection(1, 0), 'right', 0.5);
    expect(edge.lu).toBe(1);
  });
});

describe('lightAngles and lightFromAngles', () => {
  it('reads compass bearings: north up, east right, clockwise', () => {
    const cases: [number, number, number][] = [[0, 1, 0], [1, 0, 90], [0, -1, 180], [-1, 0, 270],
      [Math.SQRT1_2, Math.SQRT1_2, 45], [-Math.SQRT1_2, Math.SQRT1_2, 315]];
    for (const [lu, lv, azimuth] of cases) {
      const a = lightAngles(lightFromProjection(lu, lv));
      expect(a.azimuthDeg).toBeCloseTo(azimuth, 9);
      expect(a.elevationDeg).toBeCloseTo(0, 5); // on the unit circle: grazing light
    }
  });

  it('gives 90° elevation overhead and the angle above the plane otherwise', () => {
    expect(lightAngles(OVERHEAD_LIGHT)).toEqual({ azimuthDeg: 0, elevationDeg: 90 });
    const l = lightFromProjection(0.5, 0); // lz = √0.75: 30° from the vertical
    expect(lightAngles(l).elevationDeg).toBeCloseTo(60, 9);
    expect(lightAngles(l).azimuthDeg).toBeCloseTo(90, 9);
  });

  it('inverts lightAngles', () => {
    for (const [lu, lv] of [[0.3, 0.4], [-0.7, 0.1], [0.05, -0.9], [-0.2, -0.2], [0.6, 0.8]]) {
      const l = lightFromProjection(lu ?? 0, lv ?? 0);
      const { azimuthDeg, elevationDeg } = lightAngles(l);
      const back = lightFromAngles(azimuthDeg, elevationDeg);
      expect(back.lu).toBeCloseTo(l.lu, 9);
      expect(back.lv).toBeCloseTo(l.lv, 9);
      expect(back.lz).toBeCloseTo(l.lz, 9);
    }
  });

  it('makes the raking presets and clamps the elevation', () => {
    const east = lightFromAngles(90, 30);
    expect(east.lu).toBeCloseTo(Math.cos(Math.PI / 6), 12);
    expect(east.lv).toBeCloseTo(0, 12);
    expect(east.lz).toBeCloseTo(0.5, 9);
    const north = lightFromAngles(0, 0);
    expect([north.lu, north.lv]).toEqual([0, 1]);
    const above = lightFromAngles(200, 120); // elevation clamped to 90°: overhead
    expect(above.lz).toBeCloseTo(1, 12);
    expect(Math.hypot(above.lu, above.lv)).toBeCloseTo(0, 12);
    expect(lightFromAngles(Number.NaN, Number.NaN).lz).toBe(1);
    expect(lightFromAngles(-90, 0).lu).toBeCloseTo(-1, 12); // −90° = 270° (west)
  });
});
