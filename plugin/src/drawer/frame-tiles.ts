/**
 * A frame's tiles: their textures uploaded (nearest the view's centre first, within the frame's
 * budget, or all at once), and the frame key of what will be drawn (docs/rendering.md).
 */
import { currentTexture, textureBytes, uploadedTexture, uploadPending, type TileTexture } from './plane-texture';
import { pickUploads, type PendingUpload } from './upload-budget';

/** One item of a frame and the tiles OpenSeadragon chose for it. */
export interface FrameEntry<I, T> {
  readonly item: I;
  readonly tiles: T[];
}

interface ItemLike {
  getOpacity(): number;
  getFullyLoaded(): boolean;
}

/** Options of {@link prepareFrameTiles}. */
export interface PrepareOptions<T> {
  readonly gl: WebGL2RenderingContext;
  /** The context generation (see ContextWatch). */
  readonly generation: number;
  /** Upload every texture the frame needs (a scene change, a read-back), not just the budget's. */
  readonly all: boolean;
  /** The tile's texture record (OpenSeadragon's drawer cache), undefined while it has none. */
  readonly textureOf: (tile: T) => TileTexture | undefined;
}

/** What a frame's tiles are after this frame's uploads. */
export interface FrameTiles {
  /** Each visible item and its tiles' textures (null: not drawn), for comparing frames. */
  readonly key: unknown[];
  /** Some tile still waits for its texture. */
  readonly pending: boolean;
  /** Some visible item is still loading tiles. */
  readonly loading: boolean;
}

/** Upload the frame's textures (see {@link PrepareOptions.all}) and describe what it draws. */
export function prepareFrameTiles<I extends ItemLike, T extends { squaredDistance?: number | null }>(
  entries: readonly FrameEntry<I, T>[], options: PrepareOptions<T>): FrameTiles {
  const { gl, generation } = options;
  const visible = entries.filter((e) => e.item.getOpacity() > 0);
  // each visible item's tiles' texture records, looked up once
  const records = visible.map(({ tiles }) => tiles.map((tile) => options.textureOf(tile)));
  const waiting: PendingUpload<TileTexture>[] = [];
  visible.forEach(({ tiles }, i) => {
    tiles.forEach((tile, k) => {
      const data = records[i]?.[k];
      if (data && uploadPending(data, generation)) {
        waiting.push({ tile: data, bytes: textureBytes(data), distance: tile.squaredDistance ?? Infinity });
      }
    });
  });
  const picked = options.all ? waiting.map((w) => w.tile) : pickUploads(waiting);
  for (const data of picked) {
    currentTexture(gl, data, generation);
  }
  const key: unknown[] = [];
  visible.forEach(({ item, tiles }, i) => {
    key.push(item, tiles.length);
    for (const data of records[i] ?? []) {
      key.push(data ? uploadedTexture(gl, data, generation) : null);
    }
  });
  return {
    key,
    pending: picked.length < waiting.length,
    loading: visible.some((e) => !e.item.getFullyLoaded()),
  };
}
