/**
 * Which tile textures to upload in a frame: the tiles nearest the view's centre first, up to a
 * budget of bytes per frame (docs/rendering.md, "Texture uploads"). Pure: no DOM, no GL.
 */

/**
 * Bytes of texture uploaded per frame while tiles load (a 256² RGBA plane is 256 KiB: 32 planes,
 * e.g. two 16-plane HSH tiles or ten 3-plane PTM tiles). At least one tile is uploaded per frame,
 * whatever its size, so a large bundle cannot stall the uploads.
 */
export const UPLOAD_BUDGET_BYTES = 8 * 1024 * 1024;

/** A tile waiting for its texture. */
export interface PendingUpload<T> {
  readonly tile: T;
  /** Bytes of the upload (all planes of the bundle). */
  readonly bytes: number;
  /** Squared distance of the tile's centre from the view's centre (OpenSeadragon's measure). */
  readonly distance: number;
}

/** The tiles to upload now, nearest first, within `budget` bytes (at least one). */
export function pickUploads<T>(pending: readonly PendingUpload<T>[], budget = UPLOAD_BUDGET_BYTES): T[] {
  const order = [...pending].sort((a, b) => a.distance - b.distance);
  const picked: T[] = [];
  let bytes = 0;
  for (const p of order) {
    if (picked.length > 0 && bytes + p.bytes > budget) {
      break;
    }
    picked.push(p.tile);
    bytes += p.bytes;
  }
  return picked;
}
