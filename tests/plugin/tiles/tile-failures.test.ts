import { afterEach, beforeEach, describe, expect, it, vi } from 'vitest';
import { TileFailures } from '../../../plugin/src/tiles/tile-failures';
import { fakeViewer } from '../fake-viewer';

const item = (opacity = 1) => ({ getOpacity: () => opacity });

describe('TileFailures', () => {
  beforeEach(() => { vi.useFakeTimers(); });
  afterEach(() => { vi.useRealTimers(); });

  it('counts failed tiles of visible items until they load', () => {
    const fake = fakeViewer();
    const onChange = vi.fn();
    const failures = new TileFailures(fake.viewer, { onChange });
    const [a, b, hidden] = [{ exists: false }, { exists: false }, { exists: false }];
    const shown = item();
    fake.raise('tile-load-failed', { tile: a, tiledImage: shown, message: '[lanterna] tile 3/1_1: HTTP 404 for u' });
    fake.raise('tile-load-failed', { tile: b, tiledImage: shown, message: 'x' });
    fake.raise('tile-load-failed', { tile: hidden, tiledImage: item(0), message: 'y' });
    expect(failures.state()).toEqual({ count: 2, message: 'y', retrying: true });
    fake.raise('tile-loaded', { tile: a });
    expect(failures.state().count).toBe(1);
    fake.raise('remove-item', { item: shown });
    expect(failures.state().count).toBe(0);
    expect(onChange).toHaveBeenCalled();
  });

  it('revives the failed tiles automatically twice, 4 s then 8 s later, then waits for retry()', () => {
    const fake = fakeViewer();
    const failures = new TileFailures(fake.viewer, { onChange: () => undefined });
    const tile = { exists: false };
    const fail = (): void => {
      tile.exists = false;
      fake.raise('tile-load-failed', { tile, tiledImage: item(), message: 'm' });
    };
    fail();
    vi.advanceTimersByTime(3999);
    expect(tile.exists).toBe(false);
    vi.advanceTimersByTime(1);
    expect(tile.exists).toBe(true);
    expect(fake.updates()).toBe(1);
    expect(failures.state().count).toBe(0); // being retried
    fail();
    vi.advanceTimersByTime(8000);
    expect(tile.exists).toBe(true);
    fail();
    expect(failures.state()).toMatchObject({ count: 1, retrying: false });
    vi.advanceTimersByTime(60000);
    expect(tile.exists).toBe(false);
    failures.retry();
    expect(tile.exists).toBe(true);
    expect(fake.updates()).toBe(3);
  });

  it('says it is retrying only while an automatic retry is due', () => {
    const fake = fakeViewer();
    const failures = new TileFailures(fake.viewer, { onChange: () => undefined });
    const tile = { exists: false };
    fake.raise('tile-load-failed', { tile, tiledImage: item(), message: 'm' });
    expect(failures.state().retrying).toBe(true);
    failures.retry(); // by hand: no more automatic retries for it
    tile.exists = false;
    fake.raise('tile-load-failed', { tile, tiledImage: item(), message: 'm' });
    expect(failures.state()).toMatchObject({ count: 1, retrying: false });
  });

  it('stops listening when destroyed', () => {
    const fake = fakeViewer();
    const failures = new TileFailures(fake.viewer, { onChange: () => undefined });
    expect(fake.handlers()).toBe(4);
    failures.destroy();
    expect(fake.handlers()).toBe(0);
  });
});
