import { describe, expect, it } from 'vitest';
import { isLensAction, routeGesture, routeWheel, type GestureAction } from '../../../plugin/src/ui/gesture-routing';
import type { LensHit } from '../../../plugin/src/math/lens';

type Row = [contacts: number, hit: LensHit | null, button: number, shift: boolean, mode: 'light' | 'pan',
  expected: GestureAction];

// contacts × where the gesture starts (× button, Shift, drag mode) → action
const TABLE: Row[] = [
  [1, 'inside', 0, false, 'light', 'lens-move'],
  [1, 'inside', 0, true, 'pan', 'lens-move'],
  [1, 'border', 0, false, 'light', 'lens-resize'],
  [1, 'border', 0, false, 'pan', 'lens-resize'],
  [1, 'outside', 0, false, 'light', 'light'],
  [1, 'outside', 0, true, 'light', 'pan'],
  [1, 'outside', 0, false, 'pan', 'pan'],
  [1, 'outside', 0, true, 'pan', 'light'],
  [1, null, 0, false, 'light', 'light'],
  [1, null, 0, false, 'pan', 'pan'],
  [1, 'inside', 2, false, 'light', 'pan'],
  [1, 'outside', 1, false, 'light', 'pan'],
  [2, 'inside', 0, false, 'light', 'lens-transform'],
  [2, 'border', 0, false, 'light', 'lens-transform'],
  [2, 'outside', 0, false, 'light', 'image-pinch'],
  [2, null, 0, false, 'light', 'image-pinch'],
  [3, 'inside', 0, false, 'light', 'lens-transform'],
  [0, 'inside', 0, false, 'light', 'none'],
];

describe('routeGesture', () => {
  it.each(TABLE)('%i contact(s) starting %s (button %i, shift %s, %s mode) → %s',
    (contacts, hit, button, shift, dragMode, expected) => {
      expect(routeGesture({ contacts, hit, button, shift, dragMode })).toBe(expected);
    });

  it('keeps a two-finger gesture from turning into a one-finger drag when a finger lifts', () => {
    for (const previous of ['lens-transform', 'image-pinch'] as const) {
      expect(routeGesture({ contacts: 1, hit: 'outside', dragMode: 'light', previous })).toBe('none');
      expect(routeGesture({ contacts: 1, hit: 'inside', dragMode: 'light', previous })).toBe('none');
    }
    // a second finger joins a one-finger gesture: decided again from where the pair starts
    expect(routeGesture({ contacts: 2, hit: 'inside', dragMode: 'light', previous: 'light' })).toBe('lens-transform');
    expect(routeGesture({ contacts: 2, hit: 'outside', dragMode: 'light', previous: 'lens-move' })).toBe('image-pinch');
  });

  it('routes the wheel: over the lens resizes it, elsewhere zooms', () => {
    expect(routeWheel('inside')).toBe('lens-resize');
    expect(routeWheel('border')).toBe('lens-resize');
    expect(routeWheel('outside')).toBe('image-zoom');
    expect(routeWheel(null)).toBe('image-zoom');
  });

  it('names the lens actions', () => {
    expect(['lens-move', 'lens-resize', 'lens-transform', 'light', 'pan', 'image-pinch', 'image-zoom', 'none']
      .filter((a) => isLensAction(a as GestureAction))).toEqual(['lens-move', 'lens-resize', 'lens-transform']);
  });
});
