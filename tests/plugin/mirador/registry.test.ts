import { describe, expect, it } from 'vitest';
import type { LanternaViewer } from '../../../plugin/src/api/viewer-api';
import { getWindowViewer, setWindowViewer, watchWindowViewer } from '../../../plugin/src/mirador/registry';

/** Distinct objects standing for two viewers: the registry only stores and hands them back. */
const first = {} as LanternaViewer;
const second = {} as LanternaViewer;

describe('the per-window viewer registry', () => {
  it('keeps one viewer per window', () => {
    setWindowViewer('w1', first);
    setWindowViewer('w2', second);
    expect(getWindowViewer('w1')).toBe(first);
    expect(getWindowViewer('w2')).toBe(second);
    expect(getWindowViewer('w3')).toBeNull();
    setWindowViewer('w1', null);
    setWindowViewer('w2', null);
    expect(getWindowViewer('w1')).toBeNull();
  });

  it('tells a watcher at once and on each change of its window only, until it stops', () => {
    const seen: (LanternaViewer | null)[] = [];
    const stop = watchWindowViewer('w1', (v) => { seen.push(v); });
    setWindowViewer('w1', first);
    setWindowViewer('w1', first); // no change: not told again
    setWindowViewer('w2', second);
    setWindowViewer('w1', null);
    stop();
    setWindowViewer('w1', second);
    expect(seen).toEqual([null, first, null]);
    setWindowViewer('w1', null);
    setWindowViewer('w2', null);
  });
});
