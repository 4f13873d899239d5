/**
 * The lens pass and its render target: the lens layer is drawn into a canvas-sized RGBA8 texture
 * (limited by a scissor box to the lens), then composited over the base layer inside the circle.
 */
import * as twgl from 'twgl.js';
import { FULLSCREEN_VERTEX_SHADER } from '../gl/glsl/box.glsl';
import { LENS_FRAGMENT_SHADER } from '../gl/glsl/composite.glsl';
import { U_LENS_CIRCLE, U_OPACITY, U_SOURCE } from '../gl/uniforms';
import { LanternaError } from '../errors';
import { compileProgram } from '../gl/compile';

/** A circle in device pixels, y up (`gl_FragCoord`). */
export interface DeviceCircle {
  readonly x: number;
  readonly y: number;
  readonly radius: number;
}

/** Scissor box `[x, y, w, h]` (device px, y up, clamped to the canvas) around a circle, 1 px margin. */
export function scissorBox(circle: DeviceCircle, width: number, height: number): [number, number, number, number] {
  const x0 = Math.max(0, Math.floor(circle.x - circle.radius - 1));
  const y0 = Math.max(0, Math.floor(circle.y - circle.radius - 1));
  const x1 = Math.min(width, Math.ceil(circle.x + circle.radius + 1));
  const y1 = Math.min(height, Math.ceil(circle.y + circle.radius + 1));
  return [x0, y0, Math.max(0, x1 - x0), Math.max(0, y1 - y0)];
}

/** The target texture, its framebuffer and the composite program. */
export class LensTarget {
  private texture: WebGLTexture | null = null;
  private fb: WebGLFramebuffer | null = null;
  private width = 0;
  private height = 0;
  private readonly program: twgl.ProgramInfo;

  constructor(private readonly gl: WebGL2RenderingContext) {
    this.program = compileProgram(gl, FULLSCREEN_VERTEX_SHADER, LENS_FRAGMENT_SHADER, 'lens-composite');
  }

  /** The framebuffer to draw the lens layer into (valid after {@link LensTarget.begin}). */
  get framebuffer(): WebGLFramebuffer | null {
    return this.fb;
  }

  /**
   * The lens pass: clear the target around `circle`, let `draw` draw the lens layer into it
   * (framebuffer and scissor box given), then composite it inside the circle with `opacity`.
   */
  drawLens(circle: DeviceCircle, opacity: number,
    draw: (target: WebGLFramebuffer | null, box: readonly [number, number, number, number]) => void): void {
    const gl = this.gl;
    const box = scissorBox(circle, gl.drawingBufferWidth, gl.drawingBufferHeight);
    this.begin(gl.drawingBufferWidth, gl.drawingBufferHeight, box);
    draw(this.fb, box);
    this.composite(circle, opacity, box);
  }

  /** Bind the target (resized to the canvas) and clear the scissor box to transparent. */
  begin(width: number, height: number, box: readonly [number, number, number, number]): void {
    const gl = this.gl;
    this.ensure(width, height);
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.fb);
    gl.viewport(0, 0, width, height);
    gl.enable(gl.SCISSOR_TEST);
    gl.scissor(box[0], box[1], box[2], box[3]);
    gl.clearColor(0, 0, 0, 0);
    gl.clear(gl.COLOR_BUFFER_BIT);
  }

  /** Composite the target over the default framebuffer inside `circle` with `opacity`. */
  composite(circle: DeviceCircle, opacity: number, box: readonly [number, number, number, number]): void {
    const gl = this.gl;
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.viewport(0, 0, this.width, this.height);
    gl.enable(gl.SCISSOR_TEST);
    gl.scissor(box[0], box[1], box[2], box[3]);
    gl.enable(gl.BLEND);
    gl.blendFunc(gl.ONE, gl.ONE_MINUS_SRC_ALPHA);
    gl.useProgram(this.program.program);
    gl.activeTexture(gl.TEXTURE1);
    gl.bindTexture(gl.TEXTURE_2D, this.texture);
    gl.bindSampler(1, null);
    gl.uniform1i(gl.getUniformLocation(this.program.program, U_SOURCE), 1);
    twgl.setUniforms(this.program, {
      [U_LENS_CIRCLE]: [circle.x, circle.y, circle.radius],
      [U_OPACITY]: opacity,
    });
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    gl.disable(gl.BLEND);
    gl.disable(gl.SCISSOR_TEST);
    gl.bindTexture(gl.TEXTURE_2D, null);
    gl.activeTexture(gl.TEXTURE0);
  }

  /** Free the target and the program. */
  destroy(): void {
    this.free();
    if (!this.gl.isContextLost()) {
      this.gl.deleteProgram(this.program.program);
    }
  }

  private ensure(width: number, height: number): void {
    if (this.fb && this.width === width && this.height === height) {
      return;
    }
    this.free();
    const gl = this.gl;
    this.texture = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, this.texture);
    gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA8, width, height);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    gl.bindTexture(gl.TEXTURE_2D, null);
    this.fb = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.fb);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, this.texture, 0);
    const status = gl.checkFramebufferStatus(gl.FRAMEBUFFER);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    if (status !== gl.FRAMEBUFFER_COMPLETE) {
      throw new LanternaError(`lens framebuffer incomplete (0x${status.toString(16)})`);
    }
    this.width = width;
    this.height = height;
  }

  private free(): void {
    if (!this.gl.isContextLost()) {
      this.gl.deleteFramebuffer(this.fb);
      this.gl.deleteTexture(this.texture);
    }
    this.fb = null;
    this.texture = null;
  }
}
