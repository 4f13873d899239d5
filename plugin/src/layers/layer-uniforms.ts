/**
 * Uniform values of a relight layer (pure: no GL), checked against the uniform names with `satisfies`.
 */
import type { RelightLayer } from '../iiif/relight-service';
import { svbrdfMapIndices } from '../iiif/relight-service';
import { hshNormalInverse, hshNormalWeights, hshWeights } from '../math/hsh-basis';
import { lightFromProjection } from '../math/light';
import { ptmWeights } from '../math/ptm-basis';
import { DEFAULT_RENDER_PARAMS, PARAM_NAMES, type RenderParams } from '../render/params';
import {
  MAX_PLANES, MAX_TERMS, U_BIAS, U_GLOSS_LIMITS, U_HALF, U_HSH_NORMAL_INV, U_HSH_NORMAL_WEIGHTS, U_LIGHT,
  U_MAPS, U_PARAM, U_SCALE, U_SRGB_INPUT, U_WEIGHTS,
} from '../gl/uniforms';

/** Uniforms that depend on the layer, the light and the parameters (not on the tile). */
export interface LayerUniforms {
  [U_SCALE]: Float32Array;
  [U_BIAS]: Float32Array;
  [U_WEIGHTS]: Float32Array;
  [U_LIGHT]: Float32Array;
  [U_HALF]: Float32Array;
  [U_HSH_NORMAL_WEIGHTS]: Float32Array;
  [U_HSH_NORMAL_INV]: Float32Array;
  [U_MAPS]: Int32Array;
  [U_GLOSS_LIMITS]: Float32Array;
  [U_SRGB_INPUT]: number;
  [param: string]: Float32Array | Int32Array | number;
}

/** Pad per-channel values to a vec3 (a single-band group repeats its value). */
function vec3Of(values: readonly number[]): number[] {
  return values.length === 1 ? [values[0] ?? 0, values[0] ?? 0, values[0] ?? 0] : [...values];
}

/**
 * Per-layer uniform values: scale and bias padded to {@link MAX_PLANES} vec3s, the basis weights,
 * light and half vector, the render parameters and the type's own constants.
 *
 * @param layer - the validated relight layer
 * @param lu - light x (right)
 * @param lv - light y (up)
 * @param params - render parameters
 */
export function layerUniforms(layer: RelightLayer, lu: number, lv: number,
  params: RenderParams = DEFAULT_RENDER_PARAMS): LayerUniforms {
  const scale = new Float32Array(MAX_PLANES * 3);
  const bias = new Float32Array(MAX_PLANES * 3);
  layer.planes.forEach((p, i) => {
    scale.set(vec3Of(p.scale), i * 3);
    bias.set(vec3Of(p.bias), i * 3);
  });
  const weights = new Float32Array(MAX_TERMS);
  if (layer.layerType === 'ptm') {
    weights.set(ptmWeights(lu, lv));
  } else if (layer.layerType === 'hsh') {
    weights.set(hshWeights(lu, lv, layer.terms));
  }
  const l = lightFromProjection(lu, lv);
  const hz = l.lz + 1;
  const hl = Math.hypot(l.lu, l.lv, hz);
  const maps = svbrdfMapIndices(layer);
  const out: LayerUniforms = {
    [U_SCALE]: scale,
    [U_BIAS]: bias,
    [U_WEIGHTS]: weights,
    [U_LIGHT]: Float32Array.of(l.lu, l.lv, l.lz),
    [U_HALF]: Float32Array.of(l.lu / hl, l.lv / hl, hz / hl),
    [U_HSH_NORMAL_WEIGHTS]: Float32Array.from(hshNormalWeights(layer.layerType === 'hsh' ? layer.terms : 16)),
    [U_HSH_NORMAL_INV]: Float32Array.from(hshNormalInverse()),
    [U_MAPS]: Int32Array.of(maps.normals, maps.kd, maps.ks, maps.gloss),
    [U_GLOSS_LIMITS]: Float32Array.from(layer.glossLimits),
    [U_SRGB_INPUT]: layer.inputColorSpace === 'srgb' ? 1 : 0,
  };
  for (const name of PARAM_NAMES) {
    out[U_PARAM[name]] = params[name];
  }
  return out;
}
