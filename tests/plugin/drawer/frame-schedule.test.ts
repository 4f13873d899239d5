import { describe, expect, it } from 'vitest';
import {
  compareFrames, decideFrame, PROGRESSIVE_IDLE_FACTOR, type FrameState,
} from '../../../plugin/src/drawer/frame-schedule';
import { pickUploads, UPLOAD_BUDGET_BYTES } from '../../../plugin/src/drawer/upload-budget';

const tileA = {};
const tileB = {};
const item = {};

function state(over: Partial<FrameState>): FrameState {
  return { change: 'tiles', uploadsPending: false, loading: true, gpuBusy: false, sinceLastMs: 0, lastCostMs: 0, ...over };
}

describe('comparing frames', () => {
  const key = { scene: [640, 480, 0, item, 1], tiles: [item, 1, tileA] };

  it('sees a first frame, and any change outside the tiles, as a scene change', () => {
    expect(compareFrames(null, key)).toBe('scene');
    expect(compareFrames(key, { ...key, scene: [640, 480, 1, item, 1] })).toBe('scene'); // a setting
    expect(compareFrames(key, { ...key, scene: [640, 480, 0, item, 0] })).toBe('scene'); // opacity
    expect(compareFrames(key, { ...key, scene: [640, 480, 0, item, 1, {}, 1] })).toBe('scene'); // an item
  });

  it('tells new tiles or textures from nothing new', () => {
    expect(compareFrames(key, { scene: [...key.scene], tiles: [...key.tiles] })).toBe('none');
    expect(compareFrames(key, { ...key, tiles: [item, 1, tileB] })).toBe('tiles');
    expect(compareFrames(key, { ...key, tiles: [item, 2, tileA, tileB] })).toBe('tiles');
  });
});

describe('deciding on a frame', () => {
  it('renders a scene change at once, whatever else waits', () => {
    for (const over of [{}, { uploadsPending: true }, { gpuBusy: true }, { sinceLastMs: 1, lastCostMs: 500 }]) {
      expect(decideFrame(state({ change: 'scene', ...over }))).toEqual({ render: true });
    }
  });

  it('draws an unchanged frame never again, and waits for nothing', () => {
    expect(decideFrame(state({ change: 'none', loading: false }))).toEqual({ render: false, retryMs: null });
  });

  it('keeps uploading (next animation frame) before drawing new tiles', () => {
    expect(decideFrame(state({ uploadsPending: true }))).toEqual({ render: false, retryMs: 0 });
    expect(decideFrame(state({ change: 'none', uploadsPending: true }))).toEqual({ render: false, retryMs: 0 });
  });

  it('waits for the GPU to finish the last frame before a progressive one', () => {
    expect(decideFrame(state({ gpuBusy: true, sinceLastMs: 5000, lastCostMs: 1 }))).toEqual({ render: false, retryMs: 0 });
  });

  it('leaves the GPU idle for a multiple of the last frame while tiles load', () => {
    const cost = 100;
    const due = PROGRESSIVE_IDLE_FACTOR * cost;
    expect(decideFrame(state({ sinceLastMs: due - 40, lastCostMs: cost }))).toEqual({ render: false, retryMs: 40 });
    expect(decideFrame(state({ sinceLastMs: due, lastCostMs: cost }))).toEqual({ render: true });
    expect(decideFrame(state({ sinceLastMs: 1, lastCostMs: 0 }))).toEqual({ render: true }); // cost unknown
  });

  it('draws the frame that completes the loading as soon as the GPU is free', () => {
    expect(decideFrame(state({ loading: false, sinceLastMs: 1, lastCostMs: 1000 }))).toEqual({ render: true });
  });
});

describe('the upload budget', () => {
  const mib = 1024 * 1024;

  it('uploads the tiles nearest the centre first, within the budget', () => {
    const pending = [
      { tile: 'far', bytes: 3 * mib, distance: 9 },
      { tile: 'near', bytes: 3 * mib, distance: 1 },
      { tile: 'mid', bytes: 3 * mib, distance: 4 },
    ];
    expect(pickUploads(pending, 7 * mib)).toEqual(['near', 'mid']);
    expect(pickUploads(pending, 9 * mib)).toEqual(['near', 'mid', 'far']);
  });

  it('always uploads one tile, even one larger than the budget', () => {
    expect(pickUploads([{ tile: 'huge', bytes: 4 * UPLOAD_BUDGET_BYTES, distance: 0 }])).toEqual(['huge']);
    expect(pickUploads([])).toEqual([]);
  });

  it('stops at the first tile that does not fit (nearest first, none skipped)', () => {
    const pending = [
      { tile: 'a', bytes: 2 * mib, distance: 1 },
      { tile: 'b', bytes: 8 * mib, distance: 2 },
      { tile: 'c', bytes: 1 * mib, distance: 3 },
    ];
    expect(pickUploads(pending, 4 * mib)).toEqual(['a']);
  });
});
