import { describe, expect, it } from 'vitest';
import { layerMetas, payloadForActive, topVisibleLayer } from '../../../plugin/src/mirador/layer-map';
import type { MiradorCanvasLayers } from '../../../plugin/src/mirador/types';

const ids = ['a', 'b', 'c'];

/** Apply an `updateLayers` payload as Mirador's layers reducer merges it (per layer, field by field). */
function merge(state: MiradorCanvasLayers | undefined, payload: MiradorCanvasLayers): MiradorCanvasLayers {
  const out: Record<string, object> = { ...state };
  for (const [id, fields] of Object.entries(payload)) {
    out[id] = { ...out[id], ...fields };
  }
  return out;
}

describe('Mirador layer state → our layer', () => {
  it('fills in Mirador\'s defaults: canvas order, only the first visible, opacity 1', () => {
    expect(layerMetas(ids, undefined)).toEqual([
      { imageId: 'a', visibility: true, opacity: 1, index: 0 },
      { imageId: 'b', visibility: false, opacity: 1, index: 1 },
      { imageId: 'c', visibility: false, opacity: 1, index: 2 },
    ]);
    expect(topVisibleLayer(ids, undefined)?.imageId).toBe('a');
  });

  it('shows the visible layer drawn on top (the largest index), at its opacity', () => {
    const state = { a: { index: 2 }, b: { index: 0, visibility: true, opacity: 0.3 }, c: { index: 1 } };
    expect(topVisibleLayer(ids, state)?.imageId).toBe('a');
    const hidden = merge(state, { a: { visibility: false } });
    expect(topVisibleLayer(ids, hidden)).toMatchObject({ imageId: 'b', opacity: 0.3 });
    expect(topVisibleLayer(ids, merge(hidden, { b: { visibility: false } }))).toBeNull();
  });

  it('clamps a bad opacity', () => {
    expect(layerMetas(['a'], { a: { opacity: 3 } })[0]?.opacity).toBe(1);
    expect(layerMetas(['a'], { a: { opacity: -1 } })[0]?.opacity).toBe(0);
  });
});

describe('our layer → Mirador layer state', () => {
  it('moves the layer to the front and shows it; the others keep their order and visibility', () => {
    const state = { a: { index: 0 }, b: { index: 1, visibility: false }, c: { index: 2, visibility: true } };
    const payload = payloadForActive(ids, state, 'a');
    expect(payload).not.toBeNull();
    const next = merge(state, payload ?? {});
    expect(topVisibleLayer(ids, next)?.imageId).toBe('a');
    const order = layerMetas(ids, next).sort((x, y) => x.index - y.index).map((m) => m.imageId);
    expect(order).toEqual(['b', 'c', 'a']);
    expect(layerMetas(ids, next).map((m) => m.visibility)).toEqual([true, false, true]);
  });

  it('asks nothing when the layer already is the top visible one, or is not on the canvas', () => {
    expect(payloadForActive(ids, undefined, 'a')).toBeNull();
    expect(payloadForActive(ids, undefined, 'zz')).toBeNull();
    const state = merge(undefined, payloadForActive(ids, undefined, 'c') ?? {});
    expect(payloadForActive(ids, state, 'c')).toBeNull();
  });
});
