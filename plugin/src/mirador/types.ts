/**
 * The minimal types of the Mirador 4 plugin API that Lanterna uses (Mirador ships no types). Read from
 * Mirador 4.0.0's `src/extend/*`, `src/state/actions/{layers,canvas}.js` and `src/state/selectors/layers.js`;
 * the same in 4.0–4.2. Types only.
 */

/** A React component as Mirador's plugin mapping holds it (props in, an element or null out). */
export type PluginComponent<P = Record<string, unknown>> = (props: P) => unknown;

/** Where a plugin goes: `wrap` receives the original component, `add` is rendered at a `PluginHook`. */
export type PluginMode = 'wrap' | 'add';

/** A Mirador plugin object (`src/extend/pluginValidation.js`). */
export interface MiradorPlugin {
  readonly name?: string;
  /** The component it wraps or adds to (`OpenSeadragonViewer`, `WindowTopBarPluginArea`, …). */
  readonly target: string;
  readonly mode: PluginMode;
  /** A React component (function or class): Mirador connects it to the store when a map is given. */
  readonly component: unknown;
  readonly mapStateToProps?: (state: MiradorState, ownProps: Record<string, unknown>) => Record<string, unknown>;
  readonly mapDispatchToProps?: Record<string, (...args: never[]) => unknown>
    | ((dispatch: (action: unknown) => unknown, ownProps: Record<string, unknown>) => Record<string, unknown>);
  /** Reducers added to Mirador's root reducer, by state key. */
  readonly reducers?: Record<string, (state: unknown, action: unknown) => unknown>;
  /** A redux-saga generator run with Mirador's sagas. */
  readonly saga?: () => Generator;
  /** Deep-merged into Mirador's settings. */
  readonly config?: Record<string, unknown>;
  /** For a companion-window plugin: the key its window content is registered under. */
  readonly companionWindowKey?: string;
}

/** The props a `wrap` plugin receives besides the target's own (`src/extend/withPlugins.jsx`). */
export interface WrapProps {
  /** The wrapped component (rendered as `createElement(TargetComponent, targetProps)` to keep it). */
  readonly TargetComponent: unknown;
  /** The props the target would have received (its children included). */
  readonly targetProps: Record<string, unknown>;
}

/** `viewers[windowId]`: a window's viewport in canvas pixels (centre x, y; zoom = 1 / view width). */
export interface MiradorViewport {
  readonly x: number;
  readonly y: number;
  readonly zoom: number;
  readonly rotation?: number;
  readonly flip?: boolean;
}

/** One image resource's layer state: `layers[windowId][canvasId][imageResourceId]`. */
export interface MiradorLayerState {
  readonly visibility?: boolean;
  readonly opacity?: number;
  readonly index?: number;
}

/** The layer states of one canvas, by image resource id (the painting `Image` or `Choice` item id). */
export type MiradorCanvasLayers = Readonly<Record<string, MiradorLayerState>>;

/** A window (`windows[windowId]`): the slice we read. */
export interface MiradorWindow {
  readonly id: string;
  readonly manifestId?: string;
  readonly canvasId?: string;
  readonly visibleCanvases?: readonly string[];
}

/** A loaded manifest (`manifests[manifestId]`): the slice we read. */
export interface MiradorManifestEntry {
  readonly id: string;
  readonly isFetching?: boolean;
  readonly error?: unknown;
  /** The manifest's JSON as fetched. */
  readonly json?: unknown;
}

/** The slices of Mirador's state (`state.mirador` when it is mounted under that key, else the root). */
export interface MiradorSlice {
  readonly windows?: Readonly<Record<string, MiradorWindow>>;
  readonly manifests?: Readonly<Record<string, MiradorManifestEntry>>;
  readonly viewers?: Readonly<Record<string, MiradorViewport | undefined>>;
  readonly layers?: Readonly<Record<string, Readonly<Record<string, MiradorCanvasLayers>> | undefined>>;
}

/** Mirador's redux state: its slices at the root (the default store) or under `mirador`. */
export type MiradorState = MiradorSlice & { readonly mirador?: MiradorSlice };

/** The actions we dispatch (`src/state/actions/{canvas,layers}.js`). */
export interface MiradorActions {
  /** `updateViewport(windowId, payload)`: merged into `viewers[windowId]`. */
  readonly updateViewport: (windowId: string, payload: Partial<MiradorViewport>) => unknown;
  /** `updateLayers(windowId, canvasId, payload)`: merged into `layers[windowId][canvasId]`. */
  readonly updateLayers: (windowId: string, canvasId: string, payload: MiradorCanvasLayers) => unknown;
}
