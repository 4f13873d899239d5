/**
 * The viewer's notices: the WebGL context is lost, tiles could not be loaded, errors after `ready`.
 * Kept as a list for the API and shown in the notice box over the viewer.
 */
import type OpenSeadragon from 'openseadragon';
import type { Notice } from '../api/viewer-api';
import { TileFailures } from '../tiles/tile-failures';
import { createNoticeBox, type NoticeBox, type NoticeView } from '../ui/notice-box';

/** Errors kept as notices at most (the latest). */
const MAX_ERRORS = 3;

/** Options of {@link ViewerNotices}. */
export interface ViewerNoticesOptions {
  /** Show the notice box (else the notices are only listed). */
  readonly show: boolean;
  /** The box's distance from the bottom of the viewer element (CSS px). */
  readonly bottom: number;
  /** Called when the notices changed. */
  onChange(): void;
}

/** A notice and how the box shows it. */
type Entry = Notice & Pick<NoticeView, 'tone' | 'action'>;

/** The text of an error: its message (and its name for errors that are not the plugin's own). */
function errorText(error: unknown): { message: string; detail: string } {
  if (error instanceof Error) {
    return { message: error.message || error.name, detail: error.name };
  }
  return { message: String(error), detail: '' };
}

/** The notices of one viewer. */
export class ViewerNotices {
  readonly #options: ViewerNoticesOptions;
  readonly #tiles: TileFailures;
  readonly #box: NoticeBox | null;
  #contextLost = false;
  #errors: { message: string; detail: string }[] = [];

  constructor(viewer: OpenSeadragon.Viewer, options: ViewerNoticesOptions) {
    this.#options = options;
    this.#tiles = new TileFailures(viewer, { onChange: () => { this.#changed(); } });
    this.#box = options.show ? createNoticeBox(viewer.element, { bottom: options.bottom }) : null;
  }

  /** The notices, oldest kind first (context, tiles, errors). */
  list(): Notice[] {
    return this.#entries().map(({ kind, message, detail }) => ({ kind, message, detail }));
  }

  /** The WebGL context was lost or restored. */
  setContextLost(lost: boolean): void {
    if (lost !== this.#contextLost) {
      this.#contextLost = lost;
      this.#changed();
    }
  }

  /** Show an error (the same message again moves it last). */
  reportError(error: unknown): void {
    const text = errorText(error);
    this.#errors = [...this.#errors.filter((e) => e.message !== text.message), text].slice(-MAX_ERRORS);
    this.#changed();
  }

  /** Remove the error notices. */
  dismissErrors(): void {
    if (this.#errors.length > 0) {
      this.#errors = [];
      this.#changed();
    }
  }

  /** Ask again for the tiles that failed. */
  retryTiles(): void {
    this.#tiles.retry();
  }

  /** Remove the box and stop listening. */
  destroy(): void {
    this.#tiles.destroy();
    this.#box?.destroy();
  }

  #entries(): Entry[] {
    const out: Entry[] = [];
    if (this.#contextLost) {
      out.push({
        kind: 'context-lost', tone: 'warning', detail: 'webglcontextlost',
        message: 'Graphics context lost: the view will be redrawn when the browser restores it.',
      });
    }
    const tiles = this.#tiles.state();
    if (tiles.count > 0) {
      out.push({
        kind: 'tiles-failed', tone: 'warning', detail: tiles.message,
        message: `Some tiles could not be loaded (${tiles.count}); showing a coarser level there`
          + (tiles.retrying ? ', retrying…' : '.'),
        action: { label: 'Retry', title: 'Ask for the missing tiles again', run: () => { this.retryTiles(); } },
      });
    }
    for (const e of this.#errors) {
      out.push({
        kind: 'error', tone: 'error', ...e,
        action: { label: '×', title: 'Dismiss', run: () => { this.dismissErrors(); } },
      });
    }
    return out;
  }

  #changed(): void {
    this.#box?.update(this.#entries());
    this.#options.onChange();
  }
}
