/**
 * A frame's items as the drawer reads them from OpenSeadragon: each item's rotation matrix, the
 * scene part of the frame key (docs/rendering.md, "Frame scheduling"), the items sorted by role.
 */
import type OpenSeadragon from 'openseadragon';
import type { ResolvedLayer } from '../layers/resolved-layer';
import { multiply, rotationAbout, type Mat3 } from '../math/matrix';
import type { FrameItem, FrameLayer } from './frame-renderer';

/** What the drawer reads of a TiledImage (typed locally: the shipped types omit some of it). */
export interface ItemLike {
  getOpacity(): number;
  getRotation(current?: boolean): number;
  getBoundsNoRotate(current?: boolean): OpenSeadragon.Rect;
  getFlip(): boolean;
}

const IDENTITY: Mat3 = [1, 0, 0, 0, 1, 0, 0, 0, 1];

/** The item's rotation about its centre. */
export function itemRotation(item: ItemLike): Mat3 {
  const degrees = item.getRotation(true);
  return degrees % 360 === 0 ? IDENTITY : rotationAbout(degrees, item.getBoundsNoRotate(true).getCenter());
}

/**
 * Everything but the tiles that makes a frame's picture: the canvas size, the settings' version
 * (light, mode, parameters, lens, roles: bumped by the drawer's setters), the view matrix, and each
 * item with its opacity, rotation, flip and bounds.
 */
export function sceneKey(canvas: { width: number; height: number }, settings: number, view: Mat3,
  items: readonly ItemLike[]): unknown[] {
  const key: unknown[] = [canvas.width, canvas.height, settings, ...view];
  for (const item of items) {
    const b = item.getBoundsNoRotate(true);
    key.push(item, item.getOpacity(), item.getRotation(true), item.getFlip(), b.x, b.y, b.width, b.height);
  }
  return key;
}

/** A frame's items sorted by role for the frame renderer: base layers, the lens layer, overlays. */
export interface FrameItems<T> {
  readonly layers: FrameLayer<T>[];
  readonly lensLayer: FrameLayer<T> | null;
  readonly overlays: FrameItem<T>[];
}

/**
 * Sort the visible items with tiles by role (`roleOf`: the lens layer or an overlay, else a base
 * layer); items without a resolved layer (other than overlays) are not drawn. Overlays come in
 * increasing `orderOf` (a stable sort: ties keep the world order).
 */
export function sortItems<I extends ItemLike, T>(entries: readonly { item: I; tiles: T[] }[], view: Mat3,
  roleOf: (item: I) => 'lens' | 'overlay' | undefined, layerOf: (item: I) => ResolvedLayer | undefined,
  orderOf: (item: I) => number = () => 0): FrameItems<T> {
  const layers: FrameLayer<T>[] = [];
  const overlays: (FrameItem<T> & { order: number })[] = [];
  let lensLayer: FrameLayer<T> | null = null;
  for (const { item, tiles } of entries) {
    if (item.getOpacity() === 0 || tiles.length === 0) {
      continue;
    }
    const role = roleOf(item);
    const layer = layerOf(item);
    const matrix = multiply(view, itemRotation(item));
    if (role === 'overlay') {
      overlays.push({ tiles, matrix, order: orderOf(item) });
    } else if (layer && role === 'lens') {
      lensLayer = { tiles, matrix, layer };
    } else if (layer) {
      layers.push({ tiles, matrix, layer });
    }
  }
  overlays.sort((a, b) => a.order - b.order);
  return { layers, lensLayer, overlays };
}
