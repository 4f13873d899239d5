/**
 * The light as azimuth and elevation, and the light presets of the panel (overhead, raking from the
 * four sides). Pure: no DOM.
 *
 * Azimuth: degrees clockwise from north (the top of the displayed image, +lv) towards east (+lu);
 * elevation: degrees above the image plane (90° = overhead). A local helper of the panel until
 * `math/light.ts` has its own `lightAngles`.
 */

/** A light as angles, in degrees. */
export interface LightAngles {
  /** 0–360, clockwise from north; 0 for the overhead light. */
  readonly azimuth: number;
  /** 0–90. */
  readonly elevation: number;
}

/** The angles of the light (lu, lv) (clamped to the unit disk). */
export function lightAngles(lu: number, lv: number): LightAngles {
  const r = Math.min(1, Math.hypot(lu, lv));
  const elevation = (Math.acos(r) * 180) / Math.PI;
  const azimuth = r === 0 ? 0 : (((Math.atan2(lu, lv) * 180) / Math.PI) + 360) % 360;
  return { azimuth, elevation };
}

/** The light (lu, lv) of an azimuth and an elevation (degrees). */
export function lightFromAngles(azimuth: number, elevation: number): [number, number] {
  const r = Math.cos((elevation * Math.PI) / 180);
  const a = (azimuth * Math.PI) / 180;
  return [r * Math.sin(a), r * Math.cos(a)];
}

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

const raking = (id: string, label: string, side: string, azimuth: number): LightPreset => ({
  id, label, title: `Raking light from the ${side} (${RAKING_ELEVATION}° above the surface)`,
  light: lightFromAngles(azimuth, RAKING_ELEVATION),
});

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
  const { azimuth, elevation } = lightAngles(lu, lv);
  if (elevation >= 89.5) {
    return 'Overhead (elevation 90°)';
  }
  return `Azimuth ${Math.round(azimuth) % 360}°, elevation ${Math.round(elevation)}°`;
}
