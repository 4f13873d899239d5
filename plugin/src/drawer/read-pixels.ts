/**
 * Reading the canvas back: RGBA bytes of the drawing buffer, flipped to rows top-down.
 */

/** RGBA pixels, rows top-down. */
export interface PixelData {
  readonly width: number;
  readonly height: number;
  readonly data: Uint8Array;
}

/**
 * Read the default framebuffer (call right after drawing: the buffer is not preserved).
 *
 * @returns RGBA bytes, rows top-down, at the canvas's device-pixel size
 */
export function readCanvasPixels(gl: WebGL2RenderingContext): PixelData {
  const width = gl.drawingBufferWidth;
  const height = gl.drawingBufferHeight;
  const bottomUp = new Uint8Array(width * height * 4);
  gl.readPixels(0, 0, width, height, gl.RGBA, gl.UNSIGNED_BYTE, bottomUp);
  const data = new Uint8Array(bottomUp.length);
  const row = width * 4;
  for (let y = 0; y < height; y++) {
    data.set(bottomUp.subarray((height - 1 - y) * row, (height - y) * row), y * row);
  }
  return { width, height, data };
}
