/**
 * 3×3 matrices (column-major, as WebGL `uniformMatrix3fv` expects) mapping a tile's unit quad to
 * clip space. Computed in double precision so that only the final matrix is rounded to float32.
 * Pure maths: no DOM, no GL.
 */

/** An axis-aligned rectangle. */
export interface RectLike {
  readonly x: number;
  readonly y: number;
  readonly width: number;
  readonly height: number;
}

/** Column-major 3×3 matrix. */
export type Mat3 = readonly [number, number, number, number, number, number, number, number, number];

/**
 * Multiply two column-major 3×3 matrices: `a · b`.
 */
export function multiply(a: Mat3, b: Mat3): Mat3 {
  const out: number[] = [];
  for (let col = 0; col < 3; col++) {
    for (let row = 0; row < 3; row++) {
      let s = 0;
      for (let k = 0; k < 3; k++) {
        s += a[k * 3 + row] * b[col * 3 + k];
      }
      out.push(s);
    }
  }
  return out as unknown as Mat3;
}

/**
 * View matrix: viewport coordinates (y down) → clip space (y up), for the visible viewport
 * rectangle `bounds`, optionally rotated by `rotation` radians about its centre and mirrored.
 */
export function viewMatrix(bounds: RectLike, rotation = 0, flipped = false): Mat3 {
  const cx = bounds.x + bounds.width / 2;
  const cy = bounds.y + bounds.height / 2;
  const sx = (2 / bounds.width) * (flipped ? -1 : 1);
  const sy = -2 / bounds.height;
  const scale: Mat3 = [sx, 0, 0, 0, sy, 0, 0, 0, 1];
  const c = Math.cos(-rotation);
  const s = Math.sin(-rotation);
  const rot: Mat3 = [c, s, 0, -s, c, 0, 0, 0, 1];
  const translate: Mat3 = [1, 0, 0, 0, 1, 0, -cx, -cy, 1];
  return multiply(multiply(scale, rot), translate);
}

/**
 * Model matrix: the unit quad [0,1]² → the tile's rectangle in viewport coordinates; a flipped
 * tile is mirrored about the quad's vertical centre line.
 */
export function modelMatrix(rect: RectLike, flipped = false): Mat3 {
  if (flipped) {
    return [-rect.width, 0, 0, 0, rect.height, 0, rect.x + rect.width, rect.y, 1];
  }
  return [rect.width, 0, 0, 0, rect.height, 0, rect.x, rect.y, 1];
}

/** Apply a matrix to a 2-D point (homogeneous w = 1). */
export function transformPoint(m: Mat3, x: number, y: number): [number, number] {
  return [m[0] * x + m[3] * y + m[6], m[1] * x + m[4] * y + m[7]];
}

/** Rotation by `degrees` (an OpenSeadragon item rotation) about the point `center`. */
export function rotationAbout(degrees: number, center: { readonly x: number; readonly y: number }): Mat3 {
  const a = (-degrees * Math.PI) / 180;
  const cos = Math.cos(a);
  const sin = Math.sin(a);
  const rot: Mat3 = [cos, sin, 0, -sin, cos, 0, 0, 0, 1];
  const toCenter: Mat3 = [1, 0, 0, 0, 1, 0, center.x, center.y, 1];
  return multiply(multiply(toCenter, rot), [1, 0, 0, 0, 1, 0, -center.x, -center.y, 1]);
}
