import { describe, expect, it } from 'vitest';
import {
  MAX_PLANES, U_BIAS, U_GLOSS_LIMITS, U_HALF, U_HSH_NORMAL_INV, U_HSH_NORMAL_WEIGHTS, U_LIGHT, U_PARAM,
  U_PCA_ALBEDO_WEIGHTS, U_PCA_NORMAL_WEIGHTS, U_PCA_WEIGHTS, U_SCALE, U_WEIGHTS,
} from '../../../plugin/src/gl/uniforms';
import { DEFAULT_RENDER_PARAMS, type RenderParams } from '../../../plugin/src/render/params';
import { parseRelightService, type RelightLayer } from '../../../plugin/src/iiif/relight-service';
import { layerUniforms } from '../../../plugin/src/layers/layer-uniforms';
import { resolveLayer } from '../../../plugin/src/layers/resolved-layer';
import { hshNormalInverse } from '../../../plugin/src/math/hsh-basis';
import { lightFromProjection } from '../../../plugin/src/math/light';
import { pcaAlbedoWeights, pcaNormalWeights, pcaPlaneWeights } from '../../../plugin/src/math/pca-weights';
import { pcaBlock, relightBlock } from '../fixtures';

/** The uniforms of `layer` under the light (lu, lv), resolved and clamped as the drawer does. */
function uniformsOf(layer: RelightLayer, lu: number, lv: number, params?: RenderParams) {
  return layerUniforms(resolveLayer(layer), lightFromProjection(lu, lv), params);
}

describe('layerUniforms', () => {
  const layer = parseRelightService(relightBlock());

  it('packs scale and bias per plane group, padded to MAX_PLANES', () => {
    const u = uniformsOf(layer, 0, 0);
    expect(u[U_SCALE]).toHaveLength(MAX_PLANES * 3);
    expect(Array.from(u[U_SCALE].slice(0, 9))).toEqual([2, 2, 2, 2, 2, 0, 1, 1, 1]);
    expect(u[U_BIAS][0]).toBeCloseTo(0.627, 6);
    expect(u[U_BIAS][3]).toBeCloseTo(0.498, 6);
    expect(u[U_BIAS][5]).toBe(0);
    expect(Array.from(u[U_SCALE].slice(9))).toEqual(new Array(MAX_PLANES * 3 - 9).fill(0));
  });

  it('passes the PTM weights for the light', () => {
    const u = uniformsOf(layer, 0.5, -0.5);
    expect(Array.from(u[U_WEIGHTS])).toEqual([0.25, 0.25, -0.25, 0.5, -0.5, 1, ...(new Array(10).fill(0) as number[])]);
  });

  it('gives an image layer no basis weights', () => {
    const image = parseRelightService({
      type: 'LanternaRelight', profile: 'urn:lanterna:relight:1', layerType: 'image', colorspace: 'rgb',
      width: 4, height: 4,
      planes: [{ service: { id: 'http://h/i' }, channels: ['R', 'G', 'B'], scale: [1, 1, 1], bias: [0, 0, 0] }],
    });
    expect(Array.from(uniformsOf(image, 0.5, 0.5)[U_WEIGHTS])).toEqual(new Array(16).fill(0));
  });

  it('repeats a single-band group\'s scale and bias, and indexes svbrdf maps', () => {
    const plane = (id: string, channels: string[], scale: number[], bias: number[]) => (
      { service: { id }, channels, scale, bias });
    const sv = parseRelightService({
      type: 'LanternaRelight', profile: 'urn:lanterna:relight:1', layerType: 'svbrdf', width: 4, height: 4,
      inputColorSpace: 'srgb', glossLimits: [0.05, 0.3],
      planes: [plane('k', ['KD_R', 'KD_G', 'KD_B'], [1, 1, 1], [0, 0, 0]), plane('g', ['GLOSS'], [0.5], [0.25]),
        plane('n', ['NX', 'NY', 'NZ'], [2, 2, 2], [0.5, 0.5, 0.5])],
    });
    const u = uniformsOf(sv, 0, 0);
    expect(Array.from(u[U_SCALE].slice(3, 6))).toEqual([0.5, 0.5, 0.5]);
    expect(Array.from(u[U_BIAS].slice(3, 6))).toEqual([0.25, 0.25, 0.25]);
    expect(resolveLayer(sv).program.defines).toEqual({
      SV_NORMALS: 2, SV_KD: 0, SV_KS: -1, SV_GLOSS: 1, SV_SRGB: 1, SV_DISPLAY: 0,
    });
    expect(Array.from(u[U_GLOSS_LIMITS] as Float32Array)).toEqual([Math.fround(0.05), Math.fround(0.3)]);
  });

  it('passes the light, the half vector and the parameters', () => {
    const u = uniformsOf(layer, 0.6, 0, { ...DEFAULT_RENDER_PARAMS, gamma: 2.2 });
    expect(Array.from(u[U_LIGHT]).map((x) => +x.toFixed(6))).toEqual([0.6, 0, 0.8]);
    const h = Array.from(u[U_HALF]);
    expect(Math.hypot(...h)).toBeCloseTo(1, 6);
    expect(h[0] / h[2]).toBeCloseTo(0.6 / 1.8, 6);
    expect(u[U_PARAM.gamma]).toBe(2.2);
    expect(u[U_PARAM.specExponent]).toBe(75);
  });

  it('gives an hsh layer its light weights', () => {
    const planes = Array.from({ length: 9 }, (_, k) => ({
      service: { id: `t${k}` }, channels: [`R${k}`, `G${k}`, `B${k}`], scale: [1, 1, 1], bias: [0, 0, 0] }));
    const hsh = parseRelightService({
      type: 'LanternaRelight', profile: 'urn:lanterna:relight:1', layerType: 'hsh', terms: 9, width: 4, height: 4, planes,
    });
    const u = uniformsOf(hsh, 0, 0);
    const w = u[U_WEIGHTS];
    expect(w[0]).toBeCloseTo(1 / Math.sqrt(2 * Math.PI), 6);
    expect(w[9]).toBe(0);
    expect(u[U_HSH_NORMAL_WEIGHTS]).toHaveLength(48);
  });
});

