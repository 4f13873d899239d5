/**
 * Float render targets and box passes for the screen-space unsharp modes: the quantity is drawn
 * into a float target, then the box passes ping-pong between it and a scratch target.
 */
import * as twgl from 'twgl.js';
import { BOX_FRAGMENT_SHADER, FULLSCREEN_VERTEX_SHADER } from '../gl/glsl/box.glsl';
import { U_RADIUS, U_SOURCE, U_STEP } from '../gl/uniforms';
import { LanternaError } from '../errors';
import { compileProgram } from '../gl/compile';
import { boxPasses, type BoxFilter } from '../render/filter-plan';

/** Float colour buffers are not renderable in this context (no `EXT_color_buffer_float`). */
export class FloatTargetsUnavailableError extends LanternaError {}

/** A canvas-sized RGBA32F texture and its framebuffer. */
export interface FloatTarget {
  readonly texture: WebGLTexture;
  readonly framebuffer: WebGLFramebuffer;
  readonly width: number;
  readonly height: number;
}

/**
 * The float targets one quantity is drawn into, output i of the fragment shader to target i:
 * first the `filtered` ones (at least one), box-filtered in place, then the `extras`, kept as drawn.
 */
export interface QuantityTargets {
  readonly filtered: readonly [FloatTarget, ...FloatTarget[]];
  readonly extras: readonly FloatTarget[];
  /** Draws to all of them (the first target's own framebuffer when it is the only one). */
  readonly framebuffer: WebGLFramebuffer;
}

/** The size and shape of a quantity's targets. */
export interface QuantityShape {
  readonly width: number;
  readonly height: number;
  readonly filtered: number;
  readonly extras: number;
}

/**
 * The box-pass program and one scratch target. The quantity is drawn into targets of the caller's
 * (see {@link ScreenFilter.targets}); each box pass goes from the filtered one to the scratch target
 * or back, and as the passes come in pairs (x then y) the result ends in the caller's target.
 */
export class ScreenFilter {
  private scratch: FloatTarget | null = null;
  private readonly program: twgl.ProgramInfo;

  /**
   * @throws {@link FloatTargetsUnavailableError} without `EXT_color_buffer_float`
   */
  constructor(private readonly gl: WebGL2RenderingContext) {
    if (!gl.getExtension('EXT_color_buffer_float')) {
      throw new FloatTargetsUnavailableError('float render targets (EXT_color_buffer_float) are not available');
    }
    this.program = compileProgram(gl, FULLSCREEN_VERTEX_SHADER, BOX_FRAGMENT_SHADER, 'box-pass');
  }

  /**
   * `targets` if they have the `shape`, else new ones (`targets` freed).
   *
   * @throws {@link FloatTargetsUnavailableError} if a framebuffer is incomplete
   */
  targets(targets: QuantityTargets | null, shape: QuantityShape): QuantityTargets {
    if (targets && hasShape(targets, shape)) {
      return targets;
    }
    this.free(targets);
    const gl = this.gl;
    const made: FloatTarget[] = [];
    try {
      for (let i = 0; i < Math.max(1, shape.filtered) + shape.extras; i++) {
        made.push(makeTarget(gl, shape.width, shape.height));
      }
      const first = made[0];
      const filtered = made.slice(0, Math.max(1, shape.filtered)) as [FloatTarget, ...FloatTarget[]];
      return {
        filtered, extras: made.slice(filtered.length),
        framebuffer: made.length > 1 ? drawingToAll(gl, made) : first.framebuffer,
      };
    } catch (error) {
      made.forEach((target) => { deleteTarget(gl, target); });
      throw error;
    }
  }

  /** Bind `into` (all its targets cleared to 0, viewport their size) for drawing the quantity. */
  beginQuantity(into: QuantityTargets): void {
    const gl = this.gl;
    gl.bindFramebuffer(gl.FRAMEBUFFER, into.framebuffer);
    gl.viewport(0, 0, into.filtered[0].width, into.filtered[0].height);
    gl.clearColor(0, 0, 0, 0);
    gl.clear(gl.COLOR_BUFFER_BIT);
  }

