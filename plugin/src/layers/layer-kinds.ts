/**
 * The layer kinds: one row per kind of relightable layer with everything that differs between
 * kinds — the contract's column and the render modes it supports (`docs/rendering.md`, "Modes and
 * where they apply"), whether the light changes it, its GLSL and its own uniforms.
 *
 * A layer's kind is looked up once, by {@link layerKindOf}, when the layer is set; nothing else
 * branches on `layerType`. Pure: no DOM, no GL.
 */
import { U_GLOSS_LIMITS, U_HSH_NORMAL_INV, U_HSH_NORMAL_WEIGHTS } from '../gl/uniforms';
import { svbrdfMapIndices, type LayerType, type RelightLayer } from '../iiif/relight-service';
import { hshNormalInverse, hshNormalWeights, hshWeights } from '../math/hsh-basis';
import type { Light } from '../math/light';
import { ptmWeights } from '../math/ptm-basis';
import { RENDER_MODES, type RenderMode, type ShadingClass } from '../render/modes';
import type { QuantityFacts } from '../render/quantity-key';
import { HSH_FRAGMENT_BODY } from './hsh/hsh.frag';
import { IMAGE_FRAGMENT_BODY } from './image/image.frag';
import { BILINEAR_KIND } from './bilinear/bilinear-kind';
import { HSH_MODES, type KindGlsl, type KindUniforms, type LayerKind, type LayerKindName } from './kind-types';
import { ptmFragmentBody } from './ptm/ptm.frag';
import { RBF_KIND } from './rbf/rbf-kind';
import { SH4_KIND, SH9_KIND } from './sh/sh-kind';
import { SVBRDF_FRAGMENT_BODY } from './svbrdf/svbrdf.frag';

export type { KindGlsl, KindUniforms, LayerKind, LayerKindName } from './kind-types';

/** The modes of the contract's last column: svbrdf without shape, image. */
const FLAT_MODES: readonly RenderMode[] = ['color', 'albedo', 'achromatic', 'unsharpImage'];

const NO_UNIFORMS: KindUniforms = Object.freeze({});

/** Compile-time svbrdf facts: plane index of each map (-1 when absent) and how kd/ks are encoded. */
function svbrdfDefines(layer: RelightLayer): Record<string, number> {
  const maps = svbrdfMapIndices(layer);
  return {
    SV_NORMALS: maps.normals,
    SV_KD: maps.kd,
    SV_KS: maps.ks,
    SV_GLOSS: maps.gloss,
    SV_SRGB: layer.inputColorSpace === 'srgb' ? 1 : 0,
    SV_DISPLAY: layer.inputColorSpace === 'display' ? 1 : 0,
  };
}

const SVBRDF_GLSL: KindGlsl = { name: 'svbrdf', body: SVBRDF_FRAGMENT_BODY, defines: {}, layerDefines: svbrdfDefines };

const svbrdfUniforms = (layer: RelightLayer): KindUniforms => ({
  [U_GLOSS_LIMITS]: Float32Array.from(layer.glossLimits),
});

const ptmLight = (light: Light): ArrayLike<number> => ptmWeights(light.lu, light.lv);

/** The row of an HSH kind with `terms` terms. */
function hshKind(name: 'hsh4' | 'hsh9' | 'hsh16', terms: 4 | 9 | 16): LayerKind {
  return {
    name,
    shading: 'hsh',
    modes: HSH_MODES,
    lit: true,
    previewPlane: 0,
    glsl: { name, body: HSH_FRAGMENT_BODY, defines: { TERMS: terms } },
    weights: (light) => hshWeights(light.lu, light.lv, terms),
    uniforms: () => ({
      [U_HSH_NORMAL_WEIGHTS]: Float32Array.from(hshNormalWeights(terms)),
      [U_HSH_NORMAL_INV]: Float32Array.from(hshNormalInverse()),
    }),
  };
}

