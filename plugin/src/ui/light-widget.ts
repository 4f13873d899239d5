/**
 * The light widget: a disc showing the light direction (the dot is (lu, lv) on the unit disk).
 * Drag on it to move the light; when it has focus, the arrow keys nudge the light.
 */
import { lightAngles, lightFromPointer, nudgeLight, type Light, type NudgeDirection } from '../math/light';

/** The widget's DOM and its update function. */
export interface LightWidget {
  readonly element: HTMLElement;
  /** Show a light (call when it changes elsewhere). */
  update(light: Light): void;
  /** Dim the widget when the shown layer does not depend on the light. */
  setLit(lit: boolean): void;
  destroy(): void;
}

/** Options of {@link createLightWidget}. */
export interface LightWidgetOptions {
  getLight(): Light;
  setLight(light: Light): void;
  /** Diameter in CSS px. @default 96 */
  size?: number;
  /** Distance from the parent's bottom edge, CSS px. @default 12 */
  bottom?: number;
}

const KEYS: Readonly<Record<string, NudgeDirection>> = {
  ArrowLeft: 'left', ArrowRight: 'right', ArrowUp: 'up', ArrowDown: 'down',
};

/**
 * The widget's ARIA slider values for a light. A slider has one value, so it is the azimuth (a
 * compass bearing, 0–359°, {@link lightAngles}); `aria-valuetext` reads both angles, e.g.
 * "azimuth 90°, elevation 30°" (rounded to whole degrees).
 */
export function lightAria(light: Light): Readonly<Record<'aria-valuemin' | 'aria-valuemax' | 'aria-valuenow'
  | 'aria-valuetext', string>> {
  const { azimuthDeg, elevationDeg } = lightAngles(light);
  const azimuth = Math.round(azimuthDeg) % 360;
  return {
    'aria-valuemin': '0',
    'aria-valuemax': '359',
    'aria-valuenow': String(azimuth),
    'aria-valuetext': `azimuth ${azimuth}°, elevation ${Math.round(elevationDeg)}°`,
  };
}

/**
 * Create the widget inside `parent` (bottom-left corner).
 */
export function createLightWidget(parent: HTMLElement, options: LightWidgetOptions): LightWidget {
  const size = options.size ?? 96;
  const disc = document.createElement('div');
  disc.className = 'lanterna-light-widget';
  disc.tabIndex = 0;
  disc.setAttribute('role', 'slider');
  disc.setAttribute('aria-label', 'Light direction: drag, or use the arrow keys');
  disc.setAttribute('aria-roledescription', 'light direction');
  disc.title = 'Light direction: drag here, or focus and use the arrow keys';
  Object.assign(disc.style, {
    position: 'absolute', left: '12px', bottom: `${options.bottom ?? 12}px`, width: `${size}px`, height: `${size}px`,
    borderRadius: '50%', boxSizing: 'border-box', zIndex: '10', cursor: 'crosshair', touchAction: 'none',
    background: 'radial-gradient(circle at 50% 50%, #666 0%, #333 60%, #151515 100%)',
    border: '1px solid #aaa', boxShadow: '0 1px 6px rgba(0,0,0,0.6)', outlineOffset: '3px',
  });
  const cross = document.createElement('div');
  Object.assign(cross.style, {
    position: 'absolute', inset: '0', borderRadius: '50%', pointerEvents: 'none',
    background: 'linear-gradient(#888, #888) center / 1px 100% no-repeat, linear-gradient(#888, #888) center / 100% 1px no-repeat',
    opacity: '0.35',
  });
  const dot = document.createElement('div');
  Object.assign(dot.style, {
    position: 'absolute', width: '12px', height: '12px', marginLeft: '-6px', marginTop: '-6px',
    borderRadius: '50%', background: '#ffd75e', boxShadow: '0 0 8px #ffd75e', pointerEvents: 'none',
  });
  disc.append(cross, dot);
  parent.appendChild(disc);

  const fromEvent = (ev: PointerEvent): void => {
    const r = disc.getBoundingClientRect();
    options.setLight(lightFromPointer(ev.clientX - r.left, ev.clientY - r.top, r.width, r.height));
  };
  let dragging = false;
  const onDown = (ev: PointerEvent): void => {
    ev.stopPropagation();
    ev.preventDefault();
    disc.focus();
    dragging = true;
    disc.setPointerCapture(ev.pointerId);
    fromEvent(ev);
  };
  const onMove = (ev: PointerEvent): void => {
    if (dragging) {
      ev.stopPropagation();
      fromEvent(ev);
    }
  };
  const onUp = (ev: PointerEvent): void => {
    dragging = false;
    if (disc.hasPointerCapture(ev.pointerId)) {
      disc.releasePointerCapture(ev.pointerId);
    }
  };
  const onKey = (ev: KeyboardEvent): void => {
    const dir = KEYS[ev.key];
    if (dir) {
      ev.preventDefault();
      ev.stopPropagation();
      options.setLight(nudgeLight(options.getLight(), dir, ev.shiftKey ? 0.01 : 0.05));
    }
  };
  const stop = (ev: Event): void => { ev.stopPropagation(); };
  disc.addEventListener('pointerdown', onDown);
  disc.addEventListener('pointermove', onMove);
  disc.addEventListener('pointerup', onUp);
  disc.addEventListener('pointercancel', onUp);
  disc.addEventListener('keydown', onKey);
  disc.addEventListener('wheel', stop);
  disc.addEventListener('dblclick', stop);

  const update = (light: Light): void => {
    dot.style.left = `${50 + 50 * light.lu}%`;
    dot.style.top = `${50 - 50 * light.lv}%`;
    for (const [name, value] of Object.entries(lightAria(light))) {
      disc.setAttribute(name, value);
    }
  };
  update(options.getLight());
  return {
    element: disc,
    update,
    setLit: (lit: boolean) => {
      disc.style.opacity = lit ? '1' : '0.45';
      disc.title = lit ? 'Light direction: drag here, or focus and use the arrow keys'
        : 'This layer is not lit: the light changes nothing';
    },
    destroy: () => { disc.remove(); },
  };
}
