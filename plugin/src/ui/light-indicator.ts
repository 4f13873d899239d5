/**
 * A small disc with a dot showing the light direction, in a corner of the viewer.
 */
import type { Light } from '../math/light';

/** The indicator's DOM and its update function. */
export interface LightIndicator {
  readonly element: HTMLElement;
  update(light: Light): void;
  destroy(): void;
}

/**
 * Create the indicator inside `parent` (bottom-left corner).
 *
 * @param size - diameter in CSS px
 * @default size 64
 */
export function createLightIndicator(parent: HTMLElement, size = 64): LightIndicator {
  const disc = document.createElement('div');
  disc.className = 'lanterna-light-indicator';
  disc.title = 'Light direction';
  Object.assign(disc.style, {
    position: 'absolute', left: '12px', bottom: '12px', width: `${size}px`, height: `${size}px`,
    borderRadius: '50%', background: 'radial-gradient(circle at 50% 50%, #555, #111)',
    border: '1px solid #aaa', pointerEvents: 'none', zIndex: '10', boxSizing: 'border-box',
  });
  const dot = document.createElement('div');
  Object.assign(dot.style, {
    position: 'absolute', width: '10px', height: '10px', marginLeft: '-5px', marginTop: '-5px',
    borderRadius: '50%', background: '#ffd75e', boxShadow: '0 0 6px #ffd75e',
  });
  disc.appendChild(dot);
  parent.appendChild(disc);
  const update = (light: Light): void => {
    dot.style.left = `${50 + 50 * light.lu}%`;
    dot.style.top = `${50 - 50 * light.lv}%`;
  };
  return {
    element: disc,
    update,
    destroy: () => { disc.remove(); },
  };
}
