/**
 * Compiling a GL program with twgl, with its errors turned into a {@link ShaderError}.
 */
import * as twgl from 'twgl.js';
import { LanternaError } from '../errors';

/** A shader failed to compile or link. */
export class ShaderError extends LanternaError {}

/**
 * Compile a program from a vertex and a fragment shader.
 *
 * @param name - the program's name in the error message
 * @throws {@link ShaderError} if it fails
 */
export function compileProgram(gl: WebGL2RenderingContext, vertex: string, fragment: string, name: string):
  twgl.ProgramInfo {
  const errors: string[] = [];
  const info = twgl.createProgramInfo(gl, [vertex, fragment], {
    errorCallback: (msg: string) => { errors.push(msg); },
  }) as twgl.ProgramInfo | null;
  if (!info) {
    throw new ShaderError(`program ${name} failed: ${errors.join('\n')}`);
  }
  return info;
}