  /**
   * Run the filter's box passes on `into`, in place (through the scratch target); returns its texture.
   * Leaves the default framebuffer bound (the caller binds its own).
   */
  filter(into: FloatTarget, filter: BoxFilter): WebGLTexture {
    const gl = this.gl;
    const passes = boxPasses(filter);
    if (passes.length % 2 !== 0) {
      throw new LanternaError(`a box filter of ${passes.length} passes: the passes must come in pairs`);
    }
    if (!this.scratch || this.scratch.width !== into.width || this.scratch.height !== into.height) {
      this.freeTarget(this.scratch);
      this.scratch = null;
      this.scratch = makeTarget(gl, into.width, into.height);
    }
    const pair = [into, this.scratch] as const;
    gl.useProgram(this.program.program);
    passes.forEach((pass, i) => {
      gl.bindFramebuffer(gl.FRAMEBUFFER, pair[(i + 1) % 2].framebuffer);
      gl.viewport(0, 0, into.width, into.height);
      gl.activeTexture(gl.TEXTURE1);
      gl.bindTexture(gl.TEXTURE_2D, pair[i % 2].texture);
      gl.bindSampler(1, null);
      gl.uniform1i(gl.getUniformLocation(this.program.program, U_SOURCE), 1);
      twgl.setUniforms(this.program, {
        [U_STEP]: pass.axis === 'x' ? [1, 0] : [0, 1],
        [U_RADIUS]: pass.radius,
      });
      gl.drawArrays(gl.TRIANGLES, 0, 3);
    });
    gl.bindTexture(gl.TEXTURE_2D, null);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    return into.texture;
  }

  /** Delete a quantity's targets (if the context is live). */
  free(targets: QuantityTargets | null): void {
    if (!targets || this.gl.isContextLost()) {
      return;
    }
    const all = [...targets.filtered, ...targets.extras];
    if (all.length > 1) {
      this.gl.deleteFramebuffer(targets.framebuffer);
    }
    for (const target of all) {
      deleteTarget(this.gl, target);
    }
  }

  private freeTarget(target: FloatTarget | null): void {
    if (target && !this.gl.isContextLost()) {
      deleteTarget(this.gl, target);
    }
  }

  /** Free the scratch target and the program (the caller frees its own targets). */
  destroy(): void {
    this.freeTarget(this.scratch);
    this.scratch = null;
    if (!this.gl.isContextLost()) {
      this.gl.deleteProgram(this.program.program);
    }
  }
}

function hasShape(targets: QuantityTargets, shape: QuantityShape): boolean {
  const t = targets.filtered[0];
  return t.width === shape.width && t.height === shape.height
    && targets.filtered.length === Math.max(1, shape.filtered) && targets.extras.length === shape.extras;
}

/** A framebuffer drawing output i to `targets[i]`. */
function drawingToAll(gl: WebGL2RenderingContext, targets: readonly FloatTarget[]): WebGLFramebuffer {
  const framebuffer = gl.createFramebuffer();
  gl.bindFramebuffer(gl.FRAMEBUFFER, framebuffer);
  const attachments = targets.map((target, i) => {
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0 + i, gl.TEXTURE_2D, target.texture, 0);
    return gl.COLOR_ATTACHMENT0 + i;
  });
  gl.drawBuffers(attachments);
  const status = gl.checkFramebufferStatus(gl.FRAMEBUFFER);
  gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  if (status !== gl.FRAMEBUFFER_COMPLETE) {
    gl.deleteFramebuffer(framebuffer);
    throw new FloatTargetsUnavailableError(`RGBA32F framebuffer of ${targets.length} outputs incomplete `
      + `(0x${status.toString(16)})`);
  }
  return framebuffer;
}

function deleteTarget(gl: WebGL2RenderingContext, target: FloatTarget): void {
  gl.deleteFramebuffer(target.framebuffer);
  gl.deleteTexture(target.texture);
}

/** A `width × height` RGBA32F target, nearest-sampled, clamped. */
function makeTarget(gl: WebGL2RenderingContext, width: number, height: number): FloatTarget {
  const texture = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, texture);
  gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA32F, width, height);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
  gl.bindTexture(gl.TEXTURE_2D, null);
  const framebuffer = gl.createFramebuffer();
  gl.bindFramebuffer(gl.FRAMEBUFFER, framebuffer);
  gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, texture, 0);
  const status = gl.checkFramebufferStatus(gl.FRAMEBUFFER);
  gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  if (status !== gl.FRAMEBUFFER_COMPLETE) {
    gl.deleteFramebuffer(framebuffer);
    gl.deleteTexture(texture);
    throw new FloatTargetsUnavailableError(`RGBA32F framebuffer incomplete (0x${status.toString(16)})`);
  }
  return { texture, framebuffer, width, height };
}