/** Every layer kind. */
export const LAYER_KINDS: Readonly<Record<LayerKindName, LayerKind>> = {
  'ptm-lrgb': {
    name: 'ptm-lrgb',
    shading: 'ptm-lrgb',
    modes: RENDER_MODES,
    lit: true,
    previewPlane: 2,
    // UNSHARP_TERMS: L is Σ wₖLₖ, so the unsharp quantities filter the terms (lt_unsharp_terms)
    glsl: { name: 'ptm-lrgb', body: ptmFragmentBody('lrgb'), defines: { UNSHARP_TERMS: 2 } },
    weights: ptmLight,
    uniforms: () => NO_UNIFORMS,
  },
  'ptm-rgb': {
    name: 'ptm-rgb',
    shading: 'ptm-rgb',
    modes: RENDER_MODES.filter((m) => m !== 'unsharpLuminance'),
    lit: true,
    previewPlane: 0,
    glsl: { name: 'ptm-rgb', body: ptmFragmentBody('rgb'), defines: {} },
    weights: ptmLight,
    uniforms: () => NO_UNIFORMS,
  },
  hsh4: hshKind('hsh4', 4),
  hsh9: hshKind('hsh9', 9),
  hsh16: hshKind('hsh16', 16),
  sh4: SH4_KIND,
  sh9: SH9_KIND,
  svbrdf: {
    name: 'svbrdf',
    shading: 'svbrdf',
    modes: ['color', 'normals', 'albedo', 'diffuse', 'achromatic', 'specular', 'unsharpNormals', 'unsharpImage'],
    lit: true,
    previewPlane: 0,
    glsl: SVBRDF_GLSL,
    weights: null,
    uniforms: svbrdfUniforms,
  },
  'svbrdf-flat': {
    name: 'svbrdf-flat',
    shading: 'flat',
    modes: FLAT_MODES,
    lit: false,
    previewPlane: 0,
    glsl: SVBRDF_GLSL,
    weights: null,
    uniforms: svbrdfUniforms,
  },
  rbf: RBF_KIND,
  bilinear: BILINEAR_KIND,
  image: {
    name: 'image',
    shading: 'flat',
    modes: FLAT_MODES,
    lit: false,
    previewPlane: 0,
    glsl: { name: 'image', body: IMAGE_FRAGMENT_BODY, defines: {} },
    weights: null,
    uniforms: () => NO_UNIFORMS,
  },
};

/** What the unsharp quantities of a kind's layers read and offer (`render/quantity-key.ts`). */
export function quantityFacts(kind: LayerKind): QuantityFacts {
  return { lit: kind.lit, unsharpTerms: kind.glsl.defines['UNSHARP_TERMS'] ?? 0 };
}

/** What the kind of a layer depends on. */
export type LayerFacts = Pick<RelightLayer, 'layerType' | 'colorspace' | 'terms' | 'planes'>;

/** The kind of each layer type, from the facts that refine it. */
const KIND_OF_TYPE: Readonly<Record<LayerType, (layer: LayerFacts) => LayerKindName>> = {
  ptm: (layer) => (layer.colorspace === 'lrgb' ? 'ptm-lrgb' : 'ptm-rgb'),
  hsh: (layer) => `hsh${layer.terms}` as LayerKindName,
  sh: (layer) => `sh${layer.terms}` as LayerKindName,
  svbrdf: (layer) => (svbrdfMapIndices(layer).normals >= 0 ? 'svbrdf' : 'svbrdf-flat'),
  image: () => 'image',
  rbf: () => 'rbf',
  bilinear: () => 'bilinear',
};

/** The kind of a (validated) layer. */
export function layerKindOf(layer: LayerFacts): LayerKind {
  return LAYER_KINDS[KIND_OF_TYPE[layer.layerType](layer)];
}

/** The shading class of a layer: its column in the contract's table. */
export function shadingClass(layer: LayerFacts): ShadingClass {
  return layerKindOf(layer).shading;
}

/** The modes that apply to a layer, in menu order. */
export function applicableModes(layer: LayerFacts): RenderMode[] {
  return [...layerKindOf(layer).modes];
}
