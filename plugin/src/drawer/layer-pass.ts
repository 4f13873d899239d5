/**
 * The layer pass: one relightable item drawn in a render mode, either straight into its target
 * (`direct` stage) or, for the unsharp modes, through the screen-space filter: the quantity for the
 * whole view, the box passes, then the `combine` stage into the target. A filtered quantity that
 * does not read the light is kept and reused while only the light (or a parameter the combine
 * stage reads) changes (`QuantityCache`). Also decides which programs a layer needs in a mode, so
 * that they can be compiled ahead of a frame.
 */
import * as twgl from 'twgl.js';
import type { Stage } from '../gl/glsl/modes.glsl';
import { U_FILTERED, U_FILTERED_1, U_MATRIX, U_PLANES, U_TEX_SCALE } from '../gl/uniforms';
import { quantityFacts } from '../layers/layer-kinds';
import { layerUniforms, type LayerUniforms } from '../layers/layer-uniforms';
import { ProgramCache } from '../layers/programs';
import type { ResolvedLayer } from '../layers/resolved-layer';
import type { Light } from '../math/light';
import type { Mat3 } from '../math/matrix';
import { modeFilter } from '../render/filter-plan';
import { quantityKey, quantityPlan } from '../render/quantity-key';
import { DEFAULT_RENDER_MODE, type RenderMode } from '../render/modes';
import type { RenderParams } from '../render/params';
import { ObjectIds, QuantityCache } from './quantity-cache';
import { ScreenFilter } from './screen-filter';
import { ViewCombine } from './view-combine';

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
  /** A tile's quad, or null when it has no texture (called once per tile and draw). */
  quadOf(tile: T): TileQuad | null;
  /** The sampler of the planes (smoothing on or off). */
  readonly sampler: WebGLSampler;
  /** Framebuffer of the final stage (null = the canvas). */
  readonly target: WebGLFramebuffer | null;
  /** Scissor box of the final stage (the unsharp modes filter the whole view first). */
  readonly box: ScissorBox | null;
}

/**
 * The layer-program stages a mode is drawn in on a layer: `direct`, or `quantity` then `combine`
 * around the screen filter (only `quantity` for a mode combined from the view, by {@link ViewCombine}).
 */
export function modeStages(mode: RenderMode, layer: ResolvedLayer): Stage[] {
  const plan = quantityPlan(mode, quantityFacts(layer.kind));
  if (!plan) {
    return ['direct'];
  }
  return plan.fromView ? ['quantity'] : ['quantity', 'combine'];
}

/** The samplers of the filtered targets, on texture units 1, 2. */
const FILTERED_UNIFORMS = [U_FILTERED, U_FILTERED_1];

/** Stands for the canvas (a null target) in the slot names of the kept quantities. */
const CANVAS = {};

/** The layer programs, the screen filter and the kept quantities of one GL context. */
export class LayerPass {
  private readonly programs: ProgramCache;
  private screenFilter: ScreenFilter | null = null;
  private quantities: QuantityCache | null = null;
  private viewCombine: ViewCombine;
  private readonly ids = new ObjectIds();

