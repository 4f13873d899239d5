/**
 * Layer programs: one twgl program per layer kind, chosen from a table.
 */
import * as twgl from 'twgl.js';
import { QUAD_VERTEX_SHADER } from '../gl/glsl/quad.vert';
import type { RelightLayer } from '../iiif/relight-service';
import { IMAGE_FRAGMENT_SHADER } from './image/image.frag';
import { PTM_LRGB_FRAGMENT_SHADER, PTM_RGB_FRAGMENT_SHADER } from './ptm/ptm.frag';
import { LanternaError } from '../iiif/errors';

/** Program kinds, one per fragment shader. */
export type ProgramKind = 'ptm-lrgb' | 'ptm-rgb' | 'image';

/** Fragment shader source per program kind. */
export const FRAGMENT_SHADERS: Readonly<Record<ProgramKind, string>> = {
  'ptm-lrgb': PTM_LRGB_FRAGMENT_SHADER,
  'ptm-rgb': PTM_RGB_FRAGMENT_SHADER,
  image: IMAGE_FRAGMENT_SHADER,
};

/** A shader failed to compile or link. */
export class ShaderError extends LanternaError {}

/** The program kind that draws a layer. */
export function programKind(layer: RelightLayer): ProgramKind {
  if (layer.layerType === 'image') {
    return 'image';
  }
  return layer.colorspace === 'lrgb' ? 'ptm-lrgb' : 'ptm-rgb';
}

/**
 * Compile every layer program.
 *
 * @throws {@link ShaderError} if one fails
 */
export function createPrograms(gl: WebGL2RenderingContext): Record<ProgramKind, twgl.ProgramInfo> {
  const out: Partial<Record<ProgramKind, twgl.ProgramInfo>> = {};
  for (const kind of Object.keys(FRAGMENT_SHADERS) as ProgramKind[]) {
    const errors: string[] = [];
    const info = twgl.createProgramInfo(gl, [QUAD_VERTEX_SHADER, FRAGMENT_SHADERS[kind]], {
      errorCallback: (msg: string) => { errors.push(msg); },
    }) as twgl.ProgramInfo | null;
    if (!info) {
      throw new ShaderError(`program ${kind} failed: ${errors.join('\n')}`);
    }
    out[kind] = info;
  }
  return out as Record<ProgramKind, twgl.ProgramInfo>;
}
