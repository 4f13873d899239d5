import { describe, expect, it } from 'vitest';
import { ObjectIds, QuantityCache } from '../../../plugin/src/drawer/quantity-cache';
import type { FloatTarget, QuantityTargets, ScreenFilter } from '../../../plugin/src/drawer/screen-filter';

/** A screen filter that makes plain objects for targets and counts what is alive. */
function fakeFilter(): { filter: ScreenFilter; alive: Set<QuantityTargets> } {
  const alive = new Set<QuantityTargets>();
  const target = (width: number, height: number): FloatTarget =>
    ({ texture: {}, framebuffer: {}, width, height });
  const filter = {
    targets(old: QuantityTargets | null, width: number, height: number, extras: number): QuantityTargets {
      if (old && old.filtered.width === width && old.filtered.height === height && old.extras.length === extras) {
        return old;
      }
      if (old) {
        alive.delete(old);
      }
      const made: QuantityTargets = {
        filtered: target(width, height), extras: Array.from({ length: extras }, () => target(width, height)),
        framebuffer: {},
      };
      alive.add(made);
      return made;
    },
    free(old: QuantityTargets | null): void {
      if (old) {
        alive.delete(old);
      }
    },
  };
  return { filter: filter as unknown as ScreenFilter, alive };
}

describe('the kept quantities', () => {
  it('reuse a slot whose key is unchanged, once it has been kept', () => {
    const { filter } = fakeFilter();
    const cache = new QuantityCache(filter);
    const first = cache.acquire('base', 'k1', 100, 50, 2);
    expect(first.fresh).toBe(false);
    // not kept yet (e.g. the drawing failed): still not fresh
    expect(cache.acquire('base', 'k1', 100, 50, 2).fresh).toBe(false);
    cache.keep('base', 'k1');
    const again = cache.acquire('base', 'k1', 100, 50, 2);
    expect(again.fresh).toBe(true);
    expect(again.targets).toBe(first.targets);
    expect(again.targets.extras).toHaveLength(2);
  });

  it('recompute when the key or the size changes', () => {
    const { filter } = fakeFilter();
    const cache = new QuantityCache(filter);
    cache.acquire('base', 'k1', 100, 50, 0);
    cache.keep('base', 'k1');
    expect(cache.acquire('base', 'k2', 100, 50, 0).fresh).toBe(false);
    cache.keep('base', 'k2');
    expect(cache.acquire('base', 'k1', 100, 50, 0).fresh).toBe(false); // only the last key is held
    cache.keep('base', 'k1');
    const resized = cache.acquire('base', 'k1', 101, 50, 0);
    expect(resized.fresh).toBe(false);
    expect(resized.targets.filtered.width).toBe(101);
  });

  it('keep the base and the lens apart', () => {
    const { filter } = fakeFilter();
    const cache = new QuantityCache(filter);
    const base = cache.acquire('canvas/layer', 'k', 100, 50, 2);
    cache.keep('canvas/layer', 'k');
    const lens = cache.acquire('lens/layer', 'k', 100, 50, 2);
    expect(lens.targets).not.toBe(base.targets);
    cache.keep('lens/layer', 'k');
    expect(cache.acquire('canvas/layer', 'k', 100, 50, 2)).toEqual({ targets: base.targets, fresh: true });
    expect(cache.acquire('lens/layer', 'k', 100, 50, 2)).toEqual({ targets: lens.targets, fresh: true });
  });

  it('draw an unkept quantity through one transient set and free the slot it had', () => {
    const { filter, alive } = fakeFilter();
    const cache = new QuantityCache(filter);
    cache.acquire('base', 'k', 100, 50, 2);
    cache.keep('base', 'k');
    expect(alive.size).toBe(1);
    const a = cache.acquire('base', null, 100, 50, 0);
    const b = cache.acquire('lens', null, 100, 50, 0);
    expect(a.fresh || b.fresh).toBe(false);
    expect(b.targets).toBe(a.targets);
    expect(alive.size).toBe(1); // the slot's targets went, the transient set came
    expect(cache.acquire('base', 'k', 100, 50, 2).fresh).toBe(false);
  });

  it('hold at most three slots, dropping the least recently used', () => {
    const { filter, alive } = fakeFilter();
    const cache = new QuantityCache(filter);
    for (const slot of ['a', 'b', 'c']) {
      cache.acquire(slot, 'k', 10, 10, 0);
      cache.keep(slot, 'k');
    }
    expect(cache.acquire('a', 'k', 10, 10, 0).fresh).toBe(true); // a is now the most recent
    cache.acquire('d', 'k', 10, 10, 0);
    expect(alive.size).toBe(3);
    expect(cache.acquire('a', 'k', 10, 10, 0).fresh).toBe(true);
    expect(cache.acquire('b', 'k', 10, 10, 0).fresh).toBe(false); // b was dropped
    cache.destroy();
    expect(alive.size).toBe(0);
  });
});

describe('object ids', () => {
  it('give the same object the same id and another object another', () => {
    const ids = new ObjectIds();
    const a = {};
    const b = {};
    expect(ids.of(a)).toBe(ids.of(a));
    expect(ids.of(b)).not.toBe(ids.of(a));
  });
});
