import { afterEach, describe, expect, it, vi } from 'vitest';
import { FrameScheduler } from '../../../plugin/src/drawer/frame-scheduler';

/** A WebGL2 context with fences only; `signalled` says whether the last frame's fence has signalled. */
function fakeGl(state: { signalled: boolean }): WebGL2RenderingContext {
  const gl = {
    SYNC_GPU_COMMANDS_COMPLETE: 1, SYNC_STATUS: 2, SIGNALED: 3, UNSIGNALED: 4,
    isContextLost: () => false,
    fenceSync: () => ({}),
    flush: () => undefined,
    deleteSync: () => undefined,
    getSyncParameter: () => (state.signalled ? 3 : 4),
  };
  return gl as unknown as WebGL2RenderingContext;
}

const item = {};
const frame = (tiles: unknown[], over: { uploadsPending?: boolean; loading?: boolean } = {}) => ({
  key: { scene: [640, 480, 0, item], tiles }, uploadsPending: false, loading: false, ...over,
});

describe('the frame scheduler', () => {
  afterEach(() => { vi.useRealTimers(); });

  it('renders a frame once, and not again while nothing changed', () => {
    const scheduler = new FrameScheduler(fakeGl({ signalled: true }), () => undefined);
    const render = vi.fn();
    scheduler.frame(frame([item, 1, 'tex']), render);
    scheduler.frame(frame([item, 1, 'tex']), render);
    scheduler.frame(frame([item, 1, 'tex']), render);
    expect(render).toHaveBeenCalledTimes(1);
    expect(scheduler.frames).toBe(1);
    expect(scheduler.settled).toBe(true);
  });

  it('puts a progressive frame off while the GPU draws the last one, and asks for a redraw', () => {
    vi.useFakeTimers();
    const gpu = { signalled: false };
    const redraw = vi.fn();
    const scheduler = new FrameScheduler(fakeGl(gpu), redraw);
    const render = vi.fn();
    scheduler.frame(frame([item, 1, null], { loading: true }), render);
    scheduler.frame(frame([item, 1, 'tex'], { loading: true }), render); // new texture, GPU busy
    expect(render).toHaveBeenCalledTimes(1);
    expect(scheduler.settled).toBe(false);
    vi.runOnlyPendingTimers();
    expect(redraw).toHaveBeenCalledTimes(1);
    gpu.signalled = true;
    scheduler.frame(frame([item, 1, 'tex'], { loading: false }), render); // the loading is complete
    expect(render).toHaveBeenCalledTimes(2);
    expect(scheduler.settled).toBe(true);
  });

  it('is not settled while textures wait for their upload', () => {
    vi.useFakeTimers();
    const scheduler = new FrameScheduler(fakeGl({ signalled: true }), () => undefined);
    scheduler.frame(frame([item, 1, null], { uploadsPending: true }), () => undefined);
    expect(scheduler.settled).toBe(false);
    scheduler.frame(frame([item, 1, 'tex']), () => undefined);
    expect(scheduler.settled).toBe(true);
  });
});
