/**
 * The drawing as a list of operations (strokes and clears) with undo and redo. The canvas is the
 * replay of {@link StrokeHistory.operations} in order (`draw-surface.ts`). Pure: no DOM.
 */

/** What a stroke does: paint (source-over) or erase (destination-out). */
export type StrokeTool = 'brush' | 'eraser';

/** A point of a stroke in drawing pixels, with the brush width there. */
export interface StrokePoint {
  readonly x: number;
  readonly y: number;
  readonly width: number;
}

/** One stroke: drawn opaque on its own, then composited with `opacity`. */
export interface Stroke {
  readonly kind: 'stroke';
  readonly tool: StrokeTool;
  /** CSS colour (`#rrggbb`), ignored by the eraser. */
  readonly color: string;
  /** 0–1. */
  readonly opacity: number;
  readonly points: readonly StrokePoint[];
}

/** Clear: everything before it is gone (and comes back on undo). */
export interface Clear {
  readonly kind: 'clear';
}

export type Operation = Stroke | Clear;

/** Undo and redo over a list of operations; a new operation drops what was undone. */
export class StrokeHistory {
  #done: Operation[] = [];
  #undone: Operation[] = [];

  /** The operations in effect, oldest first. */
  get operations(): readonly Operation[] {
    return this.#done;
  }

  /** Whether something is drawn: a stroke after the last clear. */
  get isEmpty(): boolean {
    const last = this.#done.at(-1);
    return last === undefined || last.kind === 'clear';
  }

  get canUndo(): boolean {
    return this.#done.length > 0;
  }

  get canRedo(): boolean {
    return this.#undone.length > 0;
  }

  /** Add an operation (a stroke with no points, or a clear of nothing, is not added); returns whether it was. */
  push(op: Operation): boolean {
    if (op.kind === 'stroke' ? op.points.length === 0 : this.isEmpty) {
      return false;
    }
    this.#done.push(op);
    this.#undone = [];
    return true;
  }

  /** Take back the last operation; returns whether there was one. */
  undo(): boolean {
    const op = this.#done.pop();
    if (op) {
      this.#undone.push(op);
    }
    return op !== undefined;
  }

  /** Do again the last operation taken back; returns whether there was one. */
  redo(): boolean {
    const op = this.#undone.pop();
    if (op) {
      this.#done.push(op);
    }
    return op !== undefined;
  }

  /** Forget everything (after an upload: the drawing is in the overlay now). */
  reset(): void {
    this.#done = [];
    this.#undone = [];
  }
}

/** The operations to replay: those after the last clear. */
export function visibleOperations(ops: readonly Operation[]): readonly Stroke[] {
  let start = 0;
  ops.forEach((op, i) => {
    if (op.kind === 'clear') {
      start = i + 1;
    }
  });
  return ops.slice(start).filter((op): op is Stroke => op.kind === 'stroke');
}
