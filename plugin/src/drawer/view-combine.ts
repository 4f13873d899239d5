/**
 * The full-screen combine of the modes that keep their per-pixel inputs for the view
 * (`combinesFromView`: `unsharpNormals`): reads the filtered quantity and the kept extras at each
 * device pixel, shades with the light and the parameters, and writes where the layer was drawn.
 */
import * as twgl from 'twgl.js';
import { FULLSCREEN_VERTEX_SHADER } from '../gl/glsl/box.glsl';
import { viewCombineFragmentShader } from '../gl/glsl/view-combine.glsl';
import { U_FILTERED, U_VIEW_ALBEDO, U_VIEW_NORMAL } from '../gl/uniforms';
import { compileProgram } from '../gl/compile';
import type { LayerUniforms } from '../layers/layer-uniforms';
import type { QuantityTargets } from './screen-filter';

/** The texture units of the filtered quantity and the extras (unit 0 is the planes'). */
const UNITS: readonly (readonly [string, number])[] = [[U_FILTERED, 1], [U_VIEW_NORMAL, 2], [U_VIEW_ALBEDO, 3]];

/** The full-screen combine programs of one GL context (one per post-step variant), compiled on first use. */
export class ViewCombine {
  private readonly programs = new Map<boolean, twgl.ProgramInfo>();

  constructor(private readonly gl: WebGL2RenderingContext) {}

  /**
   * The program for `gammaOne` (the post step for gamma = 1).
   *
   * @throws {@link ShaderError} if it does not compile
   */
  program(gammaOne: boolean): twgl.ProgramInfo {
    let info = this.programs.get(gammaOne);
    if (!info) {
      info = compileProgram(this.gl, FULLSCREEN_VERTEX_SHADER, viewCombineFragmentShader(gammaOne),
        `unsharpNormals-view-combine${gammaOne ? '/gamma1' : ''}`);
      this.programs.set(gammaOne, info);
    }
    return info;
  }

  /** Combine `kept` (the filtered quantity, then the normal and albedo) into the bound framebuffer. */
  draw(kept: QuantityTargets, uniforms: LayerUniforms, gammaOne: boolean): void {
    const gl = this.gl;
    const info = this.program(gammaOne);
    gl.useProgram(info.program);
    twgl.setUniforms(info, uniforms);
    const textures = [kept.filtered[0], ...kept.extras];
    UNITS.forEach(([name, unit], i) => {
      gl.activeTexture(gl.TEXTURE0 + unit);
      gl.bindTexture(gl.TEXTURE_2D, textures[i]?.texture ?? null);
      gl.bindSampler(unit, null);
      gl.uniform1i(gl.getUniformLocation(info.program, name), unit);
    });
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    for (const [, unit] of UNITS.slice(1)) {
      gl.activeTexture(gl.TEXTURE0 + unit);
      gl.bindTexture(gl.TEXTURE_2D, null);
    }
    gl.activeTexture(gl.TEXTURE0);
  }

  /** Delete the programs (if the context is live). */
  destroy(): void {
    if (!this.gl.isContextLost()) {
      for (const info of this.programs.values()) {
        this.gl.deleteProgram(info.program);
      }
    }
    this.programs.clear();
  }
}
