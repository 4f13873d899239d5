import { describe, expect, it } from 'vitest';
import { parseManifest } from '../../../plugin/src/iiif/manifest';
import { overlayItemWidth, overlayState } from '../../../plugin/src/overlay/overlay-state';
import { manifestWithAnnotations, overlayAnnotation, overlayPage } from '../fixtures';

describe('overlay state and placement', () => {
  const layer = parseManifest(manifestWithAnnotations([overlayPage('ptm', [
    overlayAnnotation('ptm', 1, 'Figure', '<p onclick="x()">The <i>figure</i>.</p><script>x()</script>'),
  ])])).layers[0];

  it('reports the level, its texts (long text sanitised) or that there is none', () => {
    expect(overlayState(layer ?? null, 1)).toEqual({
      level: 1, available: true, short: 'Figure', long: '<p>The <i>figure</i>.</p>',
    });
    expect(overlayState(layer ?? null, 0)).toEqual({ level: 0, available: false, short: '', long: '' });
    expect(overlayState(null, 3)).toEqual({ level: 3, available: false, short: '', long: '' });
  });

  it('places level pixel i over full-resolution pixels [i·2^L, (i+1)·2^L)', () => {
    const level = (l: number, w: number): Parameters<typeof overlayItemWidth>[0] => ({
      layer: 'ptm', level: l, short: '', long: '', serviceId: 'x', width: w, height: 1, embedded: null,
    });
    expect(overlayItemWidth(level(0, 900), 900)).toBe(1);
    expect(overlayItemWidth(level(2, 225), 900)).toBe(1);
    expect(overlayItemWidth(level(3, 113), 900)).toBeCloseTo(904 / 900, 12); // ceil(900/8) = 113 overhangs
  });
});
