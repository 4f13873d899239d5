/**
 * The public shape of a Lanterna viewer: the options of `createViewer` (`viewer/viewer.ts`), the
 * running viewer's API and its errors. Types and error classes only, so that the panel can be typed
 * against the viewer without importing it.
 */
import type OpenSeadragon from 'openseadragon';
import type { PixelData } from '../drawer/read-pixels';
import { LanternaError } from '../errors';
import type { PatchAnnotation } from '../iiif/annotation-page';

export type { PatchRenderState } from '../iiif/annotation-page';
import type { LoadedLayer } from '../iiif/load';
import type { ManifestInfo } from '../iiif/manifest';
import type { LayerType } from '../iiif/relight-service';
import type { LensState, LensUpdate } from '../lens/lens-state';
import type { Light } from '../math/light';
import type { OverlayState } from '../overlay/overlay-state';
import type { Preset, PresetLibrary, PresetTarget } from '../presets/library';
import type { RenderMode, ShadingClass } from '../render/modes';
import type { RenderParams } from '../render/params';
import type { DragMode } from '../ui/interaction';
import type { ViewStateApi } from './view-state-api';

/** Options of {@link createViewer}. */
export interface CreateViewerOptions {
  /** Container element (or its id). The viewer fills it. */
  element: HTMLElement | string;
  /** URL of the IIIF Presentation 3 manifest. */
  manifest: string;
  /** Initial light (lu, lv). @default [0, 0] */
  light?: readonly [number, number];
  /** What a plain drag does. @default 'light' */
  mode?: DragMode;
  /** Id of the layer shown first. @default the manifest's first layer */
  layer?: string;
  /** Show the light widget (a draggable, keyboard-controlled disc). @default true */
  lightIndicator?: boolean;
  /** Show the hypertext widget of the annotation overlays. @default true */
  hypertext?: boolean;
  /** Show the annotation overlays. @default true */
  overlays?: boolean;
  /**
   * Space (CSS px) kept free along the viewer's bottom edge for the host page's own controls
   * (Mirador's zoom buttons): the light widget, the annotation text box and the notices sit above it.
   * @default 0
   */
  bottomInset?: number;
  /** Extra OpenSeadragon options (the drawer, navigator and tile sources are set by Lanterna). */
  osd?: Partial<OpenSeadragon.Options>;
  /** `fetch` options for the manifest and info.json requests. */
  fetchInit?: RequestInit;
  /**
   * Longest side (px) up to which an image loads each pyramid level as one whole image per plane
   * group (its `sizes` file) instead of its tiles: one request per level and plane group. 0: tiles
   * always. @default 1024
   */
  wholeLevelMaxSide?: number;
  /**
   * Show notices over the viewer: the graphics context is lost, some tiles could not be loaded, an
   * error after `ready` (see {@link LanternaViewer.getNotices}). @default true
   */
  notices?: boolean;
  /**
   * Open only these layer ids (in manifest order); the others are not listed and never loaded.
   * `'presets'`: only the layers the preset library's entries use. @default every layer
   */
  layers?: readonly string[] | 'presets';
  /**
   * The preset library (`docs/presets.md`): its URL, or the document itself. @default the manifest's
   * `LanternaPresets` service, if any
   */
  presets?: string | object;
}

/**
 * Options of `attachLanterna` (a Lanterna viewer on an OpenSeadragon viewer the page already made,
 * docs/embedding.md): those of {@link createViewer} but the element and the OpenSeadragon options,
 * which are the page's.
 */
export type AttachLanternaOptions = Omit<CreateViewerOptions, 'element' | 'osd'>;

/** What a notice is about. */
export type NoticeKind = 'context-lost' | 'tiles-failed' | 'error';

/** A non-blocking message about the viewer's state, as {@link LanternaViewer.getNotices} lists it. */
export interface Notice {
  readonly kind: NoticeKind;
  /** The short text shown over the viewer. */
  readonly message: string;
  /** More about it: the failed URL and why, or the error's name. */
  readonly detail: string;
}

/** A layer as listed by {@link LanternaViewer.getLayers}. */
export interface LayerInfo {
  readonly id: string;
  readonly label: string;
  readonly layerType: LayerType;
  /** Its column in the contract's mode table (`docs/rendering.md`); `flat`: the light changes nothing. */
  readonly shading: ShadingClass;
  /** The render modes that apply to it, in menu order. */
  readonly modes: RenderMode[];
}

/** A render mode that is unknown or does not apply to the active layer. */
export class RenderModeError extends LanternaError {}
/** No layer has this id. */
export class UnknownLayerError extends LanternaError {}

