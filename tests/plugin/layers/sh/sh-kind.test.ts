import { describe, expect, it } from 'vitest';
import { U_HSH_NORMAL_INV, U_HSH_NORMAL_WEIGHTS } from '../../../../plugin/src/gl/uniforms';
import { parseRelightService, type RelightLayer } from '../../../../plugin/src/iiif/relight-service';
import { HSH_FRAGMENT_BODY } from '../../../../plugin/src/layers/hsh/hsh.frag';
import { LAYER_KINDS, layerKindOf, shadingClass } from '../../../../plugin/src/layers/layer-kinds';
import { resolveLayer } from '../../../../plugin/src/layers/resolved-layer';
import { SH_FRAGMENT_BODY } from '../../../../plugin/src/layers/sh/sh.frag';
import { hshNormalInverse } from '../../../../plugin/src/math/hsh-basis';
import { lightFromProjection } from '../../../../plugin/src/math/light';
import { shNormalWeights, shWeights } from '../../../../plugin/src/math/sh-basis';

function shBlock(terms: unknown, groups: number): Record<string, unknown> {
  return {
    type: 'LanternaRelight', profile: 'urn:lanterna:relight:1', layerType: 'sh', width: 4, height: 4, terms,
    planes: Array.from({ length: groups }, (_, k) => ({
      service: { id: `http://h/i${k}` }, channels: [`R${k}`, `G${k}`, `B${k}`], scale: [1, 1, 1], bias: [0, 0, 0],
    })),
  };
}

const sh = (terms: 4 | 9): RelightLayer => parseRelightService(shBlock(terms, terms));

describe('an sh layer block', () => {
  it('is parsed with its terms and HSH\'s channel layout', () => {
    const layer = sh(9);
    expect([layer.layerType, layer.terms, layer.colorspace]).toEqual(['sh', 9, 'rgb']);
    expect(layer.planes.map((p) => p.channels)).toEqual(Array.from({ length: 9 }, (_, k) => [`R${k}`, `G${k}`, `B${k}`]));
  });

  it('is refused with a one-line message for other term counts, a wrong group count or a colour space', () => {
    expect(() => parseRelightService(shBlock(16, 16))).toThrow(/^sh terms must be 4 or 9, got 16$/);
    expect(() => parseRelightService(shBlock(undefined, 4))).toThrow(/^sh terms must be 4 or 9, got undefined$/);
    expect(() => parseRelightService(shBlock(9, 4))).toThrow(/^sh9 needs 9 plane groups, got 4$/);
    expect(() => parseRelightService({ ...shBlock(4, 4), colorspace: 'lrgb' })).toThrow(/sh layer must have colorspace rgb/);
  });
});

describe('the sh kinds', () => {
  it('are chosen by the terms, shade in their own column with HSH\'s modes', () => {
    expect(layerKindOf(sh(4)).name).toBe('sh4');
    expect(layerKindOf(sh(9)).name).toBe('sh9');
    expect(shadingClass(sh(9))).toBe('sh');
    expect(LAYER_KINDS.sh9.modes).toBe(LAYER_KINDS.hsh9.modes);
    expect(resolveLayer(sh(4)).program.key).toBe('sh4');
  });

  it('give the light its SH weights and the normal estimate the SH weights of the three lights', () => {
    const light = lightFromProjection(-0.4, 0.25);
    for (const [name, terms] of [['sh4', 4], ['sh9', 9]] as const) {
      const kind = LAYER_KINDS[name];
      expect(Array.from(kind.weights?.(light) ?? [])).toEqual(Array.from(shWeights(-0.4, 0.25, terms)));
      expect(kind.glsl.defines).toEqual({ TERMS: terms });
      const uniforms = kind.uniforms(sh(terms));
      expect(Array.from(uniforms[U_HSH_NORMAL_WEIGHTS] ?? [])).toEqual(Array.from(Float32Array.from(shNormalWeights(terms))));
      expect(Array.from(uniforms[U_HSH_NORMAL_INV] ?? [])).toEqual(Array.from(Float32Array.from(hshNormalInverse())));
    }
  });

  it('use HSH\'s program body with the SH basis in place of the hemispherical one', () => {
    expect(SH_FRAGMENT_BODY).toContain('w[8] = 0.546274 * (l.x * l.x - l.y * l.y);');
    expect(SH_FRAGMENT_BODY).not.toContain('acos');
    expect(HSH_FRAGMENT_BODY).toContain('acos');
    const tail = (body: string): string => body.slice(body.indexOf('vec3 lt_raw()'));
    expect(tail(SH_FRAGMENT_BODY)).toBe(tail(HSH_FRAGMENT_BODY));
    // one fetch per plane group for the colour: the loop runs over TERMS planes
    expect(SH_FRAGMENT_BODY.match(/lanterna_plane\(k\)/g)).toHaveLength(3);
  });
});
