import { describe, expect, it } from 'vitest';
import { lightAngles, lightFromProjection } from '../../../plugin/src/math/light';
import { formatLight, LIGHT_PRESETS, RAKING_ELEVATION } from '../../../plugin/src/panel/light-angles';

describe('the panel\'s light presets and readout', () => {
  it('has overhead and raking presets from the four sides at the raking elevation', () => {
    expect(LIGHT_PRESETS.map((p) => p.id)).toEqual(['overhead', 'north', 'east', 'south', 'west']);
    expect(LIGHT_PRESETS[0]?.light).toEqual([0, 0]);
    const angles = LIGHT_PRESETS.slice(1).map((p) => lightAngles(lightFromProjection(p.light[0], p.light[1])));
    expect(angles.map((a) => Math.round(a.azimuthDeg) % 360)).toEqual([0, 90, 180, 270]);
    for (const a of angles) {
      expect(a.elevationDeg).toBeCloseTo(RAKING_ELEVATION);
    }
  });

  it('formats the readout', () => {
    expect(formatLight(0, 0)).toBe('Overhead (elevation 90°)');
    expect(formatLight(1, 0)).toBe('Azimuth 90°, elevation 0°');
    expect(formatLight(-0.5, 0.5)).toBe(`Azimuth 315°, elevation ${Math.round((Math.acos(Math.SQRT1_2) * 180) / Math.PI)}°`);
  });
});
