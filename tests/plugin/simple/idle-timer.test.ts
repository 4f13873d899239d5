import { afterEach, beforeEach, describe, expect, it, vi } from 'vitest';
import { createIdleTimer } from '../../../plugin/src/simple/idle-timer';

describe('createIdleTimer', () => {
  beforeEach(() => { vi.useFakeTimers(); });
  afterEach(() => { vi.useRealTimers(); });

  it('fires once after the quiet period, and again only after the next input', () => {
    const target = new EventTarget();
    const onIdle = vi.fn();
    const timer = createIdleTimer({ seconds: 120, onIdle, target });
    vi.advanceTimersByTime(119_000);
    expect(onIdle).not.toHaveBeenCalled();
    vi.advanceTimersByTime(1_000);
    expect(onIdle).toHaveBeenCalledTimes(1);
    vi.advanceTimersByTime(600_000);
    expect(onIdle).toHaveBeenCalledTimes(1); // nothing happened since: no second reset
    target.dispatchEvent(new Event('pointerdown'));
    vi.advanceTimersByTime(120_000);
    expect(onIdle).toHaveBeenCalledTimes(2);
    timer.destroy();
  });

  it('starts the quiet period again on every input', () => {
    const target = new EventTarget();
    const onIdle = vi.fn();
    createIdleTimer({ seconds: 10, onIdle, target });
    for (const type of ['pointermove', 'wheel', 'keydown', 'touchstart']) {
      vi.advanceTimersByTime(9_000);
      target.dispatchEvent(new Event(type));
    }
    expect(onIdle).not.toHaveBeenCalled();
    vi.advanceTimersByTime(10_000);
    expect(onIdle).toHaveBeenCalledTimes(1);
  });

  it('never fires with 0 seconds, nor after destroy', () => {
    const target = new EventTarget();
    const onIdle = vi.fn();
    createIdleTimer({ seconds: 0, onIdle, target });
    const timer = createIdleTimer({ seconds: 5, onIdle, target });
    timer.destroy();
    target.dispatchEvent(new Event('pointerdown'));
    vi.advanceTimersByTime(60_000);
    expect(onIdle).not.toHaveBeenCalled();
  });
});
