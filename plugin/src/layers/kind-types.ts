/**
 * The types of a layer-kind row ({@link LAYER_KINDS} in `layer-kinds.ts`), apart from the table so
 * that rows built in a layer type's own folder (rbf/, bilinear/) can name them. Pure.
 */
import type { RelightLayer } from '../iiif/relight-service';
import type { Light } from '../math/light';
import type { RenderMode, ShadingClass } from '../render/modes';

/** A layer kind: a layer type refined by what changes its program, its modes or its uniforms. */
export type LayerKindName = 'ptm-lrgb' | 'ptm-rgb' | 'hsh4' | 'hsh9' | 'hsh16' | 'sh4' | 'sh9' | 'svbrdf'
  | 'svbrdf-flat' | 'image' | 'rbf' | 'bilinear';

/** The GLSL of a kind: its layer functions (`lt_color`, `lt_normal`, …) and compile-time constants. */
export interface KindGlsl {
  /** Program name (in `SHADER_NAME` and the program-cache key); kinds with the same GLSL share it. */
  readonly name: string;
  /** The layer functions, placed between the shared prelude and the mode `main()`. */
  readonly body: string;
  /** The kind's own `#define`s. */
  readonly defines: Readonly<Record<string, number>>;
  /** `#define`s from one layer's compile-time facts (svbrdf: where each map is, how kd/ks are encoded). */
  layerDefines?(layer: RelightLayer): Readonly<Record<string, number>>;
}

/** Uniform values a kind adds for one layer, fixed while the layer is drawn. */
export type KindUniforms = Readonly<Record<string, Float32Array>>;

/** One row of {@link LAYER_KINDS}. */
export interface LayerKind {
  readonly name: LayerKindName;
  /** The contract's column (`flat`: an image, or an svbrdf layer without a normal map). */
  readonly shading: ShadingClass;
  /** The render modes it supports, in menu order. */
  readonly modes: readonly RenderMode[];
  /** Whether the light changes the picture (the light widget is dimmed on layers where it does not). */
  readonly lit: boolean;
  /** The plane group a TiledImage shows while it has no relit tile yet. */
  readonly previewPlane: number;
  readonly glsl: KindGlsl;
  /** `u_weights` for a light: the basis weights, or null when the kind has no light basis (all 0). */
  readonly weights: ((light: Light) => ArrayLike<number>) | null;
  /** Uniforms of a layer that follow the light, computed per frame (PCA: the light's plane weights). */
  readonly lightUniforms?: (layer: RelightLayer, light: Light) => KindUniforms;
  /** The kind's own uniforms for a layer (the scale, bias, light and parameters are common to all). */
  uniforms(layer: RelightLayer): KindUniforms;
}

/** The modes of the HSH column (HSH, SH and the PCA kinds), in menu order. */
export const HSH_MODES: readonly RenderMode[] = ['color', 'normals', 'albedo', 'diffuse', 'achromatic', 'specular',
  'unsharpNormals', 'unsharpCoefficients', 'unsharpImage'];
