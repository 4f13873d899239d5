import { readFileSync } from 'node:fs';
import { describe, expect, it } from 'vitest';
import { U_GLOSS_LIMITS, U_HSH_NORMAL_INV, U_HSH_NORMAL_WEIGHTS } from '../../../plugin/src/gl/uniforms';
import { parseRelightService, type RelightLayer } from '../../../plugin/src/iiif/relight-service';
import {
  applicableModes, LAYER_KINDS, layerKindOf, quantityFacts, shadingClass, type LayerKindName,
} from '../../../plugin/src/layers/layer-kinds';
import { resolveLayer } from '../../../plugin/src/layers/resolved-layer';
import { hshWeights } from '../../../plugin/src/math/hsh-basis';
import { lightFromProjection } from '../../../plugin/src/math/light';
import { ptmWeights } from '../../../plugin/src/math/ptm-basis';
import { RENDER_MODES, type RenderMode, type ShadingClass } from '../../../plugin/src/render/modes';
import { relightBlock } from '../fixtures';

function layer(layerType: string, extra: Record<string, unknown>, groups: string[][]): RelightLayer {
  return parseRelightService({
    type: 'LanternaRelight', profile: 'urn:lanterna:relight:1', layerType, width: 4, height: 4, ...extra,
    planes: groups.map((channels, i) => ({
      service: { id: `http://h/i${i}` }, channels, scale: channels.map(() => 1), bias: channels.map(() => 0),
    })),
  });
}

const hshGroups = (n: number): string[][] => Array.from({ length: n }, (_, k) => [`R${k}`, `G${k}`, `B${k}`]);
const lrgb = parseRelightService(relightBlock());
const rgb = layer('ptm', { colorspace: 'rgb', basis: ['lu2', 'lv2', 'lulv', 'lu', 'lv', '1'] },
  ['R', 'G', 'B'].flatMap((c) => [[`${c}0`, `${c}1`, `${c}2`], [`${c}3`, `${c}4`, `${c}5`]]));
const hsh = layer('hsh', { terms: 4 }, hshGroups(4));
const shape = layer('svbrdf', {}, [['NX', 'NY', 'NZ']]);
const material = layer('svbrdf', {}, [['KD_R', 'KD_G', 'KD_B'], ['GLOSS']]);
const image = layer('image', {}, [['R', 'G', 'B']]);
const mono = layer('image', {}, [['Y']]);

