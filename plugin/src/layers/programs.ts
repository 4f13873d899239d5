/**
 * Layer programs: one fragment shader per layer kind × render mode × stage, built from the shared
 * prelude, colour helpers and mode `main()` plus the layer's functions, compiled on first use.
 */
import * as twgl from 'twgl.js';
import { COLOR_GLSL } from '../gl/glsl/color.glsl';
import { MODE_DEFINES, MODES_MAIN_GLSL, STAGE, type Stage } from '../gl/glsl/modes.glsl';
import { planesPrelude } from '../gl/glsl/planes.glsl';
import { QUAD_VERTEX_SHADER } from '../gl/glsl/quad.vert';
import { compileProgram } from '../gl/compile';
import { svbrdfMapIndices, type RelightLayer } from '../iiif/relight-service';
import { RENDER_MODES, type RenderMode } from '../render/modes';
import { HSH_FRAGMENT_BODY } from './hsh/hsh.frag';
import { IMAGE_FRAGMENT_BODY } from './image/image.frag';
import { ptmFragmentBody } from './ptm/ptm.frag';
import { SVBRDF_FRAGMENT_BODY } from './svbrdf/svbrdf.frag';

/** Program kinds: one set of layer functions (and compile-time constants) each. */
export type ProgramKind = 'ptm-lrgb' | 'ptm-rgb' | 'hsh4' | 'hsh9' | 'hsh16' | 'svbrdf' | 'image';

/** Layer functions and extra defines per program kind. */
const KINDS: Readonly<Record<ProgramKind, { body: string; defines?: Record<string, number> }>> = {
  'ptm-lrgb': { body: ptmFragmentBody('lrgb') },
  'ptm-rgb': { body: ptmFragmentBody('rgb') },
  hsh4: { body: HSH_FRAGMENT_BODY, defines: { TERMS: 4 } },
  hsh9: { body: HSH_FRAGMENT_BODY, defines: { TERMS: 9 } },
  hsh16: { body: HSH_FRAGMENT_BODY, defines: { TERMS: 16 } },
  svbrdf: { body: SVBRDF_FRAGMENT_BODY },
  image: { body: IMAGE_FRAGMENT_BODY },
};

/**
 * What a layer's program is built from: its kind plus compile-time facts of the layer (svbrdf: which
 * maps exist and where, sRGB input), so that the shader never branches on a uniform for them.
 */
export interface ProgramSpec {
  readonly kind: ProgramKind;
  /** Extra `#define`s (besides the kind's own). */
  readonly defines: Readonly<Record<string, number>>;
  /** Cache key: kind and defines. */
  readonly key: string;
}

/** Compile-time svbrdf facts: plane index of each map (-1 when absent) and whether kd/ks are sRGB. */
export function svbrdfDefines(layer: RelightLayer): Record<string, number> {
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

/** The program spec that draws a layer. */
export function programSpec(layer: RelightLayer): ProgramSpec {
  const kind = programKind(layer);
  const defines = kind === 'svbrdf' ? svbrdfDefines(layer) : {};
  const key = [kind, ...Object.entries(defines).map(([k, v]) => `${k}=${v}`)].join(',');
  return { kind, defines, key };
}

/** The program kind that draws a layer. */
export function programKind(layer: RelightLayer): ProgramKind {
  switch (layer.layerType) {
    case 'ptm':
      return layer.colorspace === 'lrgb' ? 'ptm-lrgb' : 'ptm-rgb';
    case 'hsh':
      return `hsh${layer.terms}` as ProgramKind;
    case 'svbrdf':
      return 'svbrdf';
    default:
      return 'image';
  }
}

/**
 * Fragment shader source of a layer kind in a render mode and stage.
 *
 * @param spec - a program kind, or a {@link ProgramSpec} with the layer's compile-time facts
 * @param gammaOne - compile the post step for `gamma` = 1 (no `pow`); otherwise it reads `u_gamma`
 */
export function fragmentShaderSource(spec: ProgramKind | ProgramSpec, mode: RenderMode, stage: Stage,
  gammaOne = false): string {
  const kind = typeof spec === 'string' ? spec : spec.kind;
  const { body, defines } = KINDS[kind];
  const all = {
    ...MODE_DEFINES,
    ...defines,
    ...(kind === 'svbrdf' ? { SV_NORMALS: 0, SV_KD: 1, SV_KS: 2, SV_GLOSS: 3, SV_SRGB: 0, SV_DISPLAY: 0 } : {}),
    ...(typeof spec === 'string' ? {} : spec.defines),
    MODE: RENDER_MODES.indexOf(mode),
    STAGE: STAGE[stage],
    GAMMA_ONE: gammaOne ? 1 : 0,
  };
  return planesPrelude(`lanterna-${kind}-${mode}-${stage}`, all) + COLOR_GLSL + body + MODES_MAIN_GLSL;
}

/** Layer programs of one GL context, compiled on first use. */
export class ProgramCache {
  private readonly programs = new Map<string, twgl.ProgramInfo>();

  constructor(private readonly gl: WebGL2RenderingContext) {}

  /**
   * The program of a layer spec, mode and stage (and post step: `gammaOne` when gamma = 1).
   *
   * @throws {@link ShaderError} if it does not compile
   */
  get(spec: ProgramSpec, mode: RenderMode, stage: Stage, gammaOne = false): twgl.ProgramInfo {
    const key = `${spec.key}/${mode}/${stage}${gammaOne ? '/gamma1' : ''}`;
    let info = this.programs.get(key);
    if (!info) {
      info = compileProgram(this.gl, QUAD_VERTEX_SHADER, fragmentShaderSource(spec, mode, stage, gammaOne), key);
      this.programs.set(key, info);
    }
    return info;
  }

  /** Delete every program (the context is being dropped or rebuilt). */
  clear(): void {
    if (!this.gl.isContextLost()) {
      for (const info of this.programs.values()) {
        this.gl.deleteProgram(info.program);
      }
    }
    this.programs.clear();
  }
}
