/** Where the measurement widget goes on screen (pure: no DOM). */

/** The gap between the pointer and the widget (CSS px). */
export const GAP_PX = 16;

/** Where the widget goes: beside (x, y), flipped to the other side near an edge, inside the host. */
export function placeBeside(x: number, y: number, size: { w: number; h: number }, host: { w: number; h: number }):
  { left: number; top: number } {
  const left = x + GAP_PX + size.w <= host.w ? x + GAP_PX : x - GAP_PX - size.w;
  const top = y + GAP_PX + size.h <= host.h ? y + GAP_PX : y - GAP_PX - size.h;
  return { left: Math.max(0, Math.min(left, host.w - size.w)), top: Math.max(0, Math.min(top, host.h - size.h)) };
}
