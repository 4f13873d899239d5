/**
 * The layer pass: one relightable item drawn in a render mode, either straight into its target
 * (`direct` stage) or, for the unsharp modes, through the screen-space filter: the quantity for the
 * whole view, the box passes, then the `combine` stage into the target. Also decides which
 * programs a layer needs in a mode, so that they can be compiled ahead of a frame.
 */
import * as twgl from 'twgl.js';
import type { Stage } from '../gl/glsl/modes.glsl';
import { U_FILTERED, U_MATRIX, U_PLANES, U_TEX_SCALE } from '../gl/uniforms';
import { layerUniforms, type LayerUniforms } from '../layers/layer-uniforms';
import { ProgramCache } from '../layers/programs';
import type { ResolvedLayer } from '../layers/resolved-layer';
import type { Light } from '../math/light';
import type { Mat3 } from '../math/matrix';
import { modeFilter } from '../render/filter-plan';
import { DEFAULT_RENDER_MODE, type RenderMode } from '../render/modes';
import type { RenderParams } from '../render/params';
import { ScreenFilter } from './screen-filter';

/** A scissor box `[x, y, w, h]` in device px, y up. */
export type ScissorBox = readonly [number, number, number, number];

/** One tile ready to draw: its texture array, placement (clip space) and the valid part of the texture. */
export interface TileQuad {
  readonly texture: WebGLTexture;
  readonly matrix: Mat3;
  readonly texScale: readonly [number, number];
}

/** One item to relight. */
export interface LayerDraw<T> {
  readonly layer: ResolvedLayer;
  /** The requested mode (a layer it does not apply to is drawn in the default mode). */
  readonly mode: RenderMode;
  readonly params: RenderParams;
  readonly light: Light;
  /** The item's tiles, coarse level first. */
  readonly tiles: readonly T[];
  /** A tile's quad, or null when it has no texture (called as each tile is drawn, once per stage). */
  quadOf(tile: T): TileQuad | null;
  /** The sampler of the planes (smoothing on or off). */
  readonly sampler: WebGLSampler;
  /** Framebuffer of the final stage (null = the canvas). */
  readonly target: WebGLFramebuffer | null;
  /** Scissor box of the final stage (the unsharp modes filter the whole view first). */
  readonly box: ScissorBox | null;
}

/** The stages a mode is drawn in: `direct`, or `quantity` then `combine` around the screen filter. */
export function modeStages(mode: RenderMode): Stage[] {
  return modeFilter(mode) ? ['quantity', 'combine'] : ['direct'];
}

/** The layer programs and the screen filter of one GL context. */
export class LayerPass {
  private readonly programs: ProgramCache;
  private screenFilter: ScreenFilter | null = null;

  constructor(private readonly gl: WebGL2RenderingContext) {
    this.programs = new ProgramCache(gl);
  }

  /**
   * Compile the programs a layer needs in a mode (and create the screen filter if the mode uses it).
   *
   * @throws {@link ShaderError} or {@link FloatTargetsUnavailableError}
   */
  prepare(layer: ResolvedLayer, mode: RenderMode, params: RenderParams): void {
    const gammaOne = params.gamma === 1;
    if (modeFilter(mode)) {
      this.screenFilter ??= new ScreenFilter(this.gl);
    }
    for (const stage of modeStages(mode)) {
      this.programs.get(layer.program, mode, stage, gammaOne);
    }
  }

  /** Relight one item (see {@link LayerDraw}). */
  draw<T>(d: LayerDraw<T>): void {
    const gl = this.gl;
    const mode = d.layer.kind.modes.includes(d.mode) ? d.mode : DEFAULT_RENDER_MODE;
    const spec = d.layer.program;
    const uniforms = layerUniforms(d.layer, d.light, d.params);
    const gammaOne = d.params.gamma === 1;
    const filter = modeFilter(mode);
    const { box } = d;
    const bindTarget = (): void => {
      gl.bindFramebuffer(gl.FRAMEBUFFER, d.target);
      gl.viewport(0, 0, gl.drawingBufferWidth, gl.drawingBufferHeight);
      if (box) {
        gl.enable(gl.SCISSOR_TEST);
        gl.scissor(box[0], box[1], box[2], box[3]);
      }
    };
    if (!filter) {
      bindTarget();
      this.drawTiles(d, this.programs.get(spec, mode, 'direct', gammaOne), uniforms, null);
      gl.disable(gl.SCISSOR_TEST);
      return;
    }
    // Screen-space unsharp masking: quantity for the whole view, box passes, then combine.
    gl.disable(gl.SCISSOR_TEST);
    this.screenFilter ??= new ScreenFilter(gl);
    this.screenFilter.beginQuantity(gl.drawingBufferWidth, gl.drawingBufferHeight);
    this.drawTiles(d, this.programs.get(spec, mode, 'quantity', gammaOne), uniforms, null);
    const filtered = this.screenFilter.filter(filter);
    bindTarget();
    this.drawTiles(d, this.programs.get(spec, mode, 'combine', gammaOne), uniforms, filtered);
    gl.disable(gl.SCISSOR_TEST);
  }

  /** Forget the programs and the filter (after a context loss; they went with the context). */
  forget(): void {
    this.programs.forget();
    this.screenFilter = null;
  }

  /** Free the programs and the filter's targets. */
  destroy(): void {
    this.programs.clear();
    this.screenFilter?.destroy();
  }

  /** Draw an item's tiles (coarse level first, finer over them: painter's algorithm, opaque). */
  private drawTiles<T>(d: LayerDraw<T>, programInfo: twgl.ProgramInfo, uniforms: LayerUniforms,
    filtered: WebGLTexture | null): void {
    const gl = this.gl;
    gl.useProgram(programInfo.program);
    twgl.setUniforms(programInfo, uniforms);
    gl.uniform1i(gl.getUniformLocation(programInfo.program, U_PLANES), 0);
    if (filtered) {
      gl.activeTexture(gl.TEXTURE1);
      gl.bindTexture(gl.TEXTURE_2D, filtered);
      gl.bindSampler(1, null);
      gl.uniform1i(gl.getUniformLocation(programInfo.program, U_FILTERED), 1);
    }
    gl.activeTexture(gl.TEXTURE0);
    gl.bindSampler(0, d.sampler);
    for (const tile of d.tiles) {
      const quad = d.quadOf(tile);
      if (!quad) {
        continue;
      }
      gl.bindTexture(gl.TEXTURE_2D_ARRAY, quad.texture);
      twgl.setUniforms(programInfo, {
        [U_MATRIX]: new Float32Array(quad.matrix),
        [U_TEX_SCALE]: quad.texScale,
      });
      gl.drawArrays(gl.TRIANGLE_STRIP, 0, 4);
    }
  }
}
