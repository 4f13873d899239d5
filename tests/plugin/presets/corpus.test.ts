/**
 * The plugin's reader on the corpus the Python validator is tested on (tests/data/presets): every
 * valid library is read, every invalid one is refused naming the JSON path its `.expected` file holds
 * (or a path inside it: the plugin may point at the very field the schema's rule is about).
 */
import { readdirSync, readFileSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { describe, expect, it } from 'vitest';
import { LAYER_KINDS } from '../../../plugin/src/layers/layer-kinds';
import type { PresetDataset } from '../../../plugin/src/presets/library';
import { parsePresetLibrary } from '../../../plugin/src/presets/read-library';

const CORPUS = resolve(dirname(fileURLToPath(import.meta.url)), '../../data/presets');

/** The demo dataset (tiler/demo/dataset.py): its layers' kinds give their modes. */
const DEMO: PresetDataset = {
  layers: [
    ['ptm', 'ptm-lrgb'], ['hsh', 'hsh9'], ['rbf', 'rbf'], ['svbrdf', 'svbrdf'], ['geometry', 'svbrdf'], ['band_ir', 'image'],
    ['band_uv', 'image'], ['band_R', 'image'], ['band_G', 'image'], ['band_B', 'image'], ['fc_ir_r_g', 'image'],
  ].map(([id, kind]) => ({ id: id, modes: LAYER_KINDS[kind as keyof typeof LAYER_KINDS].modes })),
  width: 1536,
  height: 1152,
};

const files = (folder: string): string[] =>
  readdirSync(join(CORPUS, folder)).filter((f) => f.endsWith('.json')).sort();

describe('the shared preset corpus', () => {
  it.each(files('valid'))('reads valid/%s', (name) => {
    const doc: unknown = JSON.parse(readFileSync(join(CORPUS, 'valid', name), 'utf8'));
    expect(() => parsePresetLibrary(doc, name, DEMO)).not.toThrow();
  });

  it.each(files('invalid'))('refuses invalid/%s naming its path', (name) => {
    const doc: unknown = JSON.parse(readFileSync(join(CORPUS, 'invalid', name), 'utf8'));
    const expected = readFileSync(join(CORPUS, 'invalid', name.replace(/\.json$/, '.expected')), 'utf8').trim();
    let message = '';
    try {
      parsePresetLibrary(doc, name, DEMO);
    } catch (error) {
      message = error instanceof Error ? error.message : String(error);
    }
    expect(message.startsWith(`${name}: `)).toBe(true);
    const path = message.slice(name.length + 2).split(': ')[0] ?? '';
    const inside = path === expected || path.startsWith(`${expected}.`) || path.startsWith(`${expected}[`);
    expect(inside, `${path} is not ${expected} or inside it`).toBe(true);
  });
});
