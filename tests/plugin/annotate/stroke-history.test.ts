import { describe, expect, it } from 'vitest';
import { StrokeHistory, visibleOperations, type Stroke } from '../../../plugin/src/annotate/stroke-history';

const stroke = (color: string, n = 2): Stroke => ({
  kind: 'stroke', tool: 'brush', color, opacity: 1,
  points: Array.from({ length: n }, (_, i) => ({ x: i, y: i, width: 4 })),
});

describe('StrokeHistory', () => {
  it('undoes and redoes strokes in order', () => {
    const h = new StrokeHistory();
    expect([h.isEmpty, h.canUndo, h.canRedo]).toEqual([true, false, false]);
    h.push(stroke('#a'));
    h.push(stroke('#b'));
    expect(h.operations.map((o) => o.kind === 'stroke' && o.color)).toEqual(['#a', '#b']);
    expect(h.undo()).toBe(true);
    expect(h.operations).toHaveLength(1);
    expect(h.canRedo).toBe(true);
    expect(h.redo()).toBe(true);
    expect(h.operations.map((o) => o.kind === 'stroke' && o.color)).toEqual(['#a', '#b']);
    expect(h.redo()).toBe(false);
    expect(h.undo() && h.undo()).toBe(true);
    expect([h.isEmpty, h.undo()]).toEqual([true, false]);
  });

  it('drops what was undone when something new is drawn', () => {
    const h = new StrokeHistory();
    h.push(stroke('#a'));
    h.push(stroke('#b'));
    h.undo();
    h.push(stroke('#c'));
    expect(h.canRedo).toBe(false);
    expect(h.operations.map((o) => o.kind === 'stroke' && o.color)).toEqual(['#a', '#c']);
  });

  it('clears, and undoing the clear brings the drawing back', () => {
    const h = new StrokeHistory();
    expect(h.push({ kind: 'clear' })).toBe(false); // nothing to clear
    h.push(stroke('#a'));
    expect(h.push({ kind: 'clear' })).toBe(true);
    expect(h.isEmpty).toBe(true);
    expect(visibleOperations(h.operations)).toEqual([]);
    h.push(stroke('#b'));
    expect(visibleOperations(h.operations).map((s) => s.color)).toEqual(['#b']);
    h.undo();
    h.undo();
    expect(h.isEmpty).toBe(false);
    expect(visibleOperations(h.operations).map((s) => s.color)).toEqual(['#a']);
  });

  it('ignores a stroke without points, and forgets everything on reset', () => {
    const h = new StrokeHistory();
    expect(h.push(stroke('#a', 0))).toBe(false);
    h.push(stroke('#a'));
    h.push(stroke('#b'));
    h.undo();
    h.reset();
    expect([h.isEmpty, h.canUndo, h.canRedo]).toEqual([true, false, false]);
  });
});
