import { describe, expect, it } from 'vitest';
import { ContextWatch } from '../../../plugin/src/drawer/context-watch';
import { currentTexture, freeTileTexture, type TileTexture } from '../../../plugin/src/drawer/plane-texture';
import type { PlaneBundle } from '../../../plugin/src/tiles/bundle';

/** A WebGL2 context that only counts texture uploads and deletions; `lost` is settable. */
function fakeGl(): { gl: WebGL2RenderingContext; state: { lost: boolean; created: number; deleted: number } } {
  const state = { lost: false, created: 0, deleted: 0 };
  const gl = new Proxy({}, {
    get: (_target, name) => {
      if (name === 'isContextLost') {
        return () => state.lost;
      }
      if (name === 'createTexture') {
        return () => ({ texture: ++state.created });
      }
      if (name === 'deleteTexture') {
        return () => { state.deleted++; };
      }
      return typeof name === 'string' && /^[A-Z]/.test(name) ? 0 : () => undefined;
    },
  });
  return { gl: gl as WebGL2RenderingContext, state };
}

function tile(width = 4): TileTexture {
  const bitmap = { width, height: 4 } as ImageBitmap;
  const bundle: PlaneBundle = { bitmaps: [bitmap, bitmap], previewIndex: 0, width: 4, height: 4 };
  return { texture: null, texScale: [1, 1], generation: -1, bundle };
}

describe('tile textures across context losses', () => {
  it('are uploaded once per context generation, from the cached bundle', () => {
    const { gl, state } = fakeGl();
    const t = tile();
    const first = currentTexture(gl, t, 0);
    expect(first).not.toBeNull();
    expect(currentTexture(gl, t, 0)).toBe(first);
    expect(state.created).toBe(1);
    state.lost = true;
    expect(currentTexture(gl, t, 0)).toBeNull();
    state.lost = false;
    const second = currentTexture(gl, t, 1); // restored: a new generation
    expect(second).not.toBe(first);
    expect(state.created).toBe(2);
    expect(state.deleted).toBe(0); // the old texture went with the old context
  });

  it('are freed only in their own, live context', () => {
    const { gl, state } = fakeGl();
    const t = tile();
    currentTexture(gl, t, 0);
    freeTileTexture(gl, t, 1);
    expect(state.deleted).toBe(0);
    currentTexture(gl, t, 1);
    freeTileTexture(gl, t, 1);
    expect(state.deleted).toBe(1);
    expect(t.texture).toBeNull();
  });

  it('are skipped (null) when the bundle was closed, without throwing', () => {
    const { gl, state } = fakeGl();
    expect(currentTexture(gl, tile(0), 0)).toBeNull();
    expect(state.created).toBe(0);
  });
});

describe('ContextWatch', () => {
  it('keeps a lost context restorable and counts restorations', () => {
    const canvas = new EventTarget() as HTMLCanvasElement;
    const { gl } = fakeGl();
    const seen: string[] = [];
    const watch = new ContextWatch(canvas, gl, {
      lost: () => { seen.push('lost'); }, restored: () => { seen.push(`restored ${watch.generation}`); },
    });
    const lost = new Event('webglcontextlost', { cancelable: true });
    canvas.dispatchEvent(lost);
    expect(lost.defaultPrevented).toBe(true);
    canvas.dispatchEvent(new Event('webglcontextrestored'));
    expect(seen).toEqual(['lost', 'restored 1']);
    watch.destroy();
    canvas.dispatchEvent(new Event('webglcontextrestored'));
    expect(watch.generation).toBe(1);
  });
});
