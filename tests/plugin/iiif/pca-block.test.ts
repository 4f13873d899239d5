import { describe, expect, it } from 'vitest';
import { RelightServiceError } from '../../../plugin/src/iiif/errors';
import { pcaChannelNames } from '../../../plugin/src/iiif/pca-block';
import { parseRelightService } from '../../../plugin/src/iiif/relight-service';
import { applicableModes, layerKindOf } from '../../../plugin/src/layers/layer-kinds';
import { pcaWeights } from '../../../plugin/src/math/pca-weights';
import { pcaBlock } from '../fixtures';

const message = (block: unknown): string => {
  try {
    parseRelightService(block);
  } catch (e) {
    expect(e).toBeInstanceOf(RelightServiceError);
    return (e as Error).message;
  }
  throw new Error('expected a RelightServiceError');
};

describe('a PCA relight block (rbf, bilinear)', () => {
  it('names its plane channels P0… and pads the last group with X channels', () => {
    expect(pcaChannelNames(4)).toEqual([['P0', 'P1', 'P2'], ['P3', 'X4', 'X5']]);
    expect(pcaChannelNames(27)).toHaveLength(9);
  });

  it('is parsed into its decoded basis and kind', () => {
    const rbf = parseRelightService(pcaBlock('rbf', 4));
    expect(rbf.layerType).toBe('rbf');
    expect(rbf.pca?.ndimensions).toBe(5);
    expect(rbf.pca?.values).toHaveLength(5 * 5 * 3);
    expect(rbf.pca?.values[0]).toBeCloseTo(0, 12); // byte 0 of the mean: 0/255
    expect(rbf.pca?.values[5 * 3 + 1]).toBeCloseTo((((16 * 37) % 256) - 127) / 1, 12); // plane 0, sample 0, G
    expect(layerKindOf(rbf).name).toBe('rbf');
    expect(applicableModes(rbf)).toEqual(['color', 'normals', 'albedo', 'diffuse', 'achromatic', 'specular',
      'unsharpNormals', 'unsharpCoefficients', 'unsharpImage']);
    const bilinear = parseRelightService(pcaBlock('bilinear', 3, { colorspace: 'mycc', yccplanes: [1, 1, 1] }));
    expect(bilinear.pca?.ndimensions).toBe(9);
    expect(bilinear.pca?.colorspace).toBe('mycc');
    expect(layerKindOf(bilinear).name).toBe('bilinear');
    expect(bilinear.pca && pcaWeights(bilinear.pca, 0.1, 0.2).every(Number.isFinite)).toBe(true);
  });

  it.each([
    [{ basis: new Array(6 * 5 * 3 - 1).fill(0) }, 'coin.basis: 89 values, expected 90'],
    [{ basis: [...new Array<number>(89).fill(0), 256] }, 'coin.basis[89] must be an integer in 0..255, got 256'],
    [{ range: [1, 2, 0, 4, 5] }, 'coin.range[2] must be a number > 0, got 0'],
    [{ range: [1, 2] }, 'coin.range: 2 values, expected 5'],
    [{ colorspace: 'ycc' }, 'coin.colorspace: unsupported colour space "ycc" for rbf (mrgb, mycc)'],
    [{ nplanes: 49 }, 'coin.nplanes must be an integer in 1..48, got 49'],
    [{ nplanes: 2.5 }, 'coin.nplanes must be an integer in 1..48, got 2.5'],
    [{ sigma: 0 }, 'coin.sigma must be a number > 0, got 0'],
    [{ lights: [0, 0] }, 'coin.lights must be a non-empty array of D·3 numbers, got [0,0]'],
    [{ lights: [0, 0, 1, 0, 'x', 1] }, 'coin.lights[4] must be a finite number, got "x"'],
    [{ colorspace: 'mycc', yccplanes: [2, 2, 2] }, 'coin.yccplanes must be [ny, nc, nc] with ny >= 1 and ny + 2·nc = nplanes (5), got [2,2,2]'],
    [{ colorspace: 'mycc', yccplanes: [3, 1, 0] }, 'coin.yccplanes must be [ny, nc, nc] with ny >= 1 and ny + 2·nc = nplanes (5), got [3,1,0]'],
    [{ colorspace: 'mycc' }, 'coin.yccplanes must be an array of 3 values, got nothing'],
  ])('refuses %j with a one-line error naming the field', (extra, expected) => {
    expect(message(pcaBlock('rbf', 5, extra))).toBe(expected);
  });

  it('refuses a bilinear block without a grid, and planes that do not match nplanes', () => {
    expect(message(pcaBlock('bilinear', 3, { resolution: 1 }))).toBe('coin.resolution must be an integer in 2..256, got 1');
    const block = pcaBlock('rbf', 4);
    const planes = block.planes as Record<string, unknown>[];
    expect(message({ ...block, planes: planes.slice(0, 1) })).toBe('rbf with 4 planes needs 2 plane groups, got 1');
    expect(message({ ...block, nplanes: 6, range: [1, 1, 1, 1, 1, 1], basis: new Array(7 * 5 * 3).fill(0) }))
      .toBe('plane 1: channels must be ["P3","P4","P5"], got ["P3","X4","X5"]');
  });
});
