import { describe, expect, it } from 'vitest';
import { MAX_PLANES, U_BIAS, U_SCALE, U_WEIGHTS } from '../../plugin/src/gl/uniforms';
import { parseRelightService } from '../../plugin/src/iiif/relight-service';
import { layerUniforms } from '../../plugin/src/layers/layer-uniforms';
import { relightBlock } from './fixtures';

describe('layerUniforms', () => {
  const layer = parseRelightService(relightBlock());

  it('packs scale and bias per plane group, padded to MAX_PLANES', () => {
    const u = layerUniforms(layer, 0, 0);
    expect(u[U_SCALE]).toHaveLength(MAX_PLANES * 3);
    expect(Array.from(u[U_SCALE].slice(0, 9))).toEqual([2, 2, 2, 2, 2, 0, 1, 1, 1]);
    expect(u[U_BIAS][0]).toBeCloseTo(0.627, 6);
    expect(u[U_BIAS][3]).toBeCloseTo(0.498, 6);
    expect(u[U_BIAS][5]).toBe(0);
    expect(Array.from(u[U_SCALE].slice(9))).toEqual(new Array(MAX_PLANES * 3 - 9).fill(0));
  });

  it('passes the PTM weights for the light', () => {
    const u = layerUniforms(layer, 0.5, -0.5);
    expect(Array.from(u[U_WEIGHTS])).toEqual([0.25, 0.25, -0.25, 0.5, -0.5, 1]);
  });

  it('gives an image layer no basis weights', () => {
    const image = parseRelightService({
      type: 'LanternaRelight', profile: 'urn:lanterna:relight:1', layerType: 'image', colorspace: 'rgb',
      width: 4, height: 4,
      planes: [{ service: { id: 'http://h/i' }, channels: ['R', 'G', 'B'], scale: [1, 1, 1], bias: [0, 0, 0] }],
    });
    expect(Array.from(layerUniforms(image, 0.5, 0.5)[U_WEIGHTS])).toEqual([0, 0, 0, 0, 0, 0]);
  });
});
