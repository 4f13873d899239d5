import { describe, expect, it } from 'vitest';
import { ObjectIds, QuantityCache } from '../../../plugin/src/drawer/quantity-cache';
import type {
  FloatTarget, QuantityShape, QuantityTargets, ScreenFilter,
} from '../../../plugin/src/drawer/screen-filter';

/** A screen filter that makes plain objects for targets and counts what is alive. */
function fakeFilter(): { filter: ScreenFilter; alive: Set<QuantityTargets> } {
  const alive = new Set<QuantityTargets>();
  const target = (width: number, height: number): FloatTarget =>
    ({ texture: {}, framebuffer: {}, width, height });
  const filter = {
    targets(old: QuantityTargets | null, shape: QuantityShape): QuantityTargets {
      const { width, height, filtered, extras } = shape;
      if (old && old.filtered[0].width === width && old.filtered[0].height === height
        && old.filtered.length === filtered && old.extras.length === extras) {
        return old;
      }
      if (old) {
        alive.delete(old);
      }
      const made: QuantityTargets = {
        filtered: [target(width, height), ...Array.from({ length: filtered - 1 }, () => target(width, height))],
        extras: Array.from({ length: extras }, () => target(width, height)),
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

const shape = (width: number, height: number, extras: number, filtered = 1): QuantityShape =>
  ({ width, height, filtered, extras });

describe('the kept quantities', () => {
  it('reuse a slot whose key is unchanged, once it has been kept', () => {
    const { filter } = fakeFilter();
    const cache = new QuantityCache(filter);
    const first = cache.acquire('base', 'k1', shape(100, 50, 2));
    expect(first.fresh).toBe(false);
    // not kept yet (e.g. the drawing failed): still not fresh
    expect(cache.acquire('base', 'k1', shape(100, 50, 2)).fresh).toBe(false);
    cache.keep('base', 'k1');
    const again = cache.acquire('base', 'k1', shape(100, 50, 2));
    expect(again.fresh).toBe(true);
    expect(again.targets).toBe(first.targets);
    expect(again.targets.extras).toHaveLength(2);
  });

  it('recompute when the key or the size changes', () => {
    const { filter } = fakeFilter();
    const cache = new QuantityCache(filter);
    cache.acquire('base', 'k1', shape(100, 50, 0));
    cache.keep('base', 'k1');
    expect(cache.acquire('base', 'k2', shape(100, 50, 0)).fresh).toBe(false);
    cache.keep('base', 'k2');
    expect(cache.acquire('base', 'k1', shape(100, 50, 0)).fresh).toBe(false); // only the last key is held
    cache.keep('base', 'k1');
    const resized = cache.acquire('base', 'k1', shape(101, 50, 0));
    expect(resized.fresh).toBe(false);
    expect(resized.targets.filtered[0].width).toBe(101);
  });

  it('remake the targets when the number of filtered targets changes', () => {
    const { filter } = fakeFilter();
    const cache = new QuantityCache(filter);
    cache.acquire('base', 'k', shape(10, 10, 0, 2));
    cache.keep('base', 'k');
    const one = cache.acquire('base', 'k', shape(10, 10, 0, 1));
    expect(one.fresh).toBe(false);
    expect(one.targets.filtered).toHaveLength(1);
  });

  it('keep the base and the lens apart', () => {
    const { filter } = fakeFilter();
    const cache = new QuantityCache(filter);
    const base = cache.acquire('canvas/layer', 'k', shape(100, 50, 2));
    cache.keep('canvas/layer', 'k');
    const lens = cache.acquire('lens/layer', 'k', shape(100, 50, 2));
    expect(lens.targets).not.toBe(base.targets);
    cache.keep('lens/layer', 'k');
    expect(cache.acquire('canvas/layer', 'k', shape(100, 50, 2))).toEqual({ targets: base.targets, fresh: true });
    expect(cache.acquire('lens/layer', 'k', shape(100, 50, 2))).toEqual({ targets: lens.targets, fresh: true });
  });

  it('draw an unkept quantity through one transient set and free the slot it had', () => {
    const { filter, alive } = fakeFilter();
    const cache = new QuantityCache(filter);
    cache.acquire('base', 'k', shape(100, 50, 2));
    cache.keep('base', 'k');
    expect(alive.size).toBe(1);
    const a = cache.acquire('base', null, shape(100, 50, 0));
    const b = cache.acquire('lens', null, shape(100, 50, 0));
    expect(a.fresh || b.fresh).toBe(false);
    expect(b.targets).toBe(a.targets);
    expect(alive.size).toBe(1); // the slot's targets went, the transient set came
    expect(cache.acquire('base', 'k', shape(100, 50, 2)).fresh).toBe(false);
  });

  it('hold at most three slots, dropping the least recently used', () => {
    const { filter, alive } = fakeFilter();
    const cache = new QuantityCache(filter);
    for (const slot of ['a', 'b', 'c']) {
      cache.acquire(slot, 'k', shape(10, 10, 0));
      cache.keep(slot, 'k');
    }
    expect(cache.acquire('a', 'k', shape(10, 10, 0)).fresh).toBe(true); // a is now the most recent
    cache.acquire('d', 'k', shape(10, 10, 0));
    expect(alive.size).toBe(3);
    expect(cache.acquire('a', 'k', shape(10, 10, 0)).fresh).toBe(true);
    expect(cache.acquire('b', 'k', shape(10, 10, 0)).fresh).toBe(false); // b was dropped
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
