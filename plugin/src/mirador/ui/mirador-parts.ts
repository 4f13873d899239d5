/**
 * The parts of Mirador 4's own exports the window's controls use, typed once here (Mirador ships no
 * types): its companion-window frame and menu button, the companion-window actions, and the
 * selectors of the state they read. All are in Mirador 4.0–4.2's `src/index.js` exports.
 */
import * as mirador from 'mirador';
import type { ComponentType, ReactNode } from 'react';
import type { MiradorState } from '../types';

/** A companion window (`companionWindows[id]`): the slice we read. */
export interface CompanionWindowState {
  readonly id: string;
  readonly content?: string | null;
  readonly position?: string | null;
}

/** An annotation page as Mirador holds it (`annotations[canvasId][pageId]`). */
export interface AnnotationPageState {
  readonly id?: string;
  readonly json?: unknown;
  readonly isFetching?: boolean;
}

/** What we use of the `mirador` module. */
interface MiradorParts {
  /** Mirador's companion-window frame (title bar, close, move and resize), connected to its store. */
  readonly ConnectedCompanionWindow: ComponentType<{
    id: string; windowId: string; title: string; paperClassName?: string; children?: ReactNode;
  }>;
  /** An icon button with a tooltip, as in Mirador's own top bars. */
  readonly MiradorMenuButton: ComponentType<{
    'aria-label': string; onClick: () => void; selected?: boolean; className?: string; children?: ReactNode;
  }>;
  readonly addCompanionWindow: (windowId: string, payload: { content: string; position: string }) => unknown;
  readonly removeCompanionWindow: (windowId: string, id: string) => unknown;
  readonly getCompanionWindowsForContent: (state: MiradorState,
    props: { windowId: string; content: string }) => readonly CompanionWindowState[];
  readonly getWindow: (state: MiradorState, props: { windowId: string }) => {
    manifestId?: string; selectedAnnotationId?: string; hoveredAnnotationIds?: readonly string[];
  } | undefined;
  readonly getManifest: (state: MiradorState, props: { windowId: string }) => { json?: unknown } | undefined;
  readonly getVisibleCanvasIds: (state: MiradorState, props: { windowId: string }) => readonly string[];
  readonly getAnnotations: (state: MiradorState) =>
    Readonly<Record<string, Readonly<Record<string, AnnotationPageState>> | undefined>> | undefined;
}

export const parts = mirador as unknown as MiradorParts;
