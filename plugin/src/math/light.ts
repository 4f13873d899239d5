/**
 * Light direction maths: pointer position → light on the unit hemisphere.
 *
 * Convention (contract): `lu` to the right, `lv` up in the displayed image, `lz` towards the viewer.
 * Pure maths: no DOM, no GL.
 */

/** A light direction: its projection (lu, lv) on the image plane and lz = √(1 − lu² − lv²). */
export interface Light {
  readonly lu: number;
  readonly lv: number;
  readonly lz: number;
}

/** The light straight above the image (lu = lv = 0, lz = 1). */
export const OVERHEAD_LIGHT: Light = Object.freeze({ lu: 0, lv: 0, lz: 1 });

/**
 * Clamp (lu, lv) to the closed unit disk and complete it to a unit light direction.
 * Non-finite input is treated as 0.
 *
 * @param lu - x component
 * @param lv - y component
 * @returns the light with (lu, lv) on or inside the unit circle
 */
export function lightFromProjection(lu: number, lv: number): Light {
  let u = Number.isFinite(lu) ? lu : 0;
  let v = Number.isFinite(lv) ? lv : 0;
  const r2 = u * u + v * v;
  if (r2 > 1) {
    const r = Math.sqrt(r2);
    u /= r;
    v /= r;
  }
  const lz = Math.sqrt(Math.max(0, 1 - u * u - v * v));
  return { lu: u, lv: v, lz };
}

/**
 * Map a pointer position inside an element to a light: `lu = 2x/w − 1`, `lv = 1 − 2y/h`,
 * clamped to the unit disk. The element's centre is the overhead light; its right edge lu = 1,
 * its top edge lv = 1.
 *
 * @param x - pointer x in CSS px from the element's left edge
 * @param y - pointer y in CSS px from the element's top edge (down)
 * @param width - element width in CSS px (> 0)
 * @param height - element height in CSS px (> 0)
 */
export function lightFromPointer(x: number, y: number, width: number, height: number): Light {
  if (!(width > 0) || !(height > 0)) {
    return OVERHEAD_LIGHT;
  }
  return lightFromProjection((2 * x) / width - 1, 1 - (2 * y) / height);
}

/** Arrow-key direction for {@link nudgeLight}. */
export type NudgeDirection = 'left' | 'right' | 'up' | 'down';

/**
 * Move the light a small step in one direction (keyboard control), staying in the unit disk.
 *
 * @param light - current light
 * @param direction - which way to move: right → lu grows, up → lv grows
 * @param step - step size in lu/lv units
 * @default step 0.05
 */
export function nudgeLight(light: Light, direction: NudgeDirection, step = 0.05): Light {
  const du = direction === 'right' ? step : direction === 'left' ? -step : 0;
  const dv = direction === 'up' ? step : direction === 'down' ? -step : 0;
  return lightFromProjection(light.lu + du, light.lv + dv);
}

/**
 * A light direction as angles, in degrees. Azimuth is a compass bearing in the displayed image:
 * 0° = the light comes from the top (north, lv > 0), 90° from the right (east, lu > 0), 180° from
 * the bottom, 270° from the left, in [0, 360). Elevation is the angle above the image plane: 90°
 * overhead, 0° grazing (raking) light.
 */
export interface LightAngles {
  readonly azimuthDeg: number;
  readonly elevationDeg: number;
}

const DEG = 180 / Math.PI;

/**
 * The angles of a light: `azimuth = atan2(lu, lv)` (0 when the light is overhead),
 * `elevation = atan2(lz, √(lu² + lv²))`.
 */
export function lightAngles(light: Light): LightAngles {
  const r = Math.hypot(light.lu, light.lv);
  const azimuth = r > 0 ? Math.atan2(light.lu, light.lv) * DEG : 0;
  return {
    azimuthDeg: azimuth < 0 ? azimuth + 360 : azimuth,
    elevationDeg: Math.atan2(Math.max(0, light.lz), r) * DEG,
  };
}

/**
 * The light of an azimuth and an elevation (degrees, see {@link LightAngles}): `lu = cos(e)·sin(a)`,
 * `lv = cos(e)·cos(a)`. The elevation is clamped to [0°, 90°]; non-finite angles count as 0
 * (azimuth) and 90° (elevation).
 */
export function lightFromAngles(azimuthDeg: number, elevationDeg: number): Light {
  const a = (Number.isFinite(azimuthDeg) ? azimuthDeg : 0) / DEG;
  const e = Math.min(90, Math.max(0, Number.isFinite(elevationDeg) ? elevationDeg : 90)) / DEG;
  const r = Math.cos(e);
  return lightFromProjection(r * Math.sin(a), r * Math.cos(a));
}
