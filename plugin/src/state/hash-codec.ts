/**
 * The view state in a URL hash (`docs/viewer-api.md`, "The link format"), readable and short:
 *
 * `#v=1&layer=ptm&mode=specular&light=0.5,-0.3&p=specKs:0.8&view=120,80,640,480&lens=400,300,60&lensMode=normals`
 *
 * Parameters equal to their defaults, and lens fields equal to the default lens's, are left out.
 * Decoding never throws: an unknown key or a malformed value is skipped and named in `problems`.
 * Pure: no DOM.
 */
import { ANNOTATION_DISPLAYS, type AnnotationDisplay } from '../lens/lens-state';
import { isRenderMode, type RenderMode } from '../render/modes';
import { DEFAULT_RENDER_PARAMS, PARAM_NAMES, mergeParams, type RenderParamName, type RenderParams } from '../render/params';
import { DEFAULT_LENS_VIEW, roundState, type LensViewState, type ViewState, type ViewStateUpdate } from './view-state';

/** The format version, the hash's first key (`v=1`). */
export const HASH_VERSION = '1';

/** What {@link decodeHash} found. */
export interface DecodedHash {
  /** The state the link holds (null: the hash is not a view link, e.g. empty). */
  readonly state: ViewStateUpdate | null;
  /** One line per key or value that was skipped. */
  readonly problems: readonly string[];
}

const numbers = (values: readonly number[]): string => values.map((v) => String(v)).join(',');

/** `name:value,…` of the parameters that differ from their defaults ('' if none). */
function paramList(params: RenderParams): string {
  return PARAM_NAMES.filter((n) => params[n] !== DEFAULT_RENDER_PARAMS[n]).map((n) => `${n}:${params[n]}`).join(',');
}

/**
 * The hash (with its `#`) of a state, rounded first ({@link roundState}): restore the rounded
 * state on this viewer too, so that what it shows is what the link shows.
 */
export function encodeHash(state: ViewState): string {
  const s = roundState(state);
  const parts: [string, string][] = [
    ['v', HASH_VERSION], ['layer', encodeURIComponent(s.layer)], ['mode', s.mode], ['light', numbers(s.light)],
  ];
  const p = paramList(s.params);
  if (p) {
    parts.push(['p', p]);
  }
  parts.push(['view', numbers(s.view)]);
  if (s.rotation !== 0) {
    parts.push(['rot', String(s.rotation)]);
  }
  if (!s.overlays) {
    parts.push(['ov', '0']);
  }
  const lens = s.lens;
  if (lens.enabled) {
    parts.push(['lens', numbers([...lens.center, lens.radius])]);
  }
  if (lens.layer && lens.layer !== s.layer) {
    parts.push(['lensLayer', encodeURIComponent(lens.layer)]);
  }
  if (lens.mode !== DEFAULT_LENS_VIEW.mode) {
    parts.push(['lensMode', lens.mode]);
  }
  const lp = paramList(lens.params);
  if (lp) {
    parts.push(['lensP', lp]);
  }
  if (lens.opacity !== DEFAULT_LENS_VIEW.opacity) {
    parts.push(['lensOpacity', String(lens.opacity)]);
  }
  if (lens.annotations !== DEFAULT_LENS_VIEW.annotations) {
    parts.push(['lensAnn', lens.annotations]);
  }
  return `#${parts.map(([k, v]) => `${k}=${v}`).join('&')}`;
}

/** `count` comma-separated finite numbers, or null. */
function numberList(text: string, count: number): number[] | null {
  const values = text.split(',').map((t) => (t.trim() === '' ? Number.NaN : Number(t)));
  return values.length === count && values.every(Number.isFinite) ? values : null;
}

/** Parameters from `name:value,…` over the defaults; unknown names and bad values are problems. */
function readParams(key: string, text: string, problems: string[]): RenderParams {
  const update: Partial<Record<RenderParamName, number>> = {};
  for (const item of text.split(',')) {
    const [name = '', value = '', ...rest] = item.split(':');
    const v = value.trim() === '' ? Number.NaN : Number(value);
    if (!(PARAM_NAMES as readonly string[]).includes(name)) {
      problems.push(`${key}: no render parameter ${JSON.stringify(name)}`);
    } else if (rest.length > 0 || !Number.isFinite(v)) {
      problems.push(`${key}: ${name} must be a number, got ${JSON.stringify(item)}`);
    } else {
      update[name as RenderParamName] = v;
    }
  }
  return mergeParams(DEFAULT_RENDER_PARAMS, update);
}

type Fields = { -readonly [K in keyof ViewStateUpdate]: ViewStateUpdate[K] };
type LensFields = { -readonly [K in keyof LensViewState]?: LensViewState[K] };

