/**
 * Keyboard shortcuts on the viewer canvas (`docs/viewer-api.md`, "Keys"): the arrows move the light,
 * Shift+arrows pan; L lens, A annotations, H home, S snapshot, ? help. OpenSeadragon keeps its other
 * keys (w/d pan, Shift+W/Shift+S and +/- zoom, 0 home, r/R rotate, f flip); its a and s are taken by
 * the annotations and the snapshot.
 */
import OpenSeadragon from 'openseadragon';
import type { LanternaViewer } from '../api/viewer-api';
import { nudgeLight, type NudgeDirection } from '../math/light';

/** What the letter keys do. */
export interface KeyActions {
  lens(): void;
  annotations(): void;
  home(): void;
  snapshot(): void;
  help(): void;
}

const ARROWS: Readonly<Record<string, NudgeDirection>> = {
  ArrowLeft: 'left', ArrowRight: 'right', ArrowUp: 'up', ArrowDown: 'down',
};
/** CSS px per Shift+arrow pan (OpenSeadragon's `pixelsPerArrowPress`). */
const PAN_PX = 40;
const PAN: Readonly<Record<NudgeDirection, readonly [number, number]>> = {
  left: [-PAN_PX, 0], right: [PAN_PX, 0], up: [0, -PAN_PX], down: [0, PAN_PX],
};
/** Letter keys (by `KeyboardEvent.code`, so any layout's L is L) → action. */
const LETTERS: Readonly<Record<string, keyof KeyActions>> = {
  KeyL: 'lens', KeyA: 'annotations', KeyH: 'home', KeyS: 'snapshot',
};

interface CanvasKeyEvent {
  originalEvent: Event;
  preventDefaultAction: boolean;
}

/** Listen to keys on the viewer's canvas; returns a function that stops. */
export function attachKeys(lanterna: LanternaViewer, actions: KeyActions): () => void {
  const viewer = lanterna.viewer;
  const onKey = (e: CanvasKeyEvent): void => {
    const ev = e.originalEvent;
    if (!(ev instanceof KeyboardEvent) || ev.ctrlKey || ev.altKey || ev.metaKey) {
      return;
    }
    const arrow = ARROWS[ev.key];
    const letter = ev.shiftKey ? undefined : LETTERS[ev.code];
    if (arrow && !ev.shiftKey) {
      const l = nudgeLight(lanterna.getLight(), arrow);
      lanterna.setLight(l.lu, l.lv);
    } else if (arrow) {
      const [dx, dy] = PAN[arrow];
      viewer.viewport.panBy(viewer.viewport.deltaPointsFromPixels(new OpenSeadragon.Point(dx, dy)));
      viewer.viewport.applyConstraints();
    } else if (letter) {
      actions[letter]();
    } else if (ev.key === '?') {
      actions.help();
    } else {
      return;
    }
    e.preventDefaultAction = true;
    ev.preventDefault();
  };
  const add = viewer.addHandler.bind(viewer) as (name: string, h: (e: CanvasKeyEvent) => void) => void;
  const remove = viewer.removeHandler.bind(viewer) as (name: string, h: (e: CanvasKeyEvent) => void) => void;
  add('canvas-key', onKey);
  return () => { remove('canvas-key', onKey); };
}
