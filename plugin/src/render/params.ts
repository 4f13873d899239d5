/**
 * Render parameters: defaults, ranges and clamping (`docs/rendering.md`, "Parameters"). Pure.
 */
import type { RenderMode, ShadingClass } from './modes';

/** Every render parameter. */
export interface RenderParams {
  /** Multiplies the shaded value before the first clamp (not for image layers). */
  readonly lightIntensity: number;
  /** Post step: `c ← clamp01(c)^(1/gamma)`. */
  readonly gamma: number;
  /** Post step: `c ← clamp01(c + brightness)`. */
  readonly brightness: number;
  /** `specular`: diffuse weight. */
  readonly specKd: number;
  /** `specular`: highlight weight. */
  readonly specKs: number;
  /** `specular`: highlight exponent. */
  readonly specExponent: number;
  /** `diffuseGain`: gain g. */
  readonly diffuseGain: number;
  /** `unsharp*`: sharpening gain g. */
  readonly umGain: number;
  /** `unsharpNormals`: diffuse weight. */
  readonly umKd: number;
  /** `unsharpNormals`: ambient weight. */
  readonly umEnv: number;
}
/** A parameter name. */
export type RenderParamName = keyof RenderParams;

/** Range, default and step of one parameter (for sliders). */
export interface ParamSpec {
  readonly min: number;
  readonly max: number;
  readonly default: number;
  readonly step: number;
  readonly label: string;
}

/** The contract's parameter table. */
export const PARAM_SPECS: Readonly<Record<RenderParamName, ParamSpec>> = {
  lightIntensity: { min: 0, max: 4, default: 1, step: 0.01, label: 'Light intensity' },
  gamma: { min: 0.2, max: 5, default: 1, step: 0.01, label: 'Gamma' },
  brightness: { min: -1, max: 1, default: 0, step: 0.01, label: 'Brightness' },
  specKd: { min: 0, max: 1, default: 0.4, step: 0.01, label: 'Diffuse (kd)' },
  specKs: { min: 0, max: 1, default: 0.7, step: 0.01, label: 'Specular (ks)' },
  specExponent: { min: 1, max: 150, default: 75, step: 1, label: 'Exponent' },
  diffuseGain: { min: 1, max: 10, default: 2, step: 0.1, label: 'Gain' },
  umGain: { min: 0.01, max: 6, default: 1, step: 0.01, label: 'Sharpening gain' },
  umKd: { min: 0.5, max: 1.5, default: 1, step: 0.01, label: 'Diffuse (kd)' },
  umEnv: { min: 0.1, max: 2, default: 0.5, step: 0.01, label: 'Ambient' },
};

/** Parameter names in table order. */
export const PARAM_NAMES = Object.keys(PARAM_SPECS) as RenderParamName[];

/** The default parameters. */
export const DEFAULT_RENDER_PARAMS: RenderParams = Object.freeze(
  Object.fromEntries(PARAM_NAMES.map((n) => [n, PARAM_SPECS[n].default])) as unknown as RenderParams,
);

/**
 * Merge a partial update into `base`, clamping each value to its range. Unknown keys and
 * non-finite values are ignored.
 */
export function mergeParams(base: RenderParams, update: Partial<Record<string, unknown>>): RenderParams {
  const out: Record<string, number> = { ...base };
  for (const name of PARAM_NAMES) {
    const v = update[name];
    if (typeof v === 'number' && Number.isFinite(v)) {
      const { min, max } = PARAM_SPECS[name];
      out[name] = Math.min(max, Math.max(min, v));
    }
  }
  return out as unknown as RenderParams;
}

/** Modes in which `lightIntensity` changes the picture (on shaded layers). */
const LIT_MODES: readonly RenderMode[] = [
  'color', 'diffuse', 'achromatic', 'specular', 'diffuseGain', 'unsharpNormals', 'unsharpCoefficients',
  'unsharpLuminance', 'unsharpImage',
];

/** The parameters that affect a mode on a layer of class `cls` (for showing the right sliders). */
export function relevantParams(mode: RenderMode, cls: ShadingClass): RenderParamName[] {
  const out: RenderParamName[] = [];
  if (cls !== 'flat' && LIT_MODES.includes(mode)) {
    out.push('lightIntensity');
  }
  if (mode === 'specular') {
    out.push('specKd', 'specKs', 'specExponent');
  } else if (mode === 'diffuseGain') {
    out.push('diffuseGain');
  } else if (mode.startsWith('unsharp')) {
    out.push('umGain');
    if (mode === 'unsharpNormals') {
      out.push('umKd', 'umEnv');
    }
  }
  out.push('gamma', 'brightness');
  return out;
}
