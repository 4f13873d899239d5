/**
 * Which controls the simplified viewer shows for a dataset and its preset library (seed paper §6.3:
 * the base menu, the lens menu, the lens toggle and the measurement toggle). Pure.
 */
import type { LayerInfo, PresetLibrary } from '../index';

/** The layer types whose materials measurement mode can show (shape and material, PTM, HSH). */
export const MEASURABLE_TYPES: ReadonlySet<string> = new Set(['svbrdf', 'ptm', 'hsh', 'sh', 'rbf', 'bilinear']);

/** What the page shows. */
export interface SimpleControls {
  /** The base-preset menu (the library has base entries). */
  readonly baseMenu: boolean;
  /** The lens-preset menu (the library has lens entries). */
  readonly lensMenu: boolean;
  /** The lens toggle: with lens entries, or with no presets at all (the lens then shows the base layer). */
  readonly lensToggle: boolean;
  /** The measurement toggle: a layer the library uses is shape+material, PTM or HSH. */
  readonly measureToggle: boolean;
  /** No presets at all: the object in its default rendering, and a note saying so. */
  readonly noPresets: boolean;
}

/** The controls for `library` over the viewer's `layers` (those it opened). */
export function simpleControls(library: PresetLibrary, layers: readonly LayerInfo[]): SimpleControls {
  const noPresets = library.base.length === 0 && library.lens.length === 0;
  // An entry's layer defaults to its preset's (docs/presets.md); types only from the plugin, so this stays pure.
  const used = new Set([...library.base, ...library.lens].map((e) => e.layer ?? library.presets[e.preset]?.layer));
  return {
    baseMenu: library.base.length > 0,
    lensMenu: library.lens.length > 0,
    lensToggle: library.lens.length > 0 || noPresets,
    measureToggle: layers.some((l) => used.has(l.id) && MEASURABLE_TYPES.has(l.layerType)),
    noPresets,
  };
}
