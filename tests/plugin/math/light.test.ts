import { describe, expect, it } from 'vitest';
import { lightFromPointer, lightFromProjection, nudgeLight, OVERHEAD_LIGHT } from '../../../plugin/src/math/light';

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
