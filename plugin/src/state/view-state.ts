/**
 * The view state: everything that decides what the viewer shows (layer, mode, parameters, light,
 * overlays, lens, the image region in view), in screen-independent units, and its rounding.
 * Pure: no DOM, no GL.
 *
 * Geometry is in full-resolution **image pixels**, the lens's centre and radius included: a state
 * saved on one screen and restored on another of a different size shows the same region, and the
 * lens over the same detail (`docs/viewer-api.md`, "View state").
 */
import type { AnnotationDisplay } from '../lens/lens-state';
import { DEFAULT_RENDER_MODE, type RenderMode } from '../render/modes';
import { DEFAULT_RENDER_PARAMS, PARAM_NAMES, PARAM_SPECS, type RenderParams } from '../render/params';

/** A rectangle of the image: x, y, width, height in full-resolution image pixels. */
export type ImageRect = readonly [number, number, number, number];

/** The lens part of a {@link ViewState}. */
export interface LensViewState {
  readonly enabled: boolean;
  /** Centre (x, y), image pixels. */
  readonly center: readonly [number, number];
  /** Radius, image pixels. */
  readonly radius: number;
  /** Id of the layer in the lens ('' = the active layer). */
  readonly layer: string;
  readonly mode: RenderMode;
  readonly params: RenderParams;
  readonly opacity: number;
  readonly annotations: AnnotationDisplay;
}

/** What `LanternaViewer.getState` returns and `setState` restores. */
export interface ViewState {
  readonly layer: string;
  readonly mode: RenderMode;
  /** Every render parameter. */
  readonly params: RenderParams;
  /** The light's projection (lu, lv). */
  readonly light: readonly [number, number];
  readonly overlays: boolean;
  /** The image region in view (the whole viewer, not clipped to the image). */
  readonly view: ImageRect;
  /** Rotation of the view, degrees clockwise. */
  readonly rotation: number;
  readonly lens: LensViewState;
}

/** The argument of `setState`: any subset (the lens too); what is left out stays as it is. */
export type ViewStateUpdate = Partial<Omit<ViewState, 'lens'>> & { readonly lens?: Partial<LensViewState> };

/** The lens of a state that does not say otherwise (off, following the active layer). */
export const DEFAULT_LENS_VIEW: LensViewState = Object.freeze({
  enabled: false, center: [0, 0] as const, radius: 0, layer: '', mode: DEFAULT_RENDER_MODE,
  params: DEFAULT_RENDER_PARAMS, opacity: 1, annotations: 'everywhere' as const,
});

/** Round `v` to `decimals` decimals (a number that prints as at most that many). */
export function roundTo(v: number, decimals: number): number {
  const f = 10 ** decimals;
  return Math.round(v * f) / f;
}

/** Decimals kept of the light's lu and lv. */
export const LIGHT_DECIMALS = 3;
/** Decimals kept of the lens opacity. */
export const OPACITY_DECIMALS = 3;

/** Decimals kept of a parameter: one more than its slider step has. */
export function paramDecimals(name: keyof RenderParams): number {
  return Math.max(0, Math.ceil(-Math.log10(PARAM_SPECS[name].step) - 1e-9)) + 1;
}

/**
 * Decimals kept of image-pixel geometry for a view `width` image px wide: a step of at most 1/10⁷
 * of the view (10⁻⁴ px for a 1024-px-wide view), never finer than 10⁻⁸ px: so fine that showing
 * the rounded view moves nothing a viewer (or a test) can see.
 */
export function geometryDecimals(width: number): number {
  const w = Number.isFinite(width) && width > 0 ? width : 1;
  return Math.min(8, Math.max(0, Math.ceil(-Math.log10(w / 1e7))));
}

/** The light rounded to {@link LIGHT_DECIMALS}, stepped towards 0 until it lies in the unit disk. */
export function roundLight(light: readonly [number, number]): [number, number] {
  const step = 10 ** -LIGHT_DECIMALS;
  let [u, v] = light.map((c) => roundTo(Number.isFinite(c) ? c : 0, LIGHT_DECIMALS)) as [number, number];
  while (u * u + v * v > 1) {
    if (Math.abs(u) >= Math.abs(v)) {
      u = roundTo(u - Math.sign(u) * step, LIGHT_DECIMALS);
    } else {
      v = roundTo(v - Math.sign(v) * step, LIGHT_DECIMALS);
    }
  }
  return [u, v];
}

/** Every parameter rounded to {@link paramDecimals}. */
export function roundParams(params: RenderParams): RenderParams {
  return Object.fromEntries(PARAM_NAMES.map((n) => [n, roundTo(params[n], paramDecimals(n))])) as unknown as RenderParams;
}

/**
 * The state as a link stores it: every number rounded (idempotent: a rounded state rounds to
 * itself). Restoring the rounded state shows exactly what the link shows.
 */
export function roundState(state: ViewState): ViewState {
  const g = geometryDecimals(state.view[2]);
  const r = (v: number): number => roundTo(v, g);
  const { lens } = state;
  return {
    ...state,
    params: roundParams(state.params),
    light: roundLight(state.light),
    view: [r(state.view[0]), r(state.view[1]), r(state.view[2]), r(state.view[3])],
    rotation: roundTo(state.rotation, 2),
    lens: {
      ...lens,
      center: [r(lens.center[0]), r(lens.center[1])],
      radius: r(lens.radius),
      params: roundParams(lens.params),
      opacity: roundTo(lens.opacity, OPACITY_DECIMALS),
    },
  };
}

/**
 * Whether two states show the same thing, geometry compared to within `slack` steps of its rounding
 * (the viewport's own floating-point round trip), everything else exactly.
 */
export function sameState(a: ViewState, b: ViewState, slack = 1): boolean {
  const tol = slack * 10 ** -geometryDecimals(a.view[2]);
  const near = (x: readonly number[], y: readonly number[]): boolean => x.every((v, i) => Math.abs(v - (y[i] ?? NaN)) <= tol);
  const same = (x: RenderParams, y: RenderParams): boolean => PARAM_NAMES.every((n) => x[n] === y[n]);
  const la = a.lens;
  const lb = b.lens;
  return a.layer === b.layer && a.mode === b.mode && same(a.params, b.params) && a.light[0] === b.light[0]
    && a.light[1] === b.light[1] && a.overlays === b.overlays && a.rotation === b.rotation && near(a.view, b.view)
    && la.enabled === lb.enabled && la.layer === lb.layer && la.mode === lb.mode && same(la.params, lb.params)
    && la.opacity === lb.opacity && la.annotations === lb.annotations
    && (!la.enabled || near([...la.center, la.radius], [...lb.center, lb.radius]));
}
