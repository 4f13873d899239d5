/**
 * The Mirador plugin that puts Lanterna's viewer in a window whose canvas Lanterna relights: a `wrap`
 * of `OpenSeadragonViewer` (components in `window-view.ts`).
 */
import { getCurrentCanvas, getLayers, getManifest, updateLayers, updateViewport } from 'mirador';
import { lanternaCanvas, type LanternaCanvas } from './lanterna-canvas';
import type { MiradorPlugin } from './types';
import { LanternaSwitch } from './window-view';

/** The last answer per manifest JSON and canvas, so that the props stay the same object while nothing changes. */
const cache = new WeakMap<object, Map<string, LanternaCanvas | null>>();

function cachedCanvas(manifestUrl: string, json: unknown, canvasId: string): LanternaCanvas | null {
  if (typeof json !== 'object' || json === null) {
    return null;
  }
  let byCanvas = cache.get(json);
  if (!byCanvas) {
    byCanvas = new Map();
    cache.set(json, byCanvas);
  }
  const key = `${manifestUrl} ${canvasId}`;
  if (!byCanvas.has(key)) {
    byCanvas.set(key, lanternaCanvas(manifestUrl, json, canvasId));
  }
  return byCanvas.get(key) ?? null;
}

/** The window's Lanterna canvas (or null) and Mirador's layer state of its current canvas. */
export function lanternaStateToProps(state: unknown, ownProps: Record<string, unknown>): Record<string, unknown> {
  const windowId = String(ownProps.windowId);
  const canvas = getCurrentCanvas(state, { windowId });
  const manifest = getManifest(state, { windowId });
  if (!canvas || !manifest?.json) {
    return { lanterna: null };
  }
  return {
    lanterna: cachedCanvas(manifest.id, manifest.json, canvas.id),
    miradorLayers: getLayers(state, { windowId, canvasId: canvas.id }),
  };
}

/** The viewer plugin (docs/mirador.md). */
export const viewerPlugin: MiradorPlugin = {
  name: 'LanternaViewer',
  target: 'OpenSeadragonViewer',
  mode: 'wrap',
  component: LanternaSwitch,
  mapStateToProps: lanternaStateToProps,
  mapDispatchToProps: { updateLayers, updateViewport },
};