  constructor(private readonly gl: WebGL2RenderingContext) {
    this.programs = new ProgramCache(gl);
    this.viewCombine = new ViewCombine(gl);
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
    for (const stage of modeStages(mode, layer)) {
      this.programs.get(layer.program, mode, stage, gammaOne);
    }
    if (quantityPlan(mode, quantityFacts(layer.kind))?.fromView) {
      this.viewCombine.program(gammaOne);
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
    const plan = quantityPlan(mode, quantityFacts(d.layer.kind));
    const quads: TileQuad[] = [];
    for (const tile of d.tiles) {
      const quad = d.quadOf(tile);
      if (quad) {
        quads.push(quad);
      }
    }
    const { box } = d;
    const bindTarget = (): void => {
      gl.bindFramebuffer(gl.FRAMEBUFFER, d.target);
      gl.viewport(0, 0, gl.drawingBufferWidth, gl.drawingBufferHeight);
      if (box) {
        gl.enable(gl.SCISSOR_TEST);
        gl.scissor(box[0], box[1], box[2], box[3]);
      }
    };
    if (!filter || !plan) {
      bindTarget();
      this.drawTiles(d.sampler, quads, this.programs.get(spec, mode, 'direct', gammaOne), uniforms, []);
      gl.disable(gl.SCISSOR_TEST);
      return;
    }
    // Screen-space unsharp masking: quantity for the whole view, box passes (or the kept result of
    // both, when the quantity does not read the light and nothing it reads changed), then combine.
    gl.disable(gl.SCISSOR_TEST);
    this.screenFilter ??= new ScreenFilter(gl);
    this.quantities ??= new QuantityCache(this.screenFilter);
    const program = this.programs.get(spec, mode, 'quantity', gammaOne);
    const width = gl.drawingBufferWidth;
    const height = gl.drawingBufferHeight;
    const ids = this.ids;
    const key = plan.kept
      ? quantityKey({
        program: ids.of(program), layer: ids.of(d.layer), filter, width, height, sampler: ids.of(d.sampler),
        tiles: quads.map((q) => ({ texture: ids.of(q.texture), matrix: q.matrix, texScale: q.texScale })),
      })
      : null;
    const slot = `${ids.of(d.target ?? CANVAS)}/${ids.of(d.layer)}`;
    const shape = { width, height, filtered: plan.filtered, extras: plan.extras };
    const { targets, fresh } = this.quantities.acquire(slot, key, shape);
    if (!fresh) {
      this.screenFilter.beginQuantity(targets);
      this.drawTiles(d.sampler, quads, program, uniforms, []);
      for (const target of targets.filtered) {
        this.screenFilter.filter(target, filter);
      }
      if (key !== null) {
        this.quantities.keep(slot, key);
      }
    }
    bindTarget();
    if (plan.fromView) {
      this.viewCombine.draw(targets, uniforms, gammaOne);
    } else {
      const combine = this.programs.get(spec, mode, 'combine', gammaOne);
      this.drawTiles(d.sampler, quads, combine, uniforms, targets.filtered.map((t) => t.texture));
    }
    gl.disable(gl.SCISSOR_TEST);
  }

  /** Forget the programs, the filter and the kept quantities (after a context loss: they went with the context). */
  forget(): void {
    this.programs.forget();
    this.viewCombine = new ViewCombine(this.gl);
    this.screenFilter = null;
    this.quantities = null;
  }

  /** Free the programs, the filter's and the kept quantities' targets. */
  destroy(): void {
    this.programs.clear();
    this.viewCombine.destroy();
    this.quantities?.destroy();
    this.screenFilter?.destroy();
  }

  /** Draw an item's tiles (coarse level first, finer over them: painter's algorithm, opaque). */
  private drawTiles(sampler: WebGLSampler, quads: readonly TileQuad[], programInfo: twgl.ProgramInfo,
    uniforms: LayerUniforms, filtered: readonly WebGLTexture[]): void {
    const gl = this.gl;
    gl.useProgram(programInfo.program);
    twgl.setUniforms(programInfo, uniforms);
    gl.uniform1i(gl.getUniformLocation(programInfo.program, U_PLANES), 0);
    filtered.forEach((texture, i) => {
      gl.activeTexture(gl.TEXTURE1 + i);
      gl.bindTexture(gl.TEXTURE_2D, texture);
      gl.bindSampler(1 + i, null);
      gl.uniform1i(gl.getUniformLocation(programInfo.program, FILTERED_UNIFORMS[i] ?? ''), 1 + i);
    });
    gl.activeTexture(gl.TEXTURE0);
    gl.bindSampler(0, sampler);
    for (const quad of quads) {
      gl.bindTexture(gl.TEXTURE_2D_ARRAY, quad.texture);
      twgl.setUniforms(programInfo, {
        [U_MATRIX]: new Float32Array(quad.matrix),
        [U_TEX_SCALE]: quad.texScale,
      });
      gl.drawArrays(gl.TRIANGLE_STRIP, 0, 4);
    }
  }
}
