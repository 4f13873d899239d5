import { describe, expect, it } from 'vitest';
import { initialLens, LensOptionError, updateLens } from '../../../plugin/src/lens/lens-state';
import { MIN_LENS_RADIUS } from '../../../plugin/src/math/lens';

describe('lens state', () => {
  it('starts off, centred, with a fifth of the short side as radius', () => {
    const s = initialLens(640, 480);
    expect(s.enabled).toBe(false);
    expect(s.center).toEqual([320, 240]);
    expect(s.radius).toBe(96);
    expect(s.opacity).toBe(1);
    expect(s.annotations).toBe('everywhere');
  });

  it('updates only the given fields, clamping opacity and radius, merging params', () => {
    const s = updateLens(initialLens(640, 480), { enabled: true, opacity: 3, radius: 1, params: { gamma: 2 } });
    expect(s.enabled).toBe(true);
    expect(s.opacity).toBe(1);
    expect(s.radius).toBe(MIN_LENS_RADIUS);
    expect(s.params.gamma).toBe(2);
    expect(s.center).toEqual([320, 240]);
    const t = updateLens(s, { opacity: -1, params: { diffuseGain: 1.5 } });
    expect(t.opacity).toBe(0);
    expect(t.params.gamma).toBe(2);
  });

  it('rejects a malformed centre and an unknown annotation display', () => {
    const s = initialLens(640, 480);
    expect(() => updateLens(s, { center: [1, Number.NaN] })).toThrow(LensOptionError);
    expect(() => updateLens(s, { center: [1] as unknown as [number, number] })).toThrow(LensOptionError);
    expect(() => updateLens(s, { annotations: 'above' as 'inside' })).toThrow(/everywhere, inside, outside/);
  });
});
