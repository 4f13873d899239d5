/**
 * Mirador's layer state ↔ the active Lanterna layer. Pure.
 *
 * Mirador keeps `layers[windowId][canvasId][imageResourceId] = {visibility, opacity, index}`; what is
 * not set takes its defaults (`CanvasWorld.getLayerMetadata`): the index is the resource's order on
 * the canvas, only the first (preferred) `Choice` item is visible, opacity 1. The largest index is
 * drawn on top (the layers panel's "move to front" gives it `length - 1`). Lanterna shows one layer:
 * the top visible one, at its opacity.
 */
import type { MiradorCanvasLayers, MiradorLayerState } from './types';

/** One layer's resolved Mirador state. */
export interface LayerMeta {
  readonly imageId: string;
  readonly visibility: boolean;
  readonly opacity: number;
  readonly index: number;
}

/** Every layer's state, in canvas order, with Mirador's defaults filled in. */
export function layerMetas(imageIds: readonly string[], state: MiradorCanvasLayers | undefined): LayerMeta[] {
  return imageIds.map((imageId, order) => {
    const s: MiradorLayerState = state?.[imageId] ?? {};
    return {
      imageId,
      visibility: s.visibility ?? order === 0,
      opacity: typeof s.opacity === 'number' && Number.isFinite(s.opacity) ? Math.min(1, Math.max(0, s.opacity)) : 1,
      index: typeof s.index === 'number' ? s.index : order,
    };
  });
}

/** The layer Lanterna shows: the visible one drawn on top (largest index), or null when none is visible. */
export function topVisibleLayer(imageIds: readonly string[], state: MiradorCanvasLayers | undefined): LayerMeta | null {
  let top: LayerMeta | null = null;
  for (const meta of layerMetas(imageIds, state)) {
    if (meta.visibility && (!top || meta.index > top.index)) {
      top = meta;
    }
  }
  return top;
}

/**
 * The `updateLayers` payload that makes `imageId` the top visible layer: it moves to the front (the
 * others keep their order below it) and is made visible. Null when it is already the top visible one.
 */
export function payloadForActive(imageIds: readonly string[], state: MiradorCanvasLayers | undefined,
  imageId: string): MiradorCanvasLayers | null {
  if (!imageIds.includes(imageId) || topVisibleLayer(imageIds, state)?.imageId === imageId) {
    return null;
  }
  const order = layerMetas(imageIds, state).sort((a, b) => a.index - b.index).map((m) => m.imageId)
    .filter((id) => id !== imageId);
  order.push(imageId);
  const payload: Record<string, MiradorLayerState> = {};
  order.forEach((id, index) => {
    payload[id] = id === imageId ? { index, visibility: true } : { index };
  });
  return payload;
}
