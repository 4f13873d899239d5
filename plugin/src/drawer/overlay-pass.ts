/**
 * The overlay pass: annotation overlay tiles drawn over the frame, filtered on premultiplied colour,
 * composited source-over, everywhere or only inside or outside the lens.
 */
import * as twgl from 'twgl.js';
import { OVERLAY_FRAGMENT_SHADER } from '../gl/glsl/composite.glsl';
import { QUAD_VERTEX_SHADER } from '../gl/glsl/quad.vert';
import { U_LENS_CIRCLE, U_MASK, U_MATRIX, U_PLANES, U_SMOOTH, U_TEX_SCALE } from '../gl/uniforms';
import type { AnnotationDisplay } from '../lens/lens-state';
import { compileProgram } from '../gl/compile';
import type { Mat3 } from '../math/matrix';
import type { DeviceCircle } from './lens-target';

/** Overlay mask `(a, b)`: `m = a + b · inside`. */
export const OVERLAY_MASKS: Readonly<Record<AnnotationDisplay, readonly [number, number]>> = {
  everywhere: [1, 0], inside: [0, 1], outside: [1, -1],
};

/** One overlay tile: its texture array (plane 0 = RGBA, straight alpha), placement and valid part. */
export interface OverlayQuad {
  readonly texture: WebGLTexture;
  readonly matrix: Mat3;
  readonly texScale: readonly [number, number];
}

/** The overlay program and its draw call. */
export class OverlayPass {
  private readonly program: twgl.ProgramInfo;

  constructor(private readonly gl: WebGL2RenderingContext) {
    this.program = compileProgram(gl, QUAD_VERTEX_SHADER, OVERLAY_FRAGMENT_SHADER, 'overlay');
  }

  /**
   * Draw `quads` onto the canvas. `circle` is the lens (null = off: overlays show everywhere);
   * `smooth`: bilinear filtering of the premultiplied texels, else the nearest texel.
   */
  draw(quads: Iterable<OverlayQuad>, circle: DeviceCircle | null, display: AnnotationDisplay,
    smooth: boolean): void {
    const gl = this.gl;
    const program = this.program;
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.viewport(0, 0, gl.drawingBufferWidth, gl.drawingBufferHeight);
    gl.useProgram(program.program);
    gl.uniform1i(gl.getUniformLocation(program.program, U_PLANES), 0);
    twgl.setUniforms(program, {
      [U_LENS_CIRCLE]: circle ? [circle.x, circle.y, circle.radius] : [0, 0, 0],
      [U_MASK]: OVERLAY_MASKS[circle ? display : 'everywhere'],
      [U_SMOOTH]: smooth ? 1 : 0,
    });
    gl.activeTexture(gl.TEXTURE0);
    gl.bindSampler(0, null); // texelFetch: the shader filters
    gl.enable(gl.BLEND);
    gl.blendFunc(gl.ONE, gl.ONE_MINUS_SRC_ALPHA);
    for (const quad of quads) {
      gl.bindTexture(gl.TEXTURE_2D_ARRAY, quad.texture);
      twgl.setUniforms(program, { [U_MATRIX]: new Float32Array(quad.matrix), [U_TEX_SCALE]: quad.texScale });
      gl.drawArrays(gl.TRIANGLE_STRIP, 0, 4);
    }
    gl.disable(gl.BLEND);
  }

  /** Free the program. */
  destroy(): void {
    if (!this.gl.isContextLost()) {
      this.gl.deleteProgram(this.program.program);
    }
  }
}
