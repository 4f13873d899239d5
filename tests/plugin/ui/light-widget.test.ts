import { describe, expect, it } from 'vitest';
import { lightFromAngles, lightFromProjection, OVERHEAD_LIGHT } from '../../../plugin/src/math/light';
import { lightAria } from '../../../plugin/src/ui/light-widget';

describe('lightAria (the light widget as an ARIA slider)', () => {
  it('has the azimuth as its value, within its range', () => {
    for (const [azimuth, elevation] of [[0, 10], [90, 30], [181, 45], [359.4, 5], [270, 80]]) {
      const aria = lightAria(lightFromAngles(azimuth ?? 0, elevation ?? 0));
      expect(aria['aria-valuemin']).toBe('0');
      expect(aria['aria-valuemax']).toBe('359');
      const now = Number(aria['aria-valuenow']);
      expect(now).toBe(Math.round(azimuth ?? 0) % 360);
      expect(now).toBeGreaterThanOrEqual(0);
      expect(now).toBeLessThanOrEqual(359);
    }
  });

  it('reads both angles in its value text', () => {
    expect(lightAria(lightFromAngles(90, 30))['aria-valuetext']).toBe('azimuth 90°, elevation 30°');
    expect(lightAria(OVERHEAD_LIGHT)['aria-valuetext']).toBe('azimuth 0°, elevation 90°');
    expect(lightAria(lightFromProjection(0, -1))['aria-valuetext']).toBe('azimuth 180°, elevation 0°');
    expect(lightAria(lightFromAngles(359.7, 12))['aria-valuenow']).toBe('0'); // 360° is 0°
  });
});
