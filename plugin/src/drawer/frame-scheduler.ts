/**
 * The drawer's frame scheduling: renders a relit frame only when {@link decideFrame} says it is
 * due, measures each frame's GPU time with a fence, and asks OpenSeadragon for another `draw`
 * when a frame was put off (docs/rendering.md, "Frame scheduling").
 */
import { compareFrames, decideFrame, sceneChanged, type FrameKey } from './frame-schedule';

/** What the drawer knows of a frame besides its key. */
export interface FrameInput {
  readonly key: FrameKey;
  readonly uploadsPending: boolean;
  readonly loading: boolean;
}

/** Frame scheduler of one drawer (one WebGL2 context). */
export class FrameScheduler {
  readonly #gl: WebGL2RenderingContext;
  readonly #redraw: () => void;
  #last: FrameKey | null = null;
  #fence: WebGLSync | null = null;
  #submitted = 0;
  #cost = 0;
  #timer: ReturnType<typeof setTimeout> | null = null;
  #timerAt = Infinity;
  #waiting = false;
  #frames = 0;

  /** @param redraw - asks OpenSeadragon for a `draw` at its next update (`viewer.forceRedraw`) */
  constructor(gl: WebGL2RenderingContext, redraw: () => void) {
    this.#gl = gl;
    this.#redraw = redraw;
  }

  /** Relit frames rendered for the screen so far (not counting read-backs). */
  get frames(): number {
    return this.#frames;
  }

  /** True when the last rendered frame shows the current state and nothing waits to be drawn. */
  get settled(): boolean {
    return !this.#waiting;
  }

  /** Forget the last frame (a lost context): the next frame renders whatever it is. */
  reset(): void {
    this.#last = null;
    this.#deleteFence();
  }

  /** True if `scene` differs from the last rendered frame's (a frame then uploads every texture it needs). */
  sceneChanged(scene: readonly unknown[]): boolean {
    return sceneChanged(this.#last, scene);
  }

  /** Decide on the frame `input` and call `render` if it is due. */
  frame(input: FrameInput, render: () => void): void {
    const now = performance.now();
    this.#poll(now);
    const decision = decideFrame({
      change: compareFrames(this.#last, input.key),
      uploadsPending: input.uploadsPending,
      loading: input.loading,
      gpuBusy: this.#fence !== null,
      sinceLastMs: now - this.#submitted,
      lastCostMs: this.#cost,
    });
    if (!decision.render) {
      this.#waiting = decision.retryMs !== null;
      if (decision.retryMs !== null) {
        this.#schedule(decision.retryMs);
      }
      return;
    }
    render();
    this.#frames++;
    this.#last = input.key;
    this.#waiting = input.uploadsPending;
    this.#deleteFence();
    if (!this.#gl.isContextLost()) {
      this.#fence = this.#gl.fenceSync(this.#gl.SYNC_GPU_COMMANDS_COMPLETE, 0);
      this.#gl.flush();
    }
    this.#submitted = now;
  }

  destroy(): void {
    if (this.#timer !== null) {
      clearTimeout(this.#timer);
      this.#timer = null;
    }
    this.#deleteFence();
  }

  /** Take the last frame's GPU time if its fence has signalled. */
  #poll(now: number): void {
    const gl = this.#gl;
    if (this.#fence === null) {
      return;
    }
    if (gl.isContextLost()) {
      this.#fence = null;
      return;
    }
    if (gl.getSyncParameter(this.#fence, gl.SYNC_STATUS) === gl.SIGNALED) {
      this.#cost = now - this.#submitted;
      this.#deleteFence();
    }
  }

  /**
   * Ask for a `draw` in `ms` (0: at the next update). OpenSeadragon clears its redraw flag after
   * `draw` returns, so even that one is asked from a timer, never from inside `draw`.
   */
  #schedule(ms: number): void {
    const at = performance.now() + ms;
    if (this.#timer !== null && this.#timerAt <= at) {
      return;
    }
    if (this.#timer !== null) {
      clearTimeout(this.#timer);
    }
    this.#timerAt = at;
    this.#timer = setTimeout(() => {
      this.#timer = null;
      this.#timerAt = Infinity;
      this.#redraw();
    }, ms);
  }

  #deleteFence(): void {
    if (this.#fence !== null && !this.#gl.isContextLost()) {
      this.#gl.deleteSync(this.#fence);
    }
    this.#fence = null;
  }
}
