/**
 * The React components of the viewer plugin: {@link LanternaSwitch} wraps Mirador's
 * `OpenSeadragonViewer` and renders it unchanged unless the window's canvas is a Lanterna one; then
 * {@link LanternaWindowView} mounts our own viewer (`createViewer`, with the OpenSeadragon 6 bundled
 * here, never Mirador's) in its place, with Mirador's children (zoom buttons, canvas navigation) over it.
 */
import { Children, cloneElement, createElement, isValidElement, useEffect, useRef, useState,
  type ReactElement, type ReactNode } from 'react';
import type { LanternaViewer } from '../api/viewer-api';
import { createViewer } from '../viewer/viewer';
import type { LanternaCanvas } from './lanterna-canvas';
import { setWindowViewer } from './registry';
import type { MiradorCanvasLayers, MiradorViewport } from './types';
import { topVisibleLayer } from './layer-map';
import { WindowSync, type MiradorDispatch } from './window-sync';

/** The props the wrap plugin receives: Mirador's (the target's own) and our `mapStateToProps`'. */
export interface SwitchProps extends MiradorDispatch {
  readonly windowId: string;
  readonly TargetComponent: Parameters<typeof createElement>[0];
  readonly targetProps: Record<string, unknown>;
  /** Mirador's `viewers[windowId]`. */
  readonly viewerConfig?: Partial<MiradorViewport> | null;
  /** The window's canvas when Lanterna relights it, else null. */
  readonly lanterna: LanternaCanvas | null;
  /** Mirador's layer state of that canvas. */
  readonly miradorLayers?: MiradorCanvasLayers;
}

/** Mirador's viewer, or ours for a Lanterna canvas. */
export function LanternaSwitch(props: SwitchProps): ReactElement {
  const { lanterna } = props;
  if (!lanterna) {
    return createElement(props.TargetComponent, props.targetProps);
  }
  return createElement(LanternaWindowView, { ...props, lanterna, key: `${lanterna.manifestUrl} ${lanterna.canvasId}` });
}

/** Height (px) of Mirador's canvas controls along the window's bottom edge (zoom, previous/next). */
const MIRADOR_CONTROLS_PX = 72;

/** One window's Lanterna viewer, created on mount and destroyed on unmount (a new canvas remounts it). */
export function LanternaWindowView(props: SwitchProps & { readonly lanterna: LanternaCanvas }): ReactElement {
  const { windowId, lanterna: canvas } = props;
  const mount = useRef<HTMLDivElement>(null);
  const sync = useRef<WindowSync | null>(null);
  const latest = useRef(props);
  latest.current = props;
  const [error, setError] = useState('');
  const [ready, setReady] = useState(false);

  useEffect(() => {
    const element = mount.current;
    if (!element) {
      return undefined;
    }
    const top = topVisibleLayer(canvas.layers.map((l) => l.imageId), latest.current.miradorLayers);
    const layer = canvas.layers.find((l) => l.imageId === top?.imageId)?.id;
    let lanterna: LanternaViewer;
    try {
      lanterna = createViewer({
        element, manifest: canvas.manifestUrl, mode: 'pan', bottomInset: MIRADOR_CONTROLS_PX,
        ...(layer ? { layer } : {}) });
    } catch (e: unknown) {
      setError(e instanceof Error ? e.message : String(e));
      return undefined;
    }
    let alive = true;
    lanterna.ready.then(() => {
      if (!alive) {
        return;
      }
      const dispatch: MiradorDispatch = {
        updateViewport: (w, p) => { latest.current.updateViewport(w, p); },
        updateLayers: (w, c, p) => { latest.current.updateLayers(w, c, p); },
      };
      sync.current = new WindowSync(lanterna, element, windowId, canvas, dispatch);
      sync.current.fromMiradorLayers(latest.current.miradorLayers);
      sync.current.fromMirador(latest.current.viewerConfig);
      setWindowViewer(windowId, lanterna);
      setReady(true);
    }, (e: unknown) => {
      if (alive) {
        setError(e instanceof Error ? e.message : String(e));
      }
    });
    return () => {
      alive = false;
      sync.current?.destroy();
      sync.current = null;
      setWindowViewer(windowId, null);
      lanterna.destroy();
    };
  }, [windowId, canvas]);

  useEffect(() => { sync.current?.fromMirador(props.viewerConfig); }, [props.viewerConfig, ready]);
  useEffect(() => { sync.current?.fromMiradorLayers(props.miradorLayers); }, [props.miradorLayers, ready]);

  const zoomToWorld = (): void => { sync.current?.zoomToWorld(); };
  // `children` is the wrapped element itself (withPlugins.jsx); the target's own children are Mirador's controls.
  const own = props.targetProps.children as ReactNode;
  const children = Children.map(own, (child) => (isValidElement(child)
    ? cloneElement(child as ReactElement<{ zoomToWorld?: () => void }>, { zoomToWorld }) : child));
  return createElement('section', {
    className: 'mirador-osd-container lanterna-mirador-view',
    'data-window-id': windowId,
    style: { flex: 1, position: 'relative', overflow: 'hidden' },
  },
  createElement('div', { ref: mount, className: 'lanterna-mirador-canvas', style: { position: 'absolute', inset: 0 } }),
  error ? createElement('div', { className: 'lanterna-mirador-error', role: 'alert',
    style: { position: 'absolute', top: 8, left: 8, right: 8, padding: 8, background: '#fff', color: '#b00020' } },
  `Lanterna: ${error}`) : null,
  children);
}
