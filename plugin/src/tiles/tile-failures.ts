/**
 * Tiles that failed to load. OpenSeadragon marks such a tile as missing (`exists = false`) and keeps
 * drawing the coarser level there, but never asks for it again; this tracker revives the failed tiles
 * for another try: automatically a few times, with a growing delay, then when asked (a Retry button).
 */
import type OpenSeadragon from 'openseadragon';

/** The parts of an OpenSeadragon tile and tiled image the tracker uses. */
interface TileLike {
  exists: boolean;
}
interface ItemLike {
  getOpacity(): number;
}
type Handler = (event: Record<string, unknown>) => void;

/** Options of {@link TileFailures}. */
export interface TileFailuresOptions {
  /** Called when the count, the message or the retry schedule changed. */
  onChange(): void;
  /** Automatic retries of a failed tile. @default 2 */
  readonly autoRetries?: number;
  /** Delay before the first automatic retry, doubled for each next one (ms). @default 4000 */
  readonly retryDelayMs?: number;
}

/** What is known of the failed tiles of visible items. */
export interface TileFailureState {
  /** Failed tiles of visible items, not being retried now. */
  readonly count: number;
  /** The latest failure's message (names the URL and the reason). */
  readonly message: string;
  /** True while an automatic retry is scheduled. */
  readonly retrying: boolean;
}

/** The failed tiles of a viewer. */
export class TileFailures {
  readonly #viewer: OpenSeadragon.Viewer;
  readonly #options: TileFailuresOptions;
  readonly #failed = new Map<TileLike, ItemLike>();
  readonly #rounds = new WeakMap<TileLike, number>();
  readonly #handlers: [string, Handler][];
  #message = '';
  #timer: ReturnType<typeof setTimeout> | null = null;
  #shown = '';

  constructor(viewer: OpenSeadragon.Viewer, options: TileFailuresOptions) {
    this.#viewer = viewer;
    this.#options = options;
    this.#handlers = [
      ['tile-load-failed', (e) => { this.#onFailed(e.tile as TileLike, e.tiledImage as ItemLike, typeof e.message === 'string' ? e.message : ''); }],
      ['tile-loaded', (e) => { this.#forget(e.tile as TileLike); }],
      ['remove-item', (e) => { this.#forgetItem(e.item as ItemLike); }],
      // Items are shown and hidden (layers, lens, overlay levels) without an event: recount per frame.
      ['update-viewport', () => { this.#changed(); }],
    ];
    const add = viewer.addHandler.bind(viewer) as unknown as (name: string, h: Handler) => void;
    for (const [name, handler] of this.#handlers) {
      add(name, handler);
    }
  }

  /** The failed tiles of visible items and the retry schedule. */
  state(): TileFailureState {
    let count = 0;
    for (const item of this.#failed.values()) {
      if (item.getOpacity() > 0) {
        count++;
      }
    }
    return { count, message: this.#message, retrying: this.#timer !== null };
  }

  /** Ask for every failed tile again now (no more automatic retries for them). */
  retry(): void {
    const limit = this.#options.autoRetries ?? 2;
    for (const tile of this.#failed.keys()) {
      this.#rounds.set(tile, limit);
    }
    this.#cancel();
    this.#revive([...this.#failed.keys()]);
  }

  /** Stop listening and cancel the scheduled retry. */
  destroy(): void {
    const remove = this.#viewer.removeHandler.bind(this.#viewer) as unknown as (name: string, h: Handler) => void;
    for (const [name, handler] of this.#handlers) {
      remove(name, handler);
    }
    this.#cancel();
    this.#failed.clear();
  }

  #onFailed(tile: TileLike, item: ItemLike, message: string): void {
    this.#failed.set(tile, item);
    this.#message = message.replace(/^\[lanterna\]\s*/, '');
    this.#schedule();
    this.#changed();
  }

  #forget(tile: TileLike): void {
    if (this.#failed.delete(tile)) {
      this.#changed();
    }
  }

  #forgetItem(item: ItemLike): void {
    for (const [tile, owner] of this.#failed) {
      if (owner === item) {
        this.#failed.delete(tile);
      }
    }
    this.#changed();
  }

  /** Schedule the next automatic retry, if a failed tile has retries left and none is scheduled. */
  #schedule(): void {
    const limit = this.#options.autoRetries ?? 2;
    const rounds = [...this.#failed.keys()].map((t) => this.#rounds.get(t) ?? 0).filter((r) => r < limit);
    if (this.#timer !== null || rounds.length === 0) {
      return;
    }
    const delay = (this.#options.retryDelayMs ?? 4000) * 2 ** Math.min(...rounds);
    this.#timer = setTimeout(() => {
      this.#timer = null;
      const due = [...this.#failed.keys()].filter((t) => (this.#rounds.get(t) ?? 0) < limit);
      for (const tile of due) {
        this.#rounds.set(tile, (this.#rounds.get(tile) ?? 0) + 1);
      }
      this.#revive(due);
    }, delay);
  }

  #cancel(): void {
    if (this.#timer !== null) {
      clearTimeout(this.#timer);
      this.#timer = null;
    }
  }

  /** Mark tiles as existing again and let OpenSeadragon pick them up now. */
  #revive(tiles: readonly TileLike[]): void {
    if (tiles.length === 0) {
      return;
    }
    for (const tile of tiles) {
      tile.exists = true;
      this.#failed.delete(tile);
    }
    // The items are fully loaded (a missing tile does not count), so OpenSeadragon would not look at
    // their tiles again until the view changes: update them now, as if it had.
    (this.#viewer.world as unknown as { update(viewportChanged: boolean): void }).update(true);
    this.#viewer.forceRedraw();
    this.#changed();
  }

  /** Call onChange if what a notice would show changed. */
  #changed(): void {
    const { count, message, retrying } = this.state();
    const key = `${count}|${count > 0 ? message : ''}|${retrying}`;
    if (key !== this.#shown) {
      this.#shown = key;
      this.#options.onChange();
    }
  }
}