/** How each key is read into the state (a table: one reader per key). */
const READERS: Readonly<Record<string, (text: string, out: Fields, lens: LensFields) => string | null>> = {
  layer: (t, out) => (t ? ((out.layer = t), null) : 'layer: empty'),
  mode: (t, out) => (isRenderMode(t) ? ((out.mode = t), null) : `mode: no render mode ${JSON.stringify(t)}`),
  light: (t, out) => {
    const v = numberList(t, 2);
    return v ? ((out.light = [v[0] ?? 0, v[1] ?? 0]), null) : `light: needs lu,lv, got ${JSON.stringify(t)}`;
  },
  view: (t, out) => {
    const v = numberList(t, 4);
    return v && (v[2] ?? 0) > 0 && (v[3] ?? 0) > 0
      ? ((out.view = [v[0] ?? 0, v[1] ?? 0, v[2] ?? 0, v[3] ?? 0]), null)
      : `view: needs x,y,w,h with w and h > 0, got ${JSON.stringify(t)}`;
  },
  rot: (t, out) => {
    const v = numberList(t, 1);
    return v ? ((out.rotation = v[0] ?? 0), null) : `rot: needs degrees, got ${JSON.stringify(t)}`;
  },
  ov: (t, out) => (t === '0' || t === '1' ? ((out.overlays = t === '1'), null) : `ov: needs 0 or 1, got ${JSON.stringify(t)}`),
  lens: (t, _out, lens) => {
    const v = numberList(t, 3);
    return v && (v[2] ?? 0) > 0
      ? (Object.assign(lens, { enabled: true, center: [v[0] ?? 0, v[1] ?? 0], radius: v[2] ?? 0 }), null)
      : `lens: needs x,y,radius with radius > 0, got ${JSON.stringify(t)}`;
  },
  lensLayer: (t, _out, lens) => (t ? ((lens.layer = t), null) : 'lensLayer: empty'),
  lensMode: (t, _out, lens) => (isRenderMode(t) ? ((lens.mode = t), null)
    : `lensMode: no render mode ${JSON.stringify(t)}`),
  lensOpacity: (t, _out, lens) => {
    const v = numberList(t, 1)?.[0];
    return v !== undefined && v >= 0 && v <= 1 ? ((lens.opacity = v), null)
      : `lensOpacity: needs a number 0–1, got ${JSON.stringify(t)}`;
  },
  lensAnn: (t, _out, lens) => ((ANNOTATION_DISPLAYS as readonly string[]).includes(t)
    ? ((lens.annotations = t as AnnotationDisplay), null)
    : `lensAnn: needs one of ${ANNOTATION_DISPLAYS.join(', ')}, got ${JSON.stringify(t)}`),
};

/**
 * Read a hash (with or without its `#`). A hash without `v` is not a view link: `state` null and no
 * problems. Left-out parameters, overlays, rotation and lens fields take their defaults; a
 * left-out layer, mode, light or view stays as the viewer has it.
 */
export function decodeHash(hash: string): DecodedHash {
  const params = new URLSearchParams(hash.replace(/^#/, ''));
  const version = params.get('v');
  if (version === null) {
    return { state: null, problems: [] };
  }
  if (version !== HASH_VERSION) {
    return { state: null, problems: [`v: unknown link version ${JSON.stringify(version)} (this viewer reads ${HASH_VERSION})`] };
  }
  const problems: string[] = [];
  const out: Fields = { params: DEFAULT_RENDER_PARAMS, overlays: true, rotation: 0 };
  const lens: LensFields = { ...DEFAULT_LENS_VIEW };
  for (const [key, text] of params) {
    if (key === 'v') {
      continue;
    }
    if (key === 'p' || key === 'lensP') {
      const read = readParams(key, text, problems);
      if (key === 'p') {
        out.params = read;
      } else {
        lens.params = read;
      }
      continue;
    }
    const reader = READERS[key];
    const problem = reader ? reader(text, out, lens) : `${key}: unknown key`;
    if (problem !== null) {
      problems.push(problem);
    }
  }
  return { state: { ...out, lens }, problems };
}

/** A layer as {@link checkLayers} needs it. */
export interface LayerModes {
  readonly id: string;
  readonly modes: readonly RenderMode[];
}

/**
 * Drop the layer, mode, lens layer and lens mode of `state` that this dataset cannot show (an
 * unknown layer, a mode that does not apply), naming each in `problems`.
 */
export function checkLayers(state: ViewStateUpdate, layers: readonly LayerModes[],
  activeLayer: string): DecodedHash {
  const problems: string[] = [];
  const find = (id: string): LayerModes | undefined => layers.find((l) => l.id === id);
  const names = layers.map((l) => l.id).join(', ');
  let { layer, mode } = state;
  if (layer !== undefined && !find(layer)) {
    problems.push(`layer: no layer ${JSON.stringify(layer)} (layers: ${names})`);
    layer = undefined;
  }
  const base = find(layer ?? activeLayer);
  if (mode !== undefined && base && !base.modes.includes(mode)) {
    problems.push(`mode: ${mode} does not apply to layer ${base.id} (${base.modes.join(', ')})`);
    mode = undefined;
  }
  let lens = state.lens;
  if (lens?.layer && !find(lens.layer)) {
    problems.push(`lensLayer: no layer ${JSON.stringify(lens.layer)} (layers: ${names})`);
    lens = { ...lens, layer: '' };
  }
  const lensLayer = find(lens?.layer || (layer ?? activeLayer));
  if (lens?.mode !== undefined && lensLayer && !lensLayer.modes.includes(lens.mode)) {
    problems.push(`lensMode: ${lens.mode} does not apply to layer ${lensLayer.id} (${lensLayer.modes.join(', ')})`);
    const rest: LensFields = { ...lens };
    delete rest.mode;
    lens = rest;
  }
  const checked: Fields = { ...state };
  delete checked.layer;
  delete checked.mode;
  return {
    state: { ...checked, ...(layer === undefined ? {} : { layer }), ...(mode === undefined ? {} : { mode }),
      ...(lens === undefined ? {} : { lens }) },
    problems,
  };
}
