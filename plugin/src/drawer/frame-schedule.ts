/**
 * When the drawer renders a relit frame: what changed since the last rendered frame, and whether
 * a frame is due now (docs/rendering.md, "Frame scheduling"). Pure: no DOM, no GL.
 */

/**
 * What changed since the last rendered frame: nothing; only the tiles (new tiles, new textures:
 * loading); or the scene (view, canvas size, items and their opacity, light, mode, parameters,
 * lens, the layer set: everything a user changes).
 */
export type FrameChange = 'none' | 'tiles' | 'scene';

/** What a frame is made of, for comparing it with the last rendered one. */
export interface FrameKey {
  /** Everything but the tiles, compared element by element (`Object.is`). */
  readonly scene: readonly unknown[];
  /** The tiles drawn and their textures, compared element by element. */
  readonly tiles: readonly unknown[];
}

/**
 * While tiles are still loading, a progressive frame (one for new tiles only) waits until the GPU
 * has been idle for this many times the last frame's GPU time: progressive frames then take at
 * most 1 / (1 + factor) of the GPU, and the rest goes to what still has to arrive (decoding,
 * uploads, the next requests), which otherwise queue behind frames that are soon replaced.
 */
export const PROGRESSIVE_IDLE_FACTOR = 3;

/** The state a frame decision is made from. */
export interface FrameState {
  readonly change: FrameChange;
  /** Some tile of the frame still waits for its texture (the upload budget of a frame ran out). */
  readonly uploadsPending: boolean;
  /** Some visible item is still loading tiles. */
  readonly loading: boolean;
  /** The last rendered frame is still being drawn by the GPU. */
  readonly gpuBusy: boolean;
  /** Time since the last rendered frame was submitted (ms). */
  readonly sinceLastMs: number;
  /** GPU time of the last rendered frame, from submission to completion (ms; 0 if unknown). */
  readonly lastCostMs: number;
}

/**
 * Render now, or not: then `retryMs` says when to look again (0: the next animation frame; null:
 * nothing is waiting, until something changes).
 */
export type FrameDecision =
  | { readonly render: true }
  | { readonly render: false; readonly retryMs: number | null };

/** The difference between the last rendered frame (null: none yet) and the next one. */
export function compareFrames(last: FrameKey | null, next: FrameKey): FrameChange {
  if (!last || sceneChanged(last, next.scene)) {
    return 'scene';
  }
  return sameElements(last.tiles, next.tiles) ? 'none' : 'tiles';
}

/** True if the scene of `next` differs from that of the last rendered frame (or there is none). */
export function sceneChanged(last: FrameKey | null, scene: readonly unknown[]): boolean {
  return !last || !sameElements(last.scene, scene);
}

function sameElements(a: readonly unknown[], b: readonly unknown[]): boolean {
  return a.length === b.length && a.every((x, i) => Object.is(x, b[i]));
}

/**
 * Whether to render a frame. A scene change renders at once (interaction stays one frame per
 * animation frame); an unchanged frame is not drawn again; a tiles-only change waits for its
 * uploads, and while tiles are loading also for the GPU to finish the last frame and stay idle
 * {@link PROGRESSIVE_IDLE_FACTOR} times as long; the frame that completes the loading renders as
 * soon as its uploads and the GPU allow.
 */
export function decideFrame(s: FrameState): FrameDecision {
  if (s.change === 'scene') {
    return { render: true };
  }
  if (s.uploadsPending) {
    return { render: false, retryMs: 0 };
  }
  if (s.change === 'none') {
    return { render: false, retryMs: null };
  }
  if (s.gpuBusy) {
    return { render: false, retryMs: 0 };
  }
  const wait = s.loading ? PROGRESSIVE_IDLE_FACTOR * s.lastCostMs - s.sinceLastMs : 0;
  return wait > 0 ? { render: false, retryMs: Math.ceil(wait) } : { render: true };
}
