/**
 * Reading a preset library (`docs/presets.md`): the schema's rules (`tiler/schemas/presets.schema.json`,
 * written out here so the viewer needs no schema engine) and, given the dataset, the semantic ones.
 * Every error names its JSON path, as the Python side's do. Pure: no DOM, no GL.
 */
import { isRenderMode } from '../render/modes';
import { PARAM_NAMES, PARAM_SPECS, type RenderParamName, type RenderParams } from '../render/params';
import {
  PRESETS_TYPE, type LensPresetEntry, type Preset, type PresetDataset, type PresetLibrary,
} from './library';
import { checkAgainst } from './check-library';
import { describe, isObj, join, MAX_LABEL, Reader } from './reader';

const MAX_PRESETS = 256;
/** Slack on lu² + lv² ≤ 1 for values written with a few decimals. */
const DISK_SLACK = 1e-9;

function readParams(r: Reader, x: unknown, path: string): Partial<RenderParams> {
  const obj = r.object(x, path, PARAM_NAMES, []);
  const out: Partial<Record<RenderParamName, number>> = {};
  for (const name of PARAM_NAMES) {
    if (name in obj) {
      const { min, max } = PARAM_SPECS[name];
      out[name] = r.number(obj[name], join(path, name), min, max);
    }
  }
  return out;
}

function readPreset(r: Reader, x: unknown, path: string): Preset {
  const obj = r.object(x, path, ['label', 'layer', 'mode', 'params', 'light', 'view'], ['label', 'layer', 'mode']);
  const mode = obj.mode;
  if (!isRenderMode(mode)) {
    r.fail(join(path, 'mode'), `unknown render mode ${describe(mode)}`);
  }
  const preset: { -readonly [K in keyof Preset]: Preset[K] } = {
    label: r.label(obj.label, join(path, 'label')),
    layer: r.id(obj.layer, join(path, 'layer')),
    mode,
    params: obj.params === undefined ? {} : readParams(r, obj.params, join(path, 'params')),
  };
  if (obj.light !== undefined) {
    const [lu, lv] = r.numbers(obj.light, join(path, 'light'), 2) as [number, number];
    if (lu * lu + lv * lv > 1 + DISK_SLACK) {
      r.fail(join(path, 'light'), `the light [${lu}, ${lv}] is outside the unit disk (lu² + lv² must be ≤ 1)`);
    }
    preset.light = [lu, lv];
  }
  if (obj.view !== undefined) {
    const [vx, vy, vw, vh] = r.numbers(obj.view, join(path, 'view'), 4) as [number, number, number, number];
    if (!(vw > 0)) {
      r.fail(join(join(path, 'view'), 2), `the width must be positive, got ${describe(vw)}`);
    }
    if (!(vh > 0)) {
      r.fail(join(join(path, 'view'), 3), `the height must be positive, got ${describe(vh)}`);
    }
    preset.view = [vx, vy, vw, vh];
  }
  return preset;
}

function readEntry(r: Reader, x: unknown, path: string, lens: boolean): LensPresetEntry {
  const fields = lens ? ['label', 'preset', 'layer', 'opacity'] : ['label', 'preset', 'layer'];
  const obj = r.object(x, path, fields, ['label', 'preset']);
  const entry: { -readonly [K in keyof LensPresetEntry]: LensPresetEntry[K] } = {
    label: r.label(obj.label, join(path, 'label')),
    preset: r.id(obj.preset, join(path, 'preset')),
  };
  if (obj.layer !== undefined) {
    entry.layer = r.id(obj.layer, join(path, 'layer'));
  }
  if (lens && obj.opacity !== undefined) {
    entry.opacity = r.number(obj.opacity, join(path, 'opacity'), 0, 1);
  }
  return entry;
}

/** The schema's rules. */
function readLibrary(r: Reader, doc: unknown): PresetLibrary {
  const obj = r.object(doc, '', ['type', 'version', 'label', 'presets', 'base', 'lens'],
    ['type', 'version', 'presets', 'base', 'lens']);
  if (obj.type !== PRESETS_TYPE) {
    r.fail('type', `expected "${PRESETS_TYPE}", got ${describe(obj.type)}`);
  }
  if (obj.version !== 1) {
    r.fail('version', `expected 1, got ${describe(obj.version)}`);
  }
  if (!isObj(obj.presets)) {
    r.fail('presets', `expected an object {id: preset}, got ${describe(obj.presets)}`);
  }
  const ids = Object.keys(obj.presets);
  if (ids.length > MAX_PRESETS) {
    r.fail('presets', `at most ${MAX_PRESETS} presets, got ${ids.length}`);
  }
  const presets: Record<string, Preset> = {};
  for (const id of ids) {
    r.id(id, join('presets', id));
    presets[id] = readPreset(r, obj.presets[id], join('presets', id));
  }
  const library: { -readonly [K in keyof PresetLibrary]: PresetLibrary[K] } = {
    type: PRESETS_TYPE,
    version: 1,
    presets,
    base: r.list(obj.base, 'base').map((e, k) => readEntry(r, e, join('base', k), false)),
    lens: r.list(obj.lens, 'lens').map((e, k) => readEntry(r, e, join('lens', k), true)),
  };
  if (obj.label !== undefined) {
    if (typeof obj.label !== 'string' || obj.label.length > MAX_LABEL) {
      r.fail('label', `expected a text of at most ${MAX_LABEL} characters, got ${describe(obj.label)}`);
    }
    library.label = obj.label;
  }
  return library;
}

/**
 * Read a preset library: the schema's rules, then, given `dataset`, the semantic ones
 * (`docs/presets.md`). Extra fields of a manifest's service block (`id`, `profile`) are allowed.
 *
 * @param source - what to name in errors (a file name or URL)
 * @throws {@link PresetError} naming the JSON path of the first problem
 */
export function parsePresetLibrary(doc: unknown, source: string, dataset?: PresetDataset): PresetLibrary {
  const r = new Reader(source);
  const body = isObj(doc)
    ? Object.fromEntries(Object.entries(doc).filter(([key]) => key !== 'id' && key !== 'profile')) : doc;
  const library = readLibrary(r, body);
  if (dataset) {
    checkAgainst(r, library, dataset);
  }
  return library;
}

