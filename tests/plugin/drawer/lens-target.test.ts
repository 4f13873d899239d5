import { describe, expect, it } from 'vitest';
import { scissorBox } from '../../../plugin/src/drawer/lens-target';

describe('scissorBox', () => {
  it('bounds the circle with a 1 px margin, in whole device pixels', () => {
    expect(scissorBox({ x: 100.5, y: 80.25, radius: 20 }, 640, 480)).toEqual([79, 59, 43, 43]);
  });

  it('is clamped to the canvas, and empty when the lens is off-canvas', () => {
    expect(scissorBox({ x: 5, y: 470, radius: 30 }, 640, 480)).toEqual([0, 439, 36, 41]);
    expect(scissorBox({ x: -100, y: 50, radius: 10 }, 640, 480)).toEqual([0, 39, 0, 22]);
  });
});
