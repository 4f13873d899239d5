/**
 * The lens's state and how `setLens` updates it. Pure: no DOM, no GL.
 */
import { LanternaError } from '../errors';
import { clampRadius } from '../math/lens';
import { DEFAULT_RENDER_MODE, type RenderMode } from '../render/modes';
import { DEFAULT_RENDER_PARAMS, mergeParams, type RenderParams } from '../render/params';

/** Where the active layer's overlay is shown relative to the lens. */
export type AnnotationDisplay = 'everywhere' | 'inside' | 'outside';

/** Every annotation display, in menu order. */
export const ANNOTATION_DISPLAYS: readonly AnnotationDisplay[] = ['everywhere', 'inside', 'outside'];

/** The lens: a circle in CSS px of the viewer element showing `layer` in `mode` over the base layer. */
export interface LensState {
  readonly enabled: boolean;
  /** Centre (x, y), CSS px of the viewer element. */
  readonly center: readonly [number, number];
  /** Radius, CSS px. */
  readonly radius: number;
  /** Id of the layer drawn inside the lens ('' = the active layer). */
  readonly layer: string;
  readonly mode: RenderMode;
  readonly params: RenderParams;
  /** Opacity of the lens layer over the base layer, 0–1. */
  readonly opacity: number;
  /** Where the active layer's overlay is shown. */
  readonly annotations: AnnotationDisplay;
}

/** The argument of `setLens`: any subset of the state (`params` are merged into the lens's parameters). */
export interface LensUpdate {
  enabled?: boolean;
  center?: readonly [number, number];
  radius?: number;
  layer?: string;
  mode?: RenderMode;
  params?: Partial<RenderParams>;
  opacity?: number;
  annotations?: AnnotationDisplay;
}

/** A lens argument that cannot be used (unknown display mode, malformed centre…). */
export class LensOptionError extends LanternaError {}

/** The initial lens for a viewer of `width × height` CSS px: off, centred, radius a fifth of the short side. */
export function initialLens(width: number, height: number): LensState {
  return {
    enabled: false,
    center: [width / 2, height / 2],
    radius: clampRadius(Math.min(width, height) / 5),
    layer: '',
    mode: DEFAULT_RENDER_MODE,
    params: DEFAULT_RENDER_PARAMS,
    opacity: 1,
    annotations: 'everywhere',
  };
}

/**
 * Apply an update: the centre must be two finite numbers, the radius is clamped, the opacity clamped
 * to 0–1, parameters merged and clamped. The layer and mode are checked by the viewer (it knows the layers).
 *
 * @throws {@link LensOptionError} on a malformed centre or an unknown annotation display
 */
export function updateLens(state: LensState, update: LensUpdate): LensState {
  let { center } = state;
  if (update.center !== undefined) {
    const [x, y] = update.center;
    if (update.center.length !== 2 || !Number.isFinite(x) || !Number.isFinite(y)) {
      throw new LensOptionError(`lens center must be [x, y] in CSS px, got ${JSON.stringify(update.center)}`);
    }
    center = [x, y];
  }
  if (update.annotations !== undefined && !ANNOTATION_DISPLAYS.includes(update.annotations)) {
    throw new LensOptionError(`lens annotations must be one of ${ANNOTATION_DISPLAYS.join(', ')}, `
      + `got ${JSON.stringify(update.annotations)}`);
  }
  const opacity = update.opacity === undefined ? state.opacity
    : Number.isFinite(update.opacity) ? Math.min(1, Math.max(0, update.opacity)) : state.opacity;
  return {
    enabled: update.enabled ?? state.enabled,
    center,
    radius: update.radius === undefined ? state.radius : clampRadius(update.radius),
    layer: update.layer ?? state.layer,
    mode: update.mode ?? state.mode,
    params: update.params === undefined ? state.params : mergeParams(state.params, update.params),
    opacity,
    annotations: update.annotations ?? state.annotations,
  };
}