/** The contract's table (docs/rendering.md, "Modes and where they apply"): the modes of each column. */
function contractTable(): Map<ShadingClass, RenderMode[]> {
  const doc = readFileSync(new URL('../../../docs/rendering.md', import.meta.url), 'utf8');
  const section = doc.split('## Modes and where they apply')[1]?.split('\n## ')[0] ?? '';
  const rows = section.split('\n').filter((line) => line.startsWith('|')).map((line) => line.split('|').slice(1, -1)
    .map((cell) => cell.trim()));
  const [header = [], , ...body] = rows;
  expect(header).toEqual(['mode', 'ptm lrgb', 'ptm rgb', 'hsh', 'sh', 'rbf', 'bilinear', 'svbrdf (with shape)',
    'svbrdf without shape, image']);
  const columns: ShadingClass[] = ['ptm-lrgb', 'ptm-rgb', 'hsh', 'sh', 'rbf', 'bilinear', 'svbrdf', 'flat'];
  const table = new Map(columns.map((c): [ShadingClass, RenderMode[]] => [c, []]));
  for (const [name = '', ...cells] of body) {
    const mode = name.replace(/`/g, '') as RenderMode;
    expect(RENDER_MODES).toContain(mode);
    columns.forEach((c, i) => {
      const cell = cells[i] ?? '';
      expect(cell.startsWith('✓') || cell === '–').toBe(true);
      if (cell.startsWith('✓')) {
        table.get(c)?.push(mode);
      }
    });
  }
  expect(body).toHaveLength(RENDER_MODES.length);
  return table;
}

const KIND_NAMES = Object.keys(LAYER_KINDS) as LayerKindName[];

describe('the layer-kind table', () => {
  it('gives every kind the modes of its column in docs/rendering.md, in menu order', () => {
    const table = contractTable();
    for (const name of KIND_NAMES) {
      const kind = LAYER_KINDS[name];
      expect(kind.name).toBe(name);
      expect([...kind.modes], name).toEqual(table.get(kind.shading));
      expect([...kind.modes], name).toEqual(RENDER_MODES.filter((m) => kind.modes.includes(m)));
    }
    expect(new Set(KIND_NAMES.map((n) => LAYER_KINDS[n].shading))).toEqual(new Set(table.keys()));
  });

  it('says the light applies exactly to the shaded kinds', () => {
    const lit = KIND_NAMES.filter((n) => LAYER_KINDS[n].lit);
    expect(lit).toEqual(['ptm-lrgb', 'ptm-rgb', 'hsh4', 'hsh9', 'hsh16', 'sh4', 'sh9', 'svbrdf', 'rbf', 'bilinear']);
    for (const name of KIND_NAMES) {
      expect(LAYER_KINDS[name].lit, name).toBe(LAYER_KINDS[name].shading !== 'flat');
    }
  });

  it('gives the basis kinds their light weights, and the others none', () => {
    const light = lightFromProjection(0.3, -0.6);
    expect(Array.from(LAYER_KINDS['ptm-lrgb'].weights?.(light) ?? [])).toEqual(Array.from(ptmWeights(0.3, -0.6)));
    expect(Array.from(LAYER_KINDS['ptm-rgb'].weights?.(light) ?? [])).toEqual(Array.from(ptmWeights(0.3, -0.6)));
    for (const [name, terms] of [['hsh4', 4], ['hsh9', 9], ['hsh16', 16]] as const) {
      expect(Array.from(LAYER_KINDS[name].weights?.(light) ?? [])).toEqual(Array.from(hshWeights(0.3, -0.6, terms)));
      expect(LAYER_KINDS[name].glsl.defines).toEqual({ TERMS: terms });
    }
    for (const name of ['svbrdf', 'svbrdf-flat', 'image', 'rbf', 'bilinear'] as const) {
      expect(LAYER_KINDS[name].weights).toBeNull();
    }
    // the PCA kinds' light weights depend on the layer's basis: per-light uniforms instead
    expect(KIND_NAMES.filter((n) => LAYER_KINDS[n].lightUniforms)).toEqual(['rbf', 'bilinear']);
  });

  it('adds each kind\'s own uniforms', () => {
    expect(Object.keys(LAYER_KINDS.hsh9.uniforms(hsh))).toEqual([U_HSH_NORMAL_WEIGHTS, U_HSH_NORMAL_INV]);
    expect(Object.keys(LAYER_KINDS.svbrdf.uniforms(shape))).toEqual([U_GLOSS_LIMITS]);
    expect(Object.keys(LAYER_KINDS['svbrdf-flat'].uniforms(material))).toEqual([U_GLOSS_LIMITS]);
    for (const name of ['ptm-lrgb', 'ptm-rgb', 'image'] as const) {
      expect(LAYER_KINDS[name].uniforms(lrgb)).toEqual({});
    }
  });

  it('shares GLSL only between the svbrdf kinds and the PCA kinds, and previews PTM LRGB from its RGB plane', () => {
    const programs = KIND_NAMES.map((n) => LAYER_KINDS[n].glsl.name);
    expect(programs).toEqual(['ptm-lrgb', 'ptm-rgb', 'hsh4', 'hsh9', 'hsh16', 'sh4', 'sh9', 'svbrdf', 'svbrdf', 'pca',
      'pca', 'image']);
    expect(LAYER_KINDS['svbrdf-flat'].glsl).toBe(LAYER_KINDS.svbrdf.glsl);
    expect(LAYER_KINDS.bilinear.glsl).toBe(LAYER_KINDS.rbf.glsl);
    expect(KIND_NAMES.filter((n) => LAYER_KINDS[n].previewPlane !== 0)).toEqual(['ptm-lrgb']);
    expect(lrgb.planes[LAYER_KINDS['ptm-lrgb'].previewPlane]?.channels).toEqual(['R', 'G', 'B']);
  });
});

describe('a layer\'s kind', () => {
  it('follows the layer type, the PTM colour space, the HSH terms and the svbrdf normal map', () => {
    const layers = [lrgb, rgb, hsh, layer('hsh', { terms: 9 }, hshGroups(9)), layer('hsh', { terms: 16 }, hshGroups(16)),
      shape, material, image, mono];
    expect(layers.map((l) => layerKindOf(l).name)).toEqual(
      ['ptm-lrgb', 'ptm-rgb', 'hsh4', 'hsh9', 'hsh16', 'svbrdf', 'svbrdf-flat', 'image', 'image']);
  });

  it('classifies layers (the public shadingClass)', () => {
    expect([lrgb, rgb, hsh, shape, material, image, mono].map(shadingClass))
      .toEqual(['ptm-lrgb', 'ptm-rgb', 'hsh', 'svbrdf', 'flat', 'flat', 'flat']);
  });

  it('gives PTM LRGB every mode', () => {
    expect(applicableModes(lrgb)).toEqual([...RENDER_MODES]);
  });

  it('follows the table for the other classes', () => {
    expect(applicableModes(rgb)).toEqual(RENDER_MODES.filter((m) => m !== 'unsharpLuminance'));
    expect(applicableModes(hsh)).toEqual(['color', 'normals', 'albedo', 'diffuse', 'achromatic', 'specular',
      'unsharpNormals', 'unsharpCoefficients', 'unsharpImage']);
    expect(applicableModes(shape)).toEqual(['color', 'normals', 'albedo', 'diffuse', 'achromatic', 'specular',
      'unsharpNormals', 'unsharpImage']);
    for (const flat of [material, image, mono]) {
      expect(applicableModes(flat)).toEqual(['color', 'albedo', 'achromatic', 'unsharpImage']);
    }
  });

  it('is resolved with its program: svbrdf programs are keyed by where the maps are', () => {
    expect(resolveLayer(lrgb).program.key).toBe('ptm-lrgb');
    expect(resolveLayer(hsh).program.key).toBe('hsh4');
    expect(resolveLayer(material).program.key)
      .toBe('svbrdf,SV_NORMALS=-1,SV_KD=0,SV_KS=-1,SV_GLOSS=1,SV_SRGB=0,SV_DISPLAY=0');
    expect(resolveLayer(shape).kind).toBe(LAYER_KINDS.svbrdf);
  });
});

describe('the unsharp terms of a kind', () => {
  it('are offered exactly by the kinds whose GLSL filters them, two groups each', () => {
    for (const kind of Object.values(LAYER_KINDS)) {
      const { unsharpTerms } = quantityFacts(kind);
      expect(kind.glsl.body.includes('lt_unsharp_terms'), kind.name).toBe(unsharpTerms > 0);
      expect([0, 2], kind.name).toContain(unsharpTerms);
      if (unsharpTerms > 0) {
        expect(kind.modes).toContain('unsharpCoefficients');
      }
    }
    expect(quantityFacts(LAYER_KINDS['ptm-lrgb']).unsharpTerms).toBe(2);
  });
});
