/**
 * A layer resolved once, when it is set: its kind (see {@link LAYER_KINDS}), the program spec that
 * draws it and its fixed uniforms. Frames draw from this, never from the layer type again.
 */
import type { RelightLayer } from '../iiif/relight-service';
import { layerKindOf, type LayerKind } from './layer-kinds';
import { fixedUniforms, type FixedUniforms } from './layer-uniforms';
import { programSpec, type ProgramSpec } from './programs';

/** A layer with what its kind says about drawing it. */
export interface ResolvedLayer {
  readonly layer: RelightLayer;
  readonly kind: LayerKind;
  readonly program: ProgramSpec;
  readonly uniforms: FixedUniforms;
}

/** Resolve a (validated) layer. */
export function resolveLayer(layer: RelightLayer): ResolvedLayer {
  const kind = layerKindOf(layer);
  return { layer, kind, program: programSpec(kind.glsl, layer), uniforms: fixedUniforms(layer, kind) };
}
