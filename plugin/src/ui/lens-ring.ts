/**
 * The lens's visible border: a DOM ring over the viewer (it takes no pointer events; the gestures
 * are routed on the viewer's canvas).
 */
import type { Circle } from '../math/lens';

/** The ring and its update function. */
export interface LensRing {
  readonly element: HTMLElement;
  /** Show the ring at a circle (CSS px of the viewer element), or hide it. */
  update(circle: Circle, visible: boolean): void;
  destroy(): void;
}

/** Create the ring inside `parent` (the viewer element). */
export function createLensRing(parent: HTMLElement): LensRing {
  const ring = document.createElement('div');
  ring.className = 'lanterna-lens-ring';
  Object.assign(ring.style, {
    position: 'absolute', left: '0', top: '0', boxSizing: 'border-box', borderRadius: '50%', pointerEvents: 'none',
    zIndex: '5', border: '2px solid rgba(255, 215, 94, 0.95)',
    boxShadow: '0 0 0 1px rgba(0, 0, 0, 0.7), inset 0 0 0 1px rgba(0, 0, 0, 0.7)',
  });
  ring.hidden = true;
  parent.appendChild(ring);
  return {
    element: ring,
    update(circle, visible) {
      ring.hidden = !visible;
      const d = 2 * circle.radius;
      // The ring's 2 px stroke lies just outside the lens circle, so the pixels inside stay the lens layer's.
      Object.assign(ring.style, {
        width: `${d + 4}px`, height: `${d + 4}px`,
        transform: `translate(${circle.x - circle.radius - 2}px, ${circle.y - circle.radius - 2}px)`,
      });
    },
    destroy() {
      ring.remove();
    },
  };
}
