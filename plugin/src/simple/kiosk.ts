/**
 * Kiosk mode (docs/simple-viewer.md): the page asks for fullscreen on every user gesture while it is
 * not fullscreen (browsers refuse it without one), and a visitor gets no context menu, no text
 * selection, no drag of page content and no zoom of the page itself (pinch, Ctrl+wheel, double tap);
 * the image still zooms, inside the viewer.
 */
import { enterFullscreen } from './fullscreen';

/** The gestures that may ask for fullscreen (user activations: not `pointerdown` of a touch). */
const ACTIVATIONS = ['pointerup', 'touchend', 'keydown', 'click'] as const;

/** Lock the page down for a kiosk; returns a function undoing it. */
export function lockDownKiosk(doc: Document): () => void {
  const root = doc.documentElement;
  root.classList.add('kiosk');
  const viewport = doc.querySelector<HTMLMetaElement>('meta[name="viewport"]');
  const before = viewport?.content ?? null;
  if (viewport) {
    viewport.content = 'width=device-width, initial-scale=1, maximum-scale=1, user-scalable=no';
  }
  const prevent = (e: Event): void => { e.preventDefault(); };
  const ctrlWheel = (e: WheelEvent): void => {
    if (e.ctrlKey) {
      e.preventDefault(); // the page's own zoom; the viewer zooms the image on a plain wheel
    }
  };
  const fullscreen = (): void => { enterFullscreen(doc); };
  const blocked = ['contextmenu', 'selectstart', 'dragstart', 'gesturestart'] as const;
  for (const type of blocked) {
    doc.addEventListener(type, prevent, { capture: true });
  }
  doc.addEventListener('wheel', ctrlWheel, { capture: true, passive: false });
  for (const type of ACTIVATIONS) {
    doc.addEventListener(type, fullscreen, { capture: true });
  }
  return () => {
    root.classList.remove('kiosk');
    if (viewport && before !== null) {
      viewport.content = before;
    }
    for (const type of blocked) {
      doc.removeEventListener(type, prevent, { capture: true });
    }
    doc.removeEventListener('wheel', ctrlWheel, { capture: true });
    for (const type of ACTIVATIONS) {
      doc.removeEventListener(type, fullscreen, { capture: true });
    }
  };
}
