import { describe, expect, it } from 'vitest';
import {
  formatLight, LIGHT_PRESETS, lightAngles, lightFromAngles, RAKING_ELEVATION,
} from '../../../plugin/src/panel/light-angles';

describe('light angles', () => {
  it('measures the azimuth clockwise from north (+lv) and the elevation from the image plane', () => {
    expect(lightAngles(0, 1).azimuth).toBeCloseTo(0);
    expect(lightAngles(1, 0).azimuth).toBeCloseTo(90);
    expect(lightAngles(0, -1).azimuth).toBeCloseTo(180);
    expect(lightAngles(-1, 0).azimuth).toBeCloseTo(270);
    expect(lightAngles(0, 0).elevation).toBeCloseTo(90);
    expect(lightAngles(0.6, 0.8).elevation).toBeCloseTo(0);
    expect(lightAngles(Math.SQRT1_2, 0).elevation).toBeCloseTo(45);
  });

  it('inverts lightFromAngles', () => {
    for (const [lu, lv] of [[0.3, -0.4], [-0.7, 0.1], [0.05, 0.9], [-0.2, -0.2]] as const) {
      const { azimuth, elevation } = lightAngles(lu, lv);
      const [u, v] = lightFromAngles(azimuth, elevation);
      expect(u).toBeCloseTo(lu, 12);
      expect(v).toBeCloseTo(lv, 12);
    }
  });

  it('has overhead and raking presets from the four sides at the raking elevation', () => {
    expect(LIGHT_PRESETS.map((p) => p.id)).toEqual(['overhead', 'north', 'east', 'south', 'west']);
    expect(LIGHT_PRESETS[0]?.light).toEqual([0, 0]);
    const azimuths = LIGHT_PRESETS.slice(1).map((p) => lightAngles(p.light[0], p.light[1]));
    expect(azimuths.map((a) => Math.round(a.azimuth))).toEqual([0, 90, 180, 270]);
    for (const a of azimuths) {
      expect(a.elevation).toBeCloseTo(RAKING_ELEVATION);
    }
  });

  it('formats the readout', () => {
    expect(formatLight(0, 0)).toBe('Overhead (elevation 90°)');
    expect(formatLight(1, 0)).toBe('Azimuth 90°, elevation 0°');
    expect(formatLight(-0.5, 0.5)).toBe(`Azimuth 315°, elevation ${Math.round((Math.acos(Math.SQRT1_2) * 180) / Math.PI)}°`);
  });
});