describe('the uniforms of a PCA layer', () => {
  const rbf = parseRelightService(pcaBlock('rbf', 4));
  const basis = rbf.pca;

  it('sizes its program by the plane groups, and fixes the normal-light weights per layer', () => {
    const resolved = resolveLayer(rbf);
    expect(resolved.program.key).toBe('pca,PCA_GROUPS=2,PCA_SLOTS=7');
    expect(resolved.uniforms[U_PCA_NORMAL_WEIGHTS]).toEqual(basis && pcaNormalWeights(basis, 7));
    expect(resolved.uniforms[U_PCA_ALBEDO_WEIGHTS]).toEqual(basis && pcaAlbedoWeights(basis, 7));
    expect(Array.from(resolved.uniforms[U_HSH_NORMAL_INV] ?? [])).toEqual(Array.from(Float32Array.from(hshNormalInverse())));
  });

  it('sends the light\'s plane weights each frame, and changes them with the light', () => {
    const a = uniformsOf(rbf, 0.3, -0.2)[U_PCA_WEIGHTS];
    const b = uniformsOf(rbf, -0.5, 0.1)[U_PCA_WEIGHTS];
    expect(a).toEqual(basis && pcaPlaneWeights(basis, 0.3, -0.2, 7));
    expect(a).toHaveLength(21);
    expect(Array.from(a as Float32Array)).not.toEqual(Array.from(b as Float32Array));
    // the PTM/HSH basis weights stay zero
    expect(Array.from(uniformsOf(rbf, 0.3, -0.2)[U_WEIGHTS])).toEqual(new Array(16).fill(0));
  });
});
