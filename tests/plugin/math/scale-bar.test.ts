import { describe, expect, it } from 'vitest';
import { chooseScaleBar, roundDown125 } from '../../../plugin/src/math/scale-bar';

describe('roundDown125', () => {
  it('gives 1, 2 or 5 × 10^k at most x', () => {
    expect([0.9, 1, 1.99, 2, 4.99, 5, 9.99, 10, 1000, 0.0031].map(roundDown125))
      .toEqual([0.5, 1, 1, 2, 2, 5, 5, 10, 1000, 0.002]);
  });
});

describe('chooseScaleBar', () => {
  it('picks a round length whose bar is length / scale × screen px per image px', () => {
    // 0.05 mm per image px, 2 screen px per image px: 160 px = 4 mm → 2 mm, 80 px
    const bar = chooseScaleBar(0.05, 'mm', 2, 160);
    expect(bar).toEqual({ value: 2, unit: 'mm', label: '2 mm', px: 80 });
  });

  it('switches to cm and m for long lengths, and fits within maxPx', () => {
    for (const [perImage, label] of [[0.5, '2 cm'], [0.05, '20 cm'], [0.005, '2 m'], [0.002, '10 m']] as const) {
      const bar = chooseScaleBar(0.1, 'mm', perImage, 200);
      expect(bar?.label).toBe(label);
      const mm = (bar?.value ?? 0) * { mm: 1, cm: 10, m: 1000 }[bar?.unit as 'mm'];
      expect(bar?.px).toBeCloseTo((mm / 0.1) * perImage, 9);
      expect(bar?.px).toBeLessThanOrEqual(200);
      expect(bar?.px).toBeGreaterThan(200 / 5 - 1e-9); // 1-2-5 steps: never below maxPx / 2.5
    }
  });

  it('reads cm and inch services, inches in inches', () => {
    expect(chooseScaleBar(0.01, 'cm', 1, 150)?.label).toBe('1 cm'); // 0.1 mm/px: 150 px = 15 mm
    const inch = chooseScaleBar(0.001, 'in', 1, 150); // 150 px = 0.15 in
    expect(inch?.label).toBe('0.1 in');
    expect(inch?.px).toBeCloseTo(100, 9);
    expect(chooseScaleBar(0.01, 'in', 1, 150)?.label).toBe('1 in');
  });

  it('small lengths stay in mm', () => {
    expect(chooseScaleBar(0.001, 'mm', 4, 100)?.label).toBe('0.02 mm');
  });

  it('gives null for bad input', () => {
    expect(chooseScaleBar(0, 'mm', 1, 100)).toBeNull();
    expect(chooseScaleBar(0.1, 'mm', Number.NaN, 100)).toBeNull();
    expect(chooseScaleBar(0.1, 'mm', 1, 0)).toBeNull();
  });
});
