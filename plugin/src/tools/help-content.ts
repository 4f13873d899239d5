/**
 * What the help overlay lists: gestures per input device and the keys (`docs/viewer-api.md`, "Keys").
 * A table of sections, each a list of [what you do, what it does].
 */

/** One section of the help overlay. */
export interface HelpSection {
  readonly title: string;
  readonly rows: readonly (readonly [string, string])[];
}

/** The help overlay's content, in the order shown. */
export const HELP_SECTIONS: readonly HelpSection[] = [
  {
    title: 'Mouse',
    rows: [
      ['Drag', 'Move the light (in pan mode: pan)'],
      ['Shift + drag', 'The other of light and pan'],
      ['Right or middle drag', 'Pan'],
      ['Wheel', 'Zoom'],
      ['Double-click', 'Zoom in'],
      ['Drag inside the lens', 'Move the lens'],
      ['Drag the lens border, or wheel over the lens', 'Resize the lens'],
    ],
  },
  {
    title: 'Touch',
    rows: [
      ['One finger', 'Move the light (in pan mode: pan)'],
      ['Two fingers', 'Pan and pinch-zoom'],
      ['Two fingers starting inside the lens', 'Move and resize the lens'],
      ['Double-tap', 'Zoom in'],
    ],
  },
  {
    title: 'Pen',
    rows: [['Drag', 'Move the light, like a mouse']],
  },
  {
    title: 'Keys (click the image first)',
    rows: [
      ['← ↑ → ↓', 'Move the light'],
      ['Shift + ← ↑ → ↓', 'Pan'],
      ['L', 'Lens on or off'],
      ['A', 'Annotations on or off'],
      ['H', 'Home: the whole object'],
      ['S', 'Save a snapshot (PNG)'],
      ['?', 'This help'],
      ['Esc', 'Close this help'],
    ],
  },
  {
    title: 'OpenSeadragon keys (also on the image)',
    rows: [
      ['W / D', 'Pan up / right'],
      ['+ / −, Shift + W / Shift + S', 'Zoom in / out'],
      ['0', 'Home'],
      ['R / Shift + R', 'Rotate clockwise / counter-clockwise'],
      ['F', 'Flip horizontally'],
      ['Tab', 'Move between the controls'],
    ],
  },
];
