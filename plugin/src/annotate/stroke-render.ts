/**
 * Drawing the operations of a {@link StrokeHistory} on a 2D canvas: each stroke is drawn opaque on a
 * scratch canvas (round caps and joins, a segment's width the mean of its ends'), then composited
 * with its opacity: source-over for the brush, destination-out for the eraser. So a stroke's own
 * overlaps do not darken it, and an eraser at 50 % halves what it passes over.
 */
import type { Stroke } from './stroke-history';

function context(canvas: HTMLCanvasElement): CanvasRenderingContext2D {
  const ctx = canvas.getContext('2d', { willReadFrequently: true });
  if (!ctx) {
    throw new Error('this browser gives no 2D canvas to draw on');
  }
  return ctx;
}

/** Draw `stroke` opaque into `ctx` (already cleared). */
function traceStroke(ctx: CanvasRenderingContext2D, stroke: Stroke): void {
  ctx.strokeStyle = ctx.fillStyle = stroke.tool === 'eraser' ? '#000000' : stroke.color;
  ctx.lineCap = 'round';
  ctx.lineJoin = 'round';
  const [first] = stroke.points;
  if (first && stroke.points.length === 1) {
    ctx.beginPath();
    ctx.arc(first.x, first.y, first.width / 2, 0, 2 * Math.PI);
    ctx.fill();
    return;
  }
  for (let i = 1; i < stroke.points.length; i++) {
    const a = stroke.points[i - 1];
    const b = stroke.points[i];
    if (!a || !b) {
      continue;
    }
    ctx.beginPath();
    ctx.lineWidth = (a.width + b.width) / 2;
    ctx.moveTo(a.x, a.y);
    ctx.lineTo(b.x, b.y);
    ctx.stroke();
  }
}

/** Draws strokes onto canvases of one size, through one scratch canvas. */
export class StrokeRenderer {
  readonly #scratch: HTMLCanvasElement;
  readonly #ctx: CanvasRenderingContext2D;

  constructor(width: number, height: number) {
    this.#scratch = document.createElement('canvas');
    this.#scratch.width = width;
    this.#scratch.height = height;
    this.#ctx = context(this.#scratch);
  }

  /** Composite `stroke` onto `target`. */
  draw(target: HTMLCanvasElement, stroke: Stroke): void {
    const { width, height } = this.#scratch;
    this.#ctx.clearRect(0, 0, width, height);
    traceStroke(this.#ctx, stroke);
    const out = context(target);
    out.save();
    out.globalAlpha = stroke.opacity;
    out.globalCompositeOperation = stroke.tool === 'eraser' ? 'destination-out' : 'source-over';
    out.drawImage(this.#scratch, 0, 0);
    out.restore();
  }

  /** Clear `target` and draw `strokes` in order. */
  replay(target: HTMLCanvasElement, strokes: readonly Stroke[]): void {
    context(target).clearRect(0, 0, target.width, target.height);
    for (const s of strokes) {
      this.draw(target, s);
    }
  }
}

/** `source` copied onto `target` (cleared first). */
export function copyCanvas(target: HTMLCanvasElement, source: HTMLCanvasElement): void {
  const ctx = context(target);
  ctx.clearRect(0, 0, target.width, target.height);
  ctx.drawImage(source, 0, 0);
}

/** The canvas as a PNG. */
export function canvasPng(canvas: HTMLCanvasElement): Promise<Blob> {
  return new Promise((resolve, reject) => {
    canvas.toBlob((blob) => {
      if (blob) {
        resolve(blob);
      } else {
        reject(new Error('the drawing could not be made into a PNG'));
      }
    }, 'image/png');
  });
}
