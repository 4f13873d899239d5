/**
 * Watching the drawer's WebGL context: a lost context is kept restorable (`preventDefault` on
 * `webglcontextlost`), and each restoration starts a new *generation*: every GL object made before
 * it is gone, so programs, targets and tile textures are made again from what the CPU still holds.
 */

/** What the watcher calls on a loss and after a restoration. */
export interface ContextHandlers {
  lost(): void;
  restored(): void;
}

/** The context's state and generation, from its canvas's events. */
export class ContextWatch {
  #generation = 0;
  readonly #canvas: HTMLCanvasElement;
  readonly #gl: WebGL2RenderingContext;
  readonly #onLost: (e: Event) => void;
  readonly #onRestored: () => void;

  constructor(canvas: HTMLCanvasElement, gl: WebGL2RenderingContext, handlers: ContextHandlers) {
    this.#canvas = canvas;
    this.#gl = gl;
    this.#onLost = (e: Event) => {
      e.preventDefault(); // without it the browser never restores the context
      handlers.lost();
    };
    this.#onRestored = () => {
      this.#generation++;
      handlers.restored();
    };
    canvas.addEventListener('webglcontextlost', this.#onLost);
    canvas.addEventListener('webglcontextrestored', this.#onRestored);
  }

  /** Incremented by each restoration: GL objects of an older generation are gone. */
  get generation(): number {
    return this.#generation;
  }

  /** True while the context is lost (every GL call is then a no-op). */
  get lost(): boolean {
    return this.#gl.isContextLost();
  }

  /** Stop listening. */
  destroy(): void {
    this.#canvas.removeEventListener('webglcontextlost', this.#onLost);
    this.#canvas.removeEventListener('webglcontextrestored', this.#onRestored);
  }
}
