/**
 * The one place the simplified viewer calls measurement mode (paper §6.3, Fig. 7): the measurement
 * widget (`plugin/src/measure/`) in the viewer's element. While it is on, a one-finger drag or a hover
 * shows the BRDF slice (shape + material), the reflectance disk (PTM, HSH) or the value (images) of the
 * pixel under the finger, and the light stays where it is.
 */
import { createMeasurement, type LanternaViewer } from '../index';

/** Measurement mode as the page drives it. */
export interface MeasurementMode {
  setEnabled(on: boolean): void;
  destroy(): void;
}

/** Connect measurement mode to `lanterna`, drawing into `host` (the viewer's element). */
export function connectMeasurement(lanterna: LanternaViewer, host: HTMLElement): MeasurementMode {
  const widget = createMeasurement(lanterna, host);
  return {
    setEnabled(on) {
      widget.setEnabled(on);
    },
    destroy() {
      widget.destroy();
    },
  };
}
