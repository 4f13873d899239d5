/**
 * The one place the simplified viewer calls measurement mode (paper §6.3, Fig. 7). The measurement
 * module (`plugin/src/measure/`, `createMeasurement(lanterna, host)`) is being built beside this page;
 * until it is connected here, the toggle only changes what a one-finger drag does (no light: the
 * drag pans) and shows a placeholder line.
 */
import type { LanternaViewer } from '../index';

/** Measurement mode as the page drives it. */
export interface MeasurementMode {
  setEnabled(on: boolean): void;
  destroy(): void;
}

/** Connect measurement mode to `lanterna`, drawing into `host` (the viewer's element). */
export function connectMeasurement(lanterna: LanternaViewer, host: HTMLElement): MeasurementMode {
  const placeholder = document.createElement('div');
  placeholder.className = 'measure-placeholder';
  placeholder.textContent = 'Measurement mode';
  placeholder.hidden = true;
  host.appendChild(placeholder);
  return {
    setEnabled(on) {
      lanterna.setMode(on ? 'pan' : 'light');
      placeholder.hidden = !on;
    },
    destroy() {
      placeholder.remove();
    },
  };
}
