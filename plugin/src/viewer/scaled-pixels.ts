/**
 * The pixels of the image region in view at a chosen scale (output pixels per image pixel), drawn
 * tile by tile: the viewer is moved so that each tile of the output fills its canvas at exactly that
 * scale, read back, and put back where it was. Tiles overlap by a margin wider than the screen-space
 * filters reach (10 device px for F5), so the unsharp modes have no seams.
 */
import OpenSeadragon from 'openseadragon';
import type { LanternaViewer } from '../api/viewer-api';
import type { PixelData } from '../drawer/read-pixels';
import { LanternaError } from '../errors';
import { loadedOrFailed } from './loaded-or-failed';
import { applyViewState, readViewState } from './view-state';

/** Device pixels of each tile's border that are drawn but not kept. */
const MARGIN = 32;
/** The largest output, pixels (256 MiB of RGBA). */
export const MAX_SNAPSHOT_PIXELS = 64 * 1024 * 1024;

/** The view's image region (clipped to the image) at `scale` output px per image px. */
export async function scaledPixels(api: LanternaViewer, scale: number): Promise<PixelData> {
  const manifest = api.manifest;
  const viewport = api.viewer.viewport;
  if (!manifest || !(scale > 0) || !Number.isFinite(scale)) {
    throw new LanternaError(`snapshot: the scale must be a positive number, got ${String(scale)}`);
  }
  if (viewport.getRotation(true) % 360 !== 0 || viewport.getFlip()) {
    throw new LanternaError('snapshot: a scaled snapshot needs an unrotated, unflipped view');
  }
  const state = readViewState(api);
  const imageW = manifest.layer.width;
  const [vx, vy, vw, vh] = state.view;
  const x0 = Math.max(0, vx);
  const y0 = Math.max(0, vy);
  const outW = Math.round((Math.min(imageW, vx + vw) - x0) * scale);
  const outH = Math.round((Math.min(manifest.layer.height, vy + vh) - y0) * scale);
  if (outW < 1 || outH < 1 || outW * outH > MAX_SNAPSHOT_PIXELS) {
    throw new LanternaError(`snapshot: ${outW}×${outH} pixels at scale ${scale} (at most ${MAX_SNAPSHOT_PIXELS} pixels)`);
  }
  const first = api.readPixels();
  const stepX = first.width - 2 * MARGIN;
  const stepY = first.height - 2 * MARGIN;
  if (stepX < 1 || stepY < 1) {
    throw new LanternaError(`snapshot: the viewer (${first.width}×${first.height} px) is too small for a scaled snapshot`);
  }
  const container = viewport.getContainerSize();
  // Device px per CSS px as the canvas has it, and the zoom at which a device px is 1/scale image px.
  const density = first.width / container.x;
  const zoom = (scale * imageW) / (container.x * density);
  const saved = { center: viewport.getCenter(true), zoom: viewport.getZoom(true), lens: api.getLens() };
  const out = new Uint8Array(outW * outH * 4);
  const element = api.viewer.element;
  element.dataset.lanternaSnapshot = 'drawing';
  try {
    for (let ty = 0; ty < outH; ty += stepY) {
      for (let tx = 0; tx < outW; tx += stepX) {
        // The canvas's top-left corner at image point (x0 + (tx − M)/scale, y0 + (ty − M)/scale).
        const left = (x0 + (tx - MARGIN) / scale) / imageW;
        const top = (y0 + (ty - MARGIN) / scale) / imageW;
        viewport.zoomTo(zoom, undefined, true);
        viewport.panTo(new OpenSeadragon.Point(left + 0.5 / zoom, top + (0.5 * container.y) / (container.x * zoom)), true);
        if (state.lens.enabled) {
          await applyViewState(api, { lens: { center: state.lens.center, radius: state.lens.radius } });
        }
        api.viewer.forceRedraw();
        await loadedOrFailed(api);
        const tile = api.readPixels();
        const cols = Math.min(stepX, outW - tx);
        for (let r = 0; r < Math.min(stepY, outH - ty); r++) {
          const from = ((MARGIN + r) * tile.width + MARGIN) * 4;
          out.set(tile.data.subarray(from, from + cols * 4), ((ty + r) * outW + tx) * 4);
        }
      }
    }
  } finally {
    viewport.zoomTo(saved.zoom, undefined, true);
    viewport.panTo(saved.center, true);
    if (saved.lens.enabled) {
      await api.setLens({ center: saved.lens.center, radius: saved.lens.radius });
    }
    api.viewer.forceRedraw();
    delete element.dataset.lanternaSnapshot;
  }
  return { width: outW, height: outH, data: out };
}
