import { describe, expect, it } from 'vitest';
import {
  destination, frameImageRect, patchFrame, rectOnScreen, toDrawing, type Rect,
} from '../../../plugin/src/annotate/patch-frame';

describe('destination', () => {
  it('is the rule of docs/annotations.md "Building"', () => {
    expect(destination(0, 10, 20, 30, 40)).toEqual([10, 20, 40, 60]);
    expect(destination(2, 5, 3, 10, 2)).toEqual([1, 0, 4, 2]); // floor(5/4), floor(3/4), ceil(15/4), ceil(5/4)
    expect(destination(3, 0, 0, 1536, 1152)).toEqual([0, 0, 192, 144]);
  });
});

describe('patchFrame', () => {
  it('grows the view to whole level pixels and clips it to the canvas', () => {
    expect(patchFrame([10.5, 3.25, 100, 50.5], 2, 1536, 1152)).toEqual({
      level: 2, x: 8, y: 0, w: 104, h: 56, x0: 2, y0: 0, width: 26, height: 14,
    });
    // A view larger than the canvas: the whole canvas; the last level pixel column overhangs (1537 = 4·384 + 1).
    expect(patchFrame([-40, -30, 2000, 1500], 2, 1537, 1150)).toEqual({
      level: 2, x: 0, y: 0, w: 1537, h: 1150, x0: 0, y0: 0, width: 385, height: 288,
    });
  });

  it('has the size the server checks: the destination of its own rectangle', () => {
    let seed = 7;
    const rand = (): number => {
      seed = (seed * 1103515245 + 12345) % 2147483648;
      return seed / 2147483648;
    };
    for (let k = 0; k < 500; k++) {
      const W = 1 + Math.floor(rand() * 3000);
      const H = 1 + Math.floor(rand() * 3000);
      const level = Math.floor(rand() * 6);
      const region: Rect = [rand() * W - 50, rand() * H - 50, rand() * W, rand() * H];
      const f = patchFrame(region, level, W, H);
      const s = 2 ** level;
      const meets = region[0] < W && region[1] < H && region[0] + region[2] > 0 && region[1] + region[3] > 0;
      const [ax, ay, ax1, ay1] = [Math.max(0, region[0]), Math.max(0, region[1]),
        Math.min(W, region[0] + region[2]), Math.min(H, region[1] + region[3])];
      if (!meets || !(ax1 > ax && ay1 > ay)) {
        continue;
      }
      expect(f).not.toBeNull();
      if (!f) {
        continue;
      }
      const [x0, y0, x1, y1] = destination(level, f.x, f.y, f.w, f.h);
      expect([f.x0, f.y0, f.width, f.height]).toEqual([x0, y0, x1 - x0, y1 - y0]);
      // inside the canvas, covering the part of the region on it, starting on the level grid
      expect(f.x).toBeGreaterThanOrEqual(0);
      expect(f.x + f.w).toBeLessThanOrEqual(W);
      expect(f.x).toBeLessThanOrEqual(ax);
      expect(f.y).toBeLessThanOrEqual(ay);
      expect(f.x + f.w).toBeGreaterThanOrEqual(Math.min(W, Math.ceil(ax1)));
      expect(f.y + f.h).toBeGreaterThanOrEqual(Math.min(H, Math.ceil(ay1)));
      expect(f.x % s).toBe(0);
      expect(f.y % s).toBe(0);
      // no level pixel more than the region needs
      expect(f.x0 * s).toBeGreaterThan(ax - s);
      expect(x1 * s).toBeLessThan(ax1 + 2 * s);
    }
  });

  it('is null when the view misses the canvas, and refuses a bad level', () => {
    expect(patchFrame([200, 0, 50, 50], 0, 100, 100)).toBeNull();
    expect(patchFrame([0, -80, 50, 50], 1, 100, 100)).toBeNull();
    expect(() => patchFrame([0, 0, 10, 10], 1.5, 100, 100)).toThrow(/whole number/);
    expect(() => patchFrame([0, 0, 10, 10], -1, 100, 100)).toThrow(RangeError);
  });
});

describe('placing the drawing on the screen', () => {
  const frame = patchFrame([8, 4, 24, 20], 2, 1000, 1000);

  it('lies on the level pixels it stands for', () => {
    expect(frame).not.toBeNull();
    if (frame) {
      expect(frameImageRect(frame)).toEqual([8, 4, 24, 20]);
    }
  });

  it('maps image pixels to CSS pixels of the viewer and back to drawing pixels', () => {
    // 400×300 CSS px showing the image region 0,0,200,150: 2 CSS px per image px
    const rect = rectOnScreen([8, 4, 24, 20], [0, 0, 200, 150], 400, 300);
    expect(rect).toEqual([16, 8, 48, 40]);
    if (frame) {
      expect(toDrawing(frame, rect, 16, 8)).toEqual([0, 0]);
      expect(toDrawing(frame, rect, 64, 48)).toEqual([frame.width, frame.height]);
      expect(toDrawing(frame, rect, 40, 28)).toEqual([frame.width / 2, frame.height / 2]);
    }
  });
});
