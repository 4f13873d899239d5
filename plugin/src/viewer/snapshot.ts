/**
 * `snapshot`: the current view as a PNG at device resolution (the pixels of `readPixels`), with what
 * it shows in text chunks (`docs/viewer-api.md`, "Snapshots").
 */
import type { LanternaViewer } from '../api/viewer-api';
import type { SnapshotOptions } from '../api/view-state-api';
import { encodeHash } from '../state/hash-codec';
import { encodePng } from '../state/png';
import { roundLight, roundParams } from '../state/view-state';
import { PARAM_NAMES } from '../render/params';
import { loadedOrFailed } from './loaded-or-failed';
import { scaledPixels } from './scaled-pixels';
import { readViewState } from './view-state';

/** zlib-compress with the browser's CompressionStream (`deflate` is the zlib format PNG uses). */
async function deflate(bytes: Uint8Array): Promise<Uint8Array> {
  const stream = new Blob([new Uint8Array(bytes)]).stream().pipeThrough(new CompressionStream('deflate'));
  return new Uint8Array(await new Response(stream).arrayBuffer());
}

/** The text chunks of a snapshot: keyword → text. */
export function snapshotTexts(api: LanternaViewer): Record<string, string> {
  const state = readViewState(api);
  const light = roundLight(state.light);
  const params = roundParams(state.params);
  return {
    Title: api.manifest?.label ?? '',
    Software: 'Lanterna',
    'Lanterna layer': state.layer,
    'Lanterna mode': state.mode,
    'Lanterna light': light.join(','),
    'Lanterna params': PARAM_NAMES.map((n) => `${n}:${params[n]}`).join(','),
    'Lanterna view': state.view.map((v) => String(Math.round(v * 100) / 100)).join(','),
    'Lanterna link': encodeHash(state),
  };
}

/** The PNG of the current view (see `LanternaViewer.snapshot`). */
export async function snapshotPng(api: LanternaViewer, options: SnapshotOptions = {}): Promise<Blob> {
  await api.ready;
  await loadedOrFailed(api);
  const texts = snapshotTexts(api);
  const { width, height, data } = options.scale === undefined ? api.readPixels() : await scaledPixels(api, options.scale);
  if (options.scale !== undefined) {
    texts['Lanterna scale'] = `${options.scale} output px per image px`;
  }
  const png = await encodePng(width, height, data, deflate, texts);
  return new Blob([new Uint8Array(png)], { type: 'image/png' });
}
