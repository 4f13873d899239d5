import { describe, expect, it } from 'vitest';
import { brushWidth, PEN_RANGE } from '../../../plugin/src/annotate/pen-width';

describe('brushWidth', () => {
  it('gives mouse and touch the chosen size, whatever they report', () => {
    for (const type of ['mouse', 'touch']) {
      for (const p of [0, 0.5, 1]) {
        expect(brushWidth(8, type, p)).toBe(8);
      }
    }
  });

  it('scales a pen\'s width with its pressure: the size at 0.5, within the range', () => {
    expect(brushWidth(8, 'pen', 0.5)).toBe(8);
    expect(brushWidth(8, 'pen', 1)).toBe(8 * PEN_RANGE[1]);
    expect(brushWidth(8, 'pen', 0.25)).toBe(4);
    expect(brushWidth(8, 'pen', 0.01)).toBe(8 * PEN_RANGE[0]);
    const widths = [0.1, 0.3, 0.6, 0.9].map((p) => brushWidth(10, 'pen', p));
    expect([...widths].sort((a, b) => a - b)).toEqual(widths);
    expect(new Set(widths).size).toBe(4);
  });

  it('falls back to the size for a pen that reports no pressure', () => {
    expect(brushWidth(6, 'pen', 0)).toBe(6);
    expect(brushWidth(6, 'pen', Number.NaN)).toBe(6);
  });
});
