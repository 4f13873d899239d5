/**
 * Preset libraries (`docs/presets.md`; the schema is `tiler/schemas/presets.schema.json`): named
 * rendering configurations of a layer, and the paper's two lists — `base` and `lens` — of entries
 * pointing at them (seed paper §6.2.2). The types and the edits; reading is in `read-library.ts`.
 * Pure: no DOM, no GL.
 */
import { LanternaError } from '../errors';
import type { RenderMode } from '../render/modes';
import type { RenderParams } from '../render/params';

/** The library document's `type`. */
export const PRESETS_TYPE = 'LanternaPresets';
/** The profile of the library's service block on a manifest. */
export const PRESETS_PROFILE = 'urn:lanterna:presets:1';

/** A named rendering configuration of one layer. */
export interface Preset {
  readonly label: string;
  /** The layer it was made for. */
  readonly layer: string;
  readonly mode: RenderMode;
  /** Parameters it sets (the others take their defaults). */
  readonly params: Partial<RenderParams>;
  /** The light's projection (lu, lv); absent: the light is left where it is. */
  readonly light?: readonly [number, number];
  /** A region (x, y, w, h) of the image in full-resolution pixels to show; absent: the view is kept. */
  readonly view?: readonly [number, number, number, number];
}

/** An entry of the base list: a label and the preset it applies (to `layer`, default the preset's). */
export interface PresetEntry {
  readonly label: string;
  readonly preset: string;
  readonly layer?: string;
}

/** An entry of the lens list: also the lens's opacity over the base (default 1). */
export interface LensPresetEntry extends PresetEntry {
  readonly opacity?: number;
}

/** A preset library. */
export interface PresetLibrary {
  readonly type: typeof PRESETS_TYPE;
  readonly version: 1;
  readonly label?: string;
  readonly presets: Readonly<Record<string, Preset>>;
  readonly base: readonly PresetEntry[];
  readonly lens: readonly LensPresetEntry[];
}

/** Which list an entry belongs to. */
export type PresetTarget = 'base' | 'lens';

/** What the semantic checks need to know of a dataset layer. */
export interface PresetLayerFacts {
  readonly id: string;
  readonly modes: readonly RenderMode[];
}

/** What the semantic checks need to know of the dataset. */
export interface PresetDataset {
  readonly layers: readonly PresetLayerFacts[];
  /** The image's size in full-resolution pixels (for `view`). */
  readonly width: number;
  readonly height: number;
}

/** A library that does not follow the schema or does not fit the dataset; the message names the JSON path. */
export class PresetError extends LanternaError {}

/** An empty library. */
export function emptyLibrary(): PresetLibrary {
  return { type: PRESETS_TYPE, version: 1, presets: {}, base: [], lens: [] };
}

/** The layer an entry applies its preset to. */
export function entryLayer(library: PresetLibrary, entry: PresetEntry): string {
  return entry.layer ?? library.presets[entry.preset]?.layer ?? '';
}

/** The ids of the layers a library's entries use, in first-use order (base first). */
export function libraryLayers(library: PresetLibrary): string[] {
  const out: string[] = [];
  for (const entry of [...library.base, ...library.lens]) {
    const id = entryLayer(library, entry);
    if (id && !out.includes(id)) {
      out.push(id);
    }
  }
  return out;
}

/** A fresh preset id from a label: lower-case words joined by '-', made unique among `taken`. */
export function presetId(label: string, taken: readonly string[]): string {
  const stem = label.toLowerCase().normalize('NFKD').replace(/[^a-z0-9]+/g, '-').replace(/^-+|-+$/g, '')
    .slice(0, 56) || 'preset';
  let id = stem;
  for (let k = 2; taken.includes(id); k++) {
    id = `${stem}-${k}`;
  }
  return id;
}

/**
 * The library with `preset` added under a new id and an entry for it appended to `target`'s list
 * (label = the preset's). Returns the new library and the id.
 */
export function addPreset(library: PresetLibrary, preset: Preset, target: PresetTarget,
  opacity?: number): { library: PresetLibrary; id: string } {
  const id = presetId(preset.label, Object.keys(library.presets));
  const presets = { ...library.presets, [id]: preset };
  const entry: LensPresetEntry = target === 'lens' && opacity !== undefined
    ? { label: preset.label, preset: id, opacity } : { label: preset.label, preset: id };
  const next = target === 'base' ? { ...library, presets, base: [...library.base, entry] }
    : { ...library, presets, lens: [...library.lens, entry] };
  return { library: next, id };
}

/** The library as the JSON document a file holds (fields in schema order, no service fields). */
export function serializeLibrary(library: PresetLibrary): string {
  const doc: Record<string, unknown> = { type: PRESETS_TYPE, version: 1 };
  if (library.label !== undefined) {
    doc.label = library.label;
  }
  doc.presets = library.presets;
  doc.base = library.base;
  doc.lens = library.lens;
  return `${JSON.stringify(doc, null, 2)}\n`;
}

/** The preset's parameters over the defaults: every parameter, as applied. */
export function presetParams(preset: Preset, defaults: RenderParams): RenderParams {
  return { ...defaults, ...preset.params };
}
