import { describe, expect, it } from 'vitest';
import { isRenderMode, isUnsharpMode, MODE_LABELS, RENDER_MODES } from '../../../plugin/src/render/modes';
import { DEFAULT_RENDER_PARAMS, mergeParams, PARAM_SPECS, relevantParams } from '../../../plugin/src/render/params';
import { boxPasses, boxPassReference, F3, F5, modeFilter } from '../../../plugin/src/render/filter-plan';

describe('render modes', () => {
  it('knows mode names, labels and the unsharp family', () => {
    expect(isRenderMode('specular')).toBe(true);
    expect(isRenderMode('Specular')).toBe(false);
    expect(isRenderMode(3)).toBe(false);
    expect(RENDER_MODES.filter(isUnsharpMode)).toEqual(
      ['unsharpNormals', 'unsharpCoefficients', 'unsharpLuminance', 'unsharpImage']);
    expect(Object.keys(MODE_LABELS)).toEqual([...RENDER_MODES]);
  });
});

describe('render parameters', () => {
  it('has the contract defaults', () => {
    expect(DEFAULT_RENDER_PARAMS).toEqual({
      lightIntensity: 1, gamma: 1, brightness: 0, specKd: 0.4, specKs: 0.7, specExponent: 75, diffuseGain: 2,
      umGain: 1, umKd: 1, umEnv: 0.5,
    });
  });

  it('clamps to the ranges and ignores unknown or non-finite values', () => {
    const p = mergeParams(DEFAULT_RENDER_PARAMS, {
      gamma: 0.01, brightness: 3, specExponent: 500, umGain: 0, lightIntensity: Number.NaN, bogus: 3, umEnv: '1',
    });
    expect(p.gamma).toBe(0.2);
    expect(p.brightness).toBe(1);
    expect(p.specExponent).toBe(150);
    expect(p.umGain).toBe(0.01);
    expect(p.lightIntensity).toBe(1);
    expect(p.umEnv).toBe(0.5);
    expect('bogus' in p).toBe(false);
    expect(mergeParams(p, { gamma: 2.2 }).brightness).toBe(1);
    for (const spec of Object.values(PARAM_SPECS)) {
      expect(spec.min).toBeLessThanOrEqual(spec.default);
      expect(spec.default).toBeLessThanOrEqual(spec.max);
    }
  });

  it('lists the sliders a mode needs', () => {
    expect(relevantParams('color', 'ptm-lrgb')).toEqual(['lightIntensity', 'gamma', 'brightness']);
    expect(relevantParams('color', 'flat')).toEqual(['gamma', 'brightness']);
    expect(relevantParams('normals', 'hsh')).toEqual(['gamma', 'brightness']);
    expect(relevantParams('specular', 'svbrdf')).toEqual(
      ['lightIntensity', 'specKd', 'specKs', 'specExponent', 'gamma', 'brightness']);
    expect(relevantParams('unsharpNormals', 'hsh')).toEqual(
      ['lightIntensity', 'umGain', 'umKd', 'umEnv', 'gamma', 'brightness']);
    expect(relevantParams('unsharpImage', 'flat')).toEqual(['umGain', 'gamma', 'brightness']);
    expect(relevantParams('diffuseGain', 'ptm-rgb')).toContain('diffuseGain');
  });
});

describe('screen-space filter plan', () => {
  it('uses F3 for coefficients and F5 for the others', () => {
    expect(modeFilter('unsharpCoefficients')).toBe(F3);
    expect(modeFilter('unsharpLuminance')).toBe(F5);
    expect(modeFilter('unsharpNormals')).toBe(F5);
    expect(modeFilter('unsharpImage')).toBe(F5);
    expect(modeFilter('specular')).toBeNull();
  });

  it('alternates horizontal and vertical passes', () => {
    expect(boxPasses(F3)).toEqual([
      { axis: 'x', radius: 1 }, { axis: 'y', radius: 1 }, { axis: 'x', radius: 1 }, { axis: 'y', radius: 1 }]);
    const f5 = boxPasses(F5);
    expect(f5).toHaveLength(10);
    expect(f5.every((p) => p.radius === 2)).toBe(true);
  });

  it('box pass: mean over 2r+1 taps, clamped to the edge', () => {
    const src = Float32Array.of(0, 3, 6, 9, 12);
    expect(Array.from(boxPassReference(src, 5, 1, { axis: 'x', radius: 1 }))).toEqual([1, 3, 6, 9, 11]);
    const want = [(0 + 0 + 0 + 3 + 6) / 5, (0 + 0 + 3 + 6 + 9) / 5, 6, (3 + 6 + 9 + 12 + 12) / 5, (6 + 9 + 12 + 12 + 12) / 5];
    expect(Array.from(boxPassReference(src, 1, 5, { axis: 'y', radius: 2 }))).toEqual(want.map(Math.fround));
  });

  it('a constant image is unchanged (so an unsharp mode changes nothing where q is flat)', () => {
    const src = new Float32Array(12).fill(0.25);
    let img: Float32Array = src;
    for (const pass of boxPasses(F5)) {
      img = boxPassReference(img, 4, 3, pass);
    }
    expect(Array.from(img)).toEqual(Array.from(src));
  });
});