/** A running Lanterna viewer. */
export interface LanternaViewer extends ViewStateApi {
  /** Resolves once the manifest is loaded and the default layer is added; rejects with a {@link LanternaError}. */
  readonly ready: Promise<void>;
  /** The OpenSeadragon viewer. */
  readonly viewer: OpenSeadragon.Viewer;
  /** The parsed manifest (null until ready). */
  readonly manifest: ManifestInfo | null;
  /** The active layer with its plane information (null until ready). */
  readonly layer: LoadedLayer | null;
  /** Set the light projection (clamped to the unit disk) and redraw. */
  setLight(lu: number, lv: number): void;
  /** The current light. */
  getLight(): Light;
  /**
   * Set what a plain drag does: `light`, `pan`, or `measure` (neither: the measurement widget,
   * `createMeasurement`, follows the pointer).
   */
  setMode(mode: DragMode): void;
  /** What a plain drag does. */
  getMode(): DragMode;
  /** The layers, in manifest order (empty until ready). */
  getLayers(): LayerInfo[];
  /** Show another layer (loads its plane information on first use); rejects with {@link UnknownLayerError}. */
  setActiveLayer(id: string): Promise<void>;
  /** The active layer's id ('' until ready). */
  getActiveLayer(): string;
  /** Set the render mode; throws {@link RenderModeError} if it does not apply to the active layer. */
  setRenderMode(mode: RenderMode): void;
  /** The render mode. */
  getRenderMode(): RenderMode;
  /** Change some render parameters (clamped to their ranges; unknown keys ignored). */
  setRenderParams(params: Partial<RenderParams>): void;
  /** The render parameters. */
  getRenderParams(): RenderParams;
  /** Set every render parameter back to its default. */
  resetRenderParams(): void;
  /**
   * Show or hide the active layer's annotation overlays (and the hypertext widget).
   */
  setOverlaysVisible(visible: boolean): void;
  /** Whether overlays are shown. */
  getOverlaysVisible(): boolean;
  /**
   * The current level (docs/annotations.md) and the active layer's overlay there: `available` false
   * when it has no overlay image at that level; `long` is sanitised HTML.
   */
  getOverlayState(): OverlayState;
  /**
   * Change the lens (any subset; `params` are merged into the lens's own parameters, `layer` ''
   * follows the active layer). Throws {@link UnknownLayerError}, {@link RenderModeError} or
   * `LensOptionError` for bad arguments; resolves once the lens layer is open.
   */
  setLens(update: LensUpdate): Promise<void>;
  /** The lens (`layer` resolved to an id). */
  getLens(): LensState;
  /**
   * The notices shown now, oldest first: `context-lost` while the WebGL context is lost,
   * `tiles-failed` while tiles of the view could not be loaded (a coarser level is drawn there), and
   * `error` for errors after `ready` (a lens or overlay layer that could not be opened, a frame that
   * could not be drawn, or one given to {@link LanternaViewer.reportError}).
   */
  getNotices(): Notice[];
  /** Show an error as an `error` notice (e.g. a rejected `setActiveLayer`); the latest three are kept. */
  reportError(error: unknown): void;
  /** Remove the `error` notices. */
  dismissErrors(): void;
  /** Ask again for every tile that failed to load (they are retried automatically twice, after 4 and 8 s). */
  retryFailedTiles(): void;
  /**
   * Call `listener` after any change of light, layer, mode, parameters, lens, overlays, level,
   * notices or annotations (a hidden patch, a refresh); returns an unsubscribe function.
   */
  onChange(listener: () => void): () => void;
  /** Fit the rectangle (x, y, w, h) in image pixels into the viewer, immediately. */
  showImageRegion(x: number, y: number, width: number, height: number): void;
  /** Resolves when every tile needed for the current view is loaded and drawn. */
  whenFullyLoaded(): Promise<void>;
  /** Render a frame now and read it back: RGBA, rows top-down, device pixels. */
  readPixels(): PixelData;
  /**
   * The region of the image in view (x, y, w, h in full-resolution image pixels, clipped to the image),
   * or null before `ready`.
   */
  getImageRegion(): [number, number, number, number] | null;
  /**
   * A layer's individual annotations (its patches, read from the W3C annotation page the manifest
   * references), in application order; the active layer's by default (`docs/annotations.md`).
   */
  getAnnotations(layerId?: string): readonly PatchAnnotation[];
  /**
   * Hide a patch (or show it again): while some patch of a level is hidden, that level is drawn
   * from its visible patches' own images instead of its pyramid. Throws a `LanternaError` for an
   * unknown id (the active layer's patches are looked up first).
   */
  setAnnotationHidden(id: string, hidden: boolean): void;
  /** Whether a patch is hidden (false for an unknown id). */
  isAnnotationHidden(id: string): boolean;
  /** Outline a patch's rectangle over the view (null: remove the outline). */
  highlightAnnotation(id: string | null): void;
  /**
   * Fit the view to a patch's rectangle and restore the render state it was drawn under (layer,
   * mode, parameters, light); resolves once done (rejects as `setState` does).
   */
  focusAnnotation(id: string): Promise<void>;
  /**
   * Fetch the manifest again (`cache: 'no-cache'`) with its annotation pages, replace every layer's
   * overlay levels and patches and swap the overlay items, without a page reload; resolves once the
   * new state is in place, then the {@link LanternaViewer.onChange} listeners are called.
   */
  refreshAnnotations(): Promise<void>;
  /** The preset library (the one given, else the manifest's, else an empty one). */
  getPresetLibrary(): PresetLibrary;
  /**
   * Replace the preset library (e.g. an imported file). It is checked against this dataset first;
   * throws `PresetError` naming the JSON path of the first problem, and then nothing changes.
   *
   * @param source - what to name in errors (a file name)
   */
  setPresetLibrary(library: unknown, source?: string): PresetLibrary;
  /**
   * Apply entry `index` of the library's `base` or `lens` list (`docs/presets.md`); the same as making
   * its calls by hand. Rejects with `PresetIndexError` for a missing entry.
   */
  applyPreset(target: PresetTarget, index: number): Promise<void>;
  /**
   * The current base (layer, mode, the parameters the mode uses, light; the view if `withView`) or lens
   * (layer, mode, parameters) as a preset named `label` (not added to the library).
   */
  capturePreset(target: PresetTarget, label: string, withView?: boolean): Preset;
  /**
   * Remove the viewer and free its GL resources. On a viewer given to `attachLanterna`: remove
   * Lanterna's items, handlers and widgets and give the page's viewer back a standard drawer
   * (docs/embedding.md).
   */
  destroy(): void;
}
