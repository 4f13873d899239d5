/**
 * The light presets of the panel (overhead, raking from the four sides) and its readout, on the
 * angles of `math/light.ts` (azimuth clockwise from north, the top of the image, +lv; elevation above
 * the image plane). Pure: no DOM.
 */
import { lightAngles, lightFromAngles, lightFromProjection } from '../math/light';


/** The elevation of the raking presets, degrees. */
export const RAKING_ELEVATION = 15;

/** A light preset of the panel. */
export interface LightPreset {
  readonly id: string;
  /** The button's text. */
  readonly label: string;
  readonly title: string;
  readonly light: readonly [number, number];
}

const raking = (id: string, label: string, side: string, azimuth: number): LightPreset => {
  const { lu, lv } = lightFromAngles(azimuth, RAKING_ELEVATION);
  return { id, label, title: `Raking light from the ${side} (${RAKING_ELEVATION}° above the surface)`, light: [lu, lv] };
};

/** Overhead, then raking from north, east, south and west. */
export const LIGHT_PRESETS: readonly LightPreset[] = [
  { id: 'overhead', label: 'Overhead', title: 'Light straight above the object (reset)', light: [0, 0] },
  raking('north', 'N', 'north (top)', 0),
  raking('east', 'E', 'east (right)', 90),
  raking('south', 'S', 'south (bottom)', 180),
  raking('west', 'W', 'west (left)', 270),
];

/** The readout of a light: "azimuth 45°, elevation 30°" (overhead: "overhead (elevation 90°)"). */
export function formatLight(lu: number, lv: number): string {
  const { azimuthDeg, elevationDeg } = lightAngles(lightFromProjection(lu, lv));
  if (elevationDeg >= 89.5) {
    return 'Overhead (elevation 90°)';
  }
  return `Azimuth ${Math.round(azimuthDeg) % 360}°, elevation ${Math.round(elevationDeg)}°`;
}
