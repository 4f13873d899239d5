/**
 * The filtered quantities kept while the light moves: one set of float targets per slot (a layer
 * drawn into one framebuffer: the canvas, or the lens target), each remembering the key of what it
 * holds (`render/quantity-key.ts`). A slot whose key is unchanged is reused as it is; the
 * quantities that read the light go through one transient set, filtered again every frame.
 */
import type { QuantityShape, QuantityTargets, ScreenFilter } from './screen-filter';

/** How many slots are kept (base layers and the lens layer of one frame, a layer switch's fade). */
const MAX_SLOTS = 3;

/** The float targets to draw the quantity into, and whether they already hold it. */
export interface QuantitySlot {
  readonly targets: QuantityTargets;
  readonly fresh: boolean;
}

interface Slot {
  targets: QuantityTargets;
  key: string | null;
}

/** Small integer ids of GL objects and layers, for the plain-data keys. */
export class ObjectIds {
  private readonly ids = new WeakMap<object, number>();
  private next = 1;

  /** The id of `object` (the same for the same object, never reused). */
  of(object: object): number {
    let id = this.ids.get(object);
    if (id === undefined) {
      id = this.next++;
      this.ids.set(object, id);
    }
    return id;
  }
}

/** The kept quantities of one GL context. */
export class QuantityCache {
  /** In least-recently-used order (a Map iterates in insertion order). */
  private readonly slots = new Map<string, Slot>();
  private transient: QuantityTargets | null = null;

  constructor(private readonly filter: ScreenFilter) {}

  /**
   * The targets of `shape` for `slot`'s quantity of `key` (null: not to be kept); `fresh` when they
   * already hold the filtered quantity of that key. When
   * they do not, the caller draws and filters the quantity into them, then calls
   * {@link QuantityCache.keep}.
   */
  acquire(slot: string, key: string | null, shape: QuantityShape): QuantitySlot {
    if (key === null) {
      this.release(slot);
      this.transient = this.filter.targets(this.transient, shape);
      return { targets: this.transient, fresh: false };
    }
    let entry = this.slots.get(slot);
    this.slots.delete(slot);
    if (!entry) {
      const oldest = this.slots.size >= MAX_SLOTS ? this.slots.keys().next().value : undefined;
      if (oldest !== undefined) {
        this.release(oldest);
      }
      entry = { targets: this.filter.targets(null, shape), key: null };
    }
    this.slots.set(slot, entry);
    const targets = this.filter.targets(entry.targets, shape);
    const fresh = entry.key === key && targets === entry.targets;
    if (!fresh) {
      entry.key = null;
      entry.targets = targets;
    }
    return { targets, fresh };
  }

  /** `slot`'s target now holds the filtered quantity of `key`. */
  keep(slot: string, key: string): void {
    const entry = this.slots.get(slot);
    if (entry) {
      entry.key = key;
    }
  }

  /** Free every target. */
  destroy(): void {
    for (const slot of [...this.slots.keys()]) {
      this.release(slot);
    }
    this.filter.free(this.transient);
    this.transient = null;
  }

  private release(slot: string): void {
    const entry = this.slots.get(slot);
    if (entry) {
      this.filter.free(entry.targets);
      this.slots.delete(slot);
    }
  }
}
