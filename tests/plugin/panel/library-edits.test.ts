import { describe, expect, it } from 'vitest';
import { addPreset, emptyLibrary, type Preset } from '../../../plugin/src/presets/library';
import { removeEntry } from '../../../plugin/src/panel/library-edits';

const preset = (label: string): Preset => ({ label, layer: 'ptm', mode: 'color', params: {} });

describe('removeEntry', () => {
  it('removes the entry and its preset when nothing else uses it', () => {
    let lib = addPreset(emptyLibrary(), preset('One'), 'base').library;
    lib = addPreset(lib, preset('Two'), 'lens', 0.5).library;
    const out = removeEntry(lib, 'base', 0);
    expect(out.base).toEqual([]);
    expect(out.lens).toEqual(lib.lens);
    expect(Object.keys(out.presets)).toEqual(['two']);
  });

  it('keeps a preset another entry still uses, and ignores an index outside the list', () => {
    const first = addPreset(emptyLibrary(), preset('One'), 'base');
    const lib = { ...first.library, lens: [{ label: 'Same', preset: first.id }] };
    const out = removeEntry(lib, 'base', 0);
    expect(Object.keys(out.presets)).toEqual([first.id]);
    expect(out.lens).toHaveLength(1);
    expect(removeEntry(lib, 'lens', 5)).toBe(lib);
  });
});
