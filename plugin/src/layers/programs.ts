/**
 * Layer programs: one fragment shader per layer kind × render mode × stage, built from the shared
 * prelude, colour helpers and mode `main()` plus the kind's layer functions, compiled on first use.
 */
import type * as twgl from 'twgl.js';
import { compileProgram } from '../gl/compile';
import { COLOR_GLSL } from '../gl/glsl/color.glsl';
import { MODE_DEFINES, MODES_MAIN_GLSL, STAGE, type Stage } from '../gl/glsl/modes.glsl';
import { planesPrelude } from '../gl/glsl/planes.glsl';
import { QUAD_VERTEX_SHADER } from '../gl/glsl/quad.vert';
import type { RelightLayer } from '../iiif/relight-service';
import { RENDER_MODES, type RenderMode } from '../render/modes';
import type { KindGlsl } from './layer-kinds';

/**
 * What a layer's program is built from: its kind's GLSL plus compile-time facts of the layer (svbrdf:
 * which maps exist and where, their encoding), so that the shader never branches on a uniform for them.
 */
export interface ProgramSpec {
  readonly glsl: KindGlsl;
  /** The layer's `#define`s (besides the kind's own). */
  readonly defines: Readonly<Record<string, number>>;
  /** Cache key: program name and the layer's defines. */
  readonly key: string;
}

/** The program spec that draws `layer` with its kind's GLSL. */
export function programSpec(glsl: KindGlsl, layer: RelightLayer): ProgramSpec {
  const defines = glsl.layerDefines?.(layer) ?? {};
  const key = [glsl.name, ...Object.entries(defines).map(([k, v]) => `${k}=${v}`)].join(',');
  return { glsl, defines, key };
}

/**
 * Fragment shader source of a layer program in a render mode and stage.
 *
 * @param gammaOne - compile the post step for `gamma` = 1 (no `pow`); otherwise it reads `u_gamma`
 */
export function fragmentShaderSource(spec: ProgramSpec, mode: RenderMode, stage: Stage, gammaOne = false): string {
  const { name, body, defines } = spec.glsl;
  const all = {
    ...MODE_DEFINES,
    ...defines,
    ...spec.defines,
    MODE: RENDER_MODES.indexOf(mode),
    STAGE: STAGE[stage],
    GAMMA_ONE: gammaOne ? 1 : 0,
  };
  return planesPrelude(`lanterna-${name}-${mode}-${stage}`, all) + COLOR_GLSL + body + MODES_MAIN_GLSL;
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

  /** Drop the programs without deleting them (after a context loss: they went with the old context). */
  forget(): void {
    this.programs.clear();
  }
}
