/**
 * The "Lanterna" companion window of a Mirador window (docs/mirador.md): a `wrap` plugin of
 * Mirador's `CompanionWindowFactory` that renders the windows whose `content` is `lanterna` itself —
 * Mirador's own companion-window frame around our controls panel (`controls-panel.ts`), mounted in
 * a React ref for the window's Lanterna viewer (`registry.ts`) — and leaves every other content to
 * Mirador.
 */
import { createElement, useEffect, useRef, useState, type ReactElement } from 'react';
import type { LanternaViewer } from '../../api/viewer-api';
import type { PanelSection } from '../../panel/panel-dom';
import { watchWindowViewer } from '../registry';
import type { MiradorPlugin, MiradorState, WrapProps } from '../types';
import { mountControlsPanel } from './controls-panel';
import { parts } from './mirador-parts';
import { ensurePanelStyle } from './panel-style';

/** The companion-window `content` of the Lanterna controls. */
export const LANTERNA_CONTENT = 'lanterna';

/** The text shown while the window has no (ready) Lanterna viewer: another canvas, or one still loading. */
export const NO_VIEWER_TEXT = 'The Lanterna controls show here while this window shows a Lanterna canvas.';

/** The window's viewer, following the registry (null: none). */
export function useWindowViewer(windowId: string): LanternaViewer | null {
  const [viewer, setViewer] = useState<LanternaViewer | null>(null);
  useEffect(() => watchWindowViewer(windowId, setViewer), [windowId]);
  return viewer;
}

const EMPTY_STYLE = { padding: '8px 12px', margin: 0, color: 'rgba(0, 0, 0, 0.6)' } as const;

interface PanelProps {
  readonly windowId: string;
  readonly manifestUrl: string;
}

/** The companion window's content: our panel once the viewer is ready, else a line saying there is none. */
function LanternaPanel({ windowId, manifestUrl }: PanelProps): ReactElement {
  const viewer = useWindowViewer(windowId);
  const mount = useRef<HTMLDivElement | null>(null);
  useEffect(() => {
    const element = mount.current;
    if (!viewer || !element) {
      return undefined;
    }
    ensurePanelStyle(element.ownerDocument);
    let live = true;
    let panel: PanelSection | null = null;
    viewer.ready.then(() => {
      if (live) {
        panel = mountControlsPanel(viewer, element, { manifestUrl });
      }
    }, () => undefined); // the viewer shows its own error
    return () => {
      live = false;
      panel?.destroy();
    };
  }, [viewer, manifestUrl]);
  return createElement('div', { className: 'lanterna-mirador-content' },
    createElement('div', { ref: mount }),
    viewer ? null : createElement('p', { className: 'lanterna-mirador-empty', style: EMPTY_STYLE }, NO_VIEWER_TEXT));
}

interface FactoryProps extends WrapProps {
  readonly content?: string | null;
  readonly id: string;
  readonly windowId: string;
  readonly manifestUrl?: string;
}

/** Mirador's `CompanionWindowFactory`, with the `lanterna` content rendered here. */
function LanternaCompanionWindowFactory(props: FactoryProps): ReactElement {
  const { content, id, windowId, manifestUrl = '' } = props;
  if (content !== LANTERNA_CONTENT) {
    return createElement(props.TargetComponent as Parameters<typeof createElement>[0], props.targetProps);
  }
  return createElement(parts.ConnectedCompanionWindow,
    { id, windowId, title: 'Lanterna', paperClassName: 'lanterna-companion-window' },
    createElement(LanternaPanel, { windowId, manifestUrl }));
}

/** The plugin: wraps `CompanionWindowFactory`; gets the window's manifest URL from Mirador's state. */
export const companionWindowPlugin: MiradorPlugin = {
  name: 'LanternaCompanionWindow',
  target: 'CompanionWindowFactory',
  mode: 'wrap',
  component: LanternaCompanionWindowFactory,
  mapStateToProps: (state: MiradorState, { windowId }: Record<string, unknown>) => ({
    manifestUrl: typeof windowId === 'string' ? parts.getWindow(state, { windowId })?.manifestId ?? '' : '',
  }),
};
