/**
 * Edits of a preset library the panel makes beyond adding a preset (`presets/library.ts`): removing
 * an entry. Pure: no DOM.
 */
import type { PresetLibrary, PresetTarget } from '../presets/library';

/**
 * The library without entry `index` of `target`'s list; its preset goes too when no other entry
 * uses it. An index outside the list changes nothing.
 */
export function removeEntry(library: PresetLibrary, target: PresetTarget, index: number): PresetLibrary {
  const entry = library[target][index];
  if (!entry) {
    return library;
  }
  const base = target === 'base' ? library.base.filter((_, i) => i !== index) : library.base;
  const lens = target === 'lens' ? library.lens.filter((_, i) => i !== index) : library.lens;
  const used = [...base, ...lens].some((e) => e.preset === entry.preset);
  const presets = used ? library.presets
    : Object.fromEntries(Object.entries(library.presets).filter(([id]) => id !== entry.preset));
  return { ...library, presets, base, lens };
}
