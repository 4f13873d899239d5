/**
 * The "Lanterna controls" button in a Mirador window's top bar (an `add` plugin of
 * `WindowTopBarPluginArea`): shown while the window has a Lanterna viewer, it opens the window's
 * Lanterna companion window on the right, or closes it when it is open.
 */
import { createElement, type ReactElement } from 'react';
import type { MiradorPlugin, MiradorState } from '../types';
import { LANTERNA_CONTENT, useWindowViewer } from './companion-window';
import { type CompanionWindowState, parts } from './mirador-parts';

/** The button's label (its tooltip and accessible name). */
export const BUTTON_LABEL = 'Lanterna controls';

interface ButtonProps {
  readonly windowId: string;
  /** The window's open Lanterna companion windows. */
  readonly openWindows: readonly CompanionWindowState[];
  readonly addCompanionWindow: (windowId: string, payload: { content: string; position: string }) => unknown;
  readonly removeCompanionWindow: (windowId: string, id: string) => unknown;
}

/** A light: a disc and its rays (our own drawing). */
function lightIcon(): ReactElement {
  return createElement('svg', { viewBox: '0 0 24 24', width: 24, height: 24, 'aria-hidden': true, focusable: false },
    createElement('path', {
      d: 'M12 7a5 5 0 1 0 0 10 5 5 0 0 0 0-10zM11 1h2v3h-2zM11 20h2v3h-2zM1 11h3v2H1zM20 11h3v2h-3z'
        + 'M4.2 5.6l1.4-1.4 2.1 2.1-1.4 1.4zM16.3 17.7l1.4-1.4 2.1 2.1-1.4 1.4z'
        + 'M4.2 18.4l2.1-2.1 1.4 1.4-2.1 2.1zM16.3 6.3l2.1-2.1 1.4 1.4-2.1 2.1z',
    }));
}

function LanternaTopBarButton({ windowId, openWindows, addCompanionWindow, removeCompanionWindow }: ButtonProps):
  ReactElement | null {
  const viewer = useWindowViewer(windowId);
  if (!viewer) {
    return null;
  }
  const open = openWindows.length > 0;
  const toggle = (): void => {
    if (open) {
      for (const { id } of openWindows) {
        removeCompanionWindow(windowId, id);
      }
    } else {
      addCompanionWindow(windowId, { content: LANTERNA_CONTENT, position: 'right' });
    }
  };
  return createElement(parts.MiradorMenuButton,
    { 'aria-label': BUTTON_LABEL, onClick: toggle, selected: open, className: 'lanterna-mirador-button' },
    lightIcon());
}

const NONE: readonly CompanionWindowState[] = [];

/** The plugin: the open Lanterna companion windows from Mirador's state (a memoised list); its two actions. */
export const topBarButtonPlugin: MiradorPlugin = {
  name: 'LanternaTopBarButton',
  target: 'WindowTopBarPluginArea',
  mode: 'add',
  component: LanternaTopBarButton,
  mapStateToProps: (state: MiradorState, { windowId }: Record<string, unknown>) => {
    const openWindows = typeof windowId === 'string'
      ? parts.getCompanionWindowsForContent(state, { windowId, content: LANTERNA_CONTENT }) : NONE;
    return { openWindows };
  },
  mapDispatchToProps: {
    addCompanionWindow: parts.addCompanionWindow,
    removeCompanionWindow: parts.removeCompanionWindow,
  },
};
