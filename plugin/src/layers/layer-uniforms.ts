/**
 * Uniform values of a relight layer (pure: no GL): those fixed while the layer is drawn, computed
 * once when it is set, and those that follow the light and the parameters, computed per frame.
 */
import { MAX_PLANES, MAX_TERMS, U_BIAS, U_HALF, U_LIGHT, U_PARAM, U_SCALE, U_WEIGHTS } from '../gl/uniforms';
import type { RelightLayer } from '../iiif/relight-service';
import type { Light } from '../math/light';
import { DEFAULT_RENDER_PARAMS, PARAM_NAMES, type RenderParams } from '../render/params';
import type { LayerKind } from './layer-kinds';

/** Uniforms fixed for a layer: its plane groups' scale and bias, and its kind's own uniforms. */
export interface FixedUniforms {
  [U_SCALE]: Float32Array;
  [U_BIAS]: Float32Array;
  [kindUniform: string]: Float32Array;
}

/** Every uniform of a layer draw that does not depend on the tile. */
export interface LayerUniforms {
  [U_SCALE]: Float32Array;
  [U_BIAS]: Float32Array;
  [U_WEIGHTS]: Float32Array;
  [U_LIGHT]: Float32Array;
  [U_HALF]: Float32Array;
  [uniform: string]: Float32Array | number;
}

/** Pad per-channel values to a vec3 (a single-band group repeats its value). */
function vec3Of(values: readonly number[]): number[] {
  return values.length === 1 ? [values[0] ?? 0, values[0] ?? 0, values[0] ?? 0] : [...values];
}

/**
 * The uniforms fixed for a layer: scale and bias padded to {@link MAX_PLANES} vec3s, and the kind's
 * own (HSH: the normal-estimate weights; svbrdf: the gloss limits).
 */
export function fixedUniforms(layer: RelightLayer, kind: LayerKind): FixedUniforms {
  const scale = new Float32Array(MAX_PLANES * 3);
  const bias = new Float32Array(MAX_PLANES * 3);
  layer.planes.forEach((p, i) => {
    scale.set(vec3Of(p.scale), i * 3);
    bias.set(vec3Of(p.bias), i * 3);
  });
  return { [U_SCALE]: scale, [U_BIAS]: bias, ...kind.uniforms(layer) };
}

/**
 * Per-draw uniform values: the layer's fixed uniforms, the basis weights of the light (zero for
 * kinds without a basis), the light and half vector, the kind's light uniforms (PCA: the light's
 * plane weights) and the render parameters.
 *
 * @param layer - the layer, its kind and fixed uniforms (a resolved layer)
 * @param light - the light (already on the unit hemisphere: it is not clamped again)
 * @param params - render parameters
 */
export function layerUniforms(
  layer: { readonly layer: RelightLayer; readonly kind: LayerKind; readonly uniforms: FixedUniforms }, light: Light,
  params: RenderParams = DEFAULT_RENDER_PARAMS): LayerUniforms {
  const weights = new Float32Array(MAX_TERMS);
  if (layer.kind.weights) {
    weights.set(layer.kind.weights(light));
  }
  const hz = light.lz + 1;
  const hl = Math.hypot(light.lu, light.lv, hz);
  const out: LayerUniforms = {
    ...layer.uniforms,
    [U_WEIGHTS]: weights,
    [U_LIGHT]: Float32Array.of(light.lu, light.lv, light.lz),
    [U_HALF]: Float32Array.of(light.lu / hl, light.lv / hl, hz / hl),
    ...layer.kind.lightUniforms?.(layer.layer, light),
  };
  for (const name of PARAM_NAMES) {
    out[U_PARAM[name]] = params[name];
  }
  return out;
}
