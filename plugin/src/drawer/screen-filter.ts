/**
 * Float render targets and box passes for the screen-space unsharp modes: the quantity is drawn
 * into target 0, then each box pass ping-pongs between the two targets.
 */
import * as twgl from 'twgl.js';
import { BOX_FRAGMENT_SHADER, FULLSCREEN_VERTEX_SHADER } from '../gl/glsl/box.glsl';
import { U_RADIUS, U_SOURCE, U_STEP } from '../gl/uniforms';
import { LanternaError } from '../errors';
import { compileProgram } from '../gl/compile';
import { boxPasses, type BoxFilter } from '../render/filter-plan';

/** Float colour buffers are not renderable in this context (no `EXT_color_buffer_float`). */
export class FloatTargetsUnavailableError extends LanternaError {}

interface Target {
  texture: WebGLTexture;
  framebuffer: WebGLFramebuffer;
}

/** Two canvas-sized RGBA32F targets and the box-pass program. */
export class ScreenFilter {
  private targets: [Target, Target] | null = null;
  private width = 0;
  private height = 0;
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

  /** Bind target 0 (sized to width × height, cleared to 0) for drawing the quantity. */
  beginQuantity(width: number, height: number): void {
    const gl = this.gl;
    const targets = this.ensure(width, height);
    gl.bindFramebuffer(gl.FRAMEBUFFER, targets[0].framebuffer);
    gl.viewport(0, 0, width, height);
    gl.clearColor(0, 0, 0, 0);
    gl.clear(gl.COLOR_BUFFER_BIT);
  }

  /**
   * Run the filter's box passes on target 0; returns the texture holding the result.
   * Leaves the default framebuffer unbound (the caller binds its own).
   */
  filter(filter: BoxFilter): WebGLTexture {
    const gl = this.gl;
    const targets = this.ensure(this.width, this.height);
    gl.useProgram(this.program.program);
    let src = 0;
    for (const pass of boxPasses(filter)) {
      const dst = 1 - src;
      gl.bindFramebuffer(gl.FRAMEBUFFER, targets[dst].framebuffer);
      gl.viewport(0, 0, this.width, this.height);
      gl.activeTexture(gl.TEXTURE1);
      gl.bindTexture(gl.TEXTURE_2D, targets[src].texture);
      gl.bindSampler(1, null);
      gl.uniform1i(gl.getUniformLocation(this.program.program, U_SOURCE), 1);
      twgl.setUniforms(this.program, {
        [U_STEP]: pass.axis === 'x' ? [1, 0] : [0, 1],
        [U_RADIUS]: pass.radius,
      });
      gl.drawArrays(gl.TRIANGLES, 0, 3);
      src = dst;
    }
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    return targets[src as 0 | 1].texture;
  }

  /** Free the targets and the program. */
  destroy(): void {
    this.freeTargets();
    if (!this.gl.isContextLost()) {
      this.gl.deleteProgram(this.program.program);
    }
  }

  private ensure(width: number, height: number): [Target, Target] {
    if (this.targets && this.width === width && this.height === height) {
      return this.targets;
    }
    this.freeTargets();
    const make = (): Target => {
      const gl = this.gl;
      const texture = gl.createTexture();
      gl.bindTexture(gl.TEXTURE_2D, texture);
      gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA32F, width, height);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
      const framebuffer = gl.createFramebuffer();
      gl.bindFramebuffer(gl.FRAMEBUFFER, framebuffer);
      gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, texture, 0);
      const status = gl.checkFramebufferStatus(gl.FRAMEBUFFER);
      gl.bindFramebuffer(gl.FRAMEBUFFER, null);
      if (status !== gl.FRAMEBUFFER_COMPLETE) {
        throw new FloatTargetsUnavailableError(`RGBA32F framebuffer incomplete (0x${status.toString(16)})`);
      }
      return { texture, framebuffer };
    };
    this.targets = [make(), make()];
    this.width = width;
    this.height = height;
    return this.targets;
  }

  private freeTargets(): void {
    if (this.targets && !this.gl.isContextLost()) {
      for (const t of this.targets) {
        this.gl.deleteFramebuffer(t.framebuffer);
        this.gl.deleteTexture(t.texture);
      }
    }
    this.targets = null;
  }
}
