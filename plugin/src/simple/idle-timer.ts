/**
 * The kiosk's idle timer: calls `onIdle` once after `seconds` without input (pointer, touch, wheel,
 * key), and again only after the next input and another quiet period.
 */

/** The events that count as input. */
export const INPUT_EVENTS = ['pointerdown', 'pointermove', 'pointerup', 'wheel', 'keydown', 'touchstart'] as const;

/** A running idle timer. */
export interface IdleTimer {
  /** Start the quiet period again (as an input does). */
  poke(): void;
  destroy(): void;
}

/** Options of {@link createIdleTimer}. */
export interface IdleTimerOptions {
  /** Seconds without input; 0 or less: never idle. */
  readonly seconds: number;
  /** Called when the quiet period is over. */
  onIdle(): void;
  /** Where input is listened for (the window). */
  readonly target: EventTarget;
}

/** Start the timer (armed: the page counts as touched now). */
export function createIdleTimer(options: IdleTimerOptions): IdleTimer {
  let timer: ReturnType<typeof setTimeout> | null = null;
  const stop = (): void => {
    if (timer !== null) {
      clearTimeout(timer);
      timer = null;
    }
  };
  const poke = (): void => {
    stop();
    if (options.seconds > 0) {
      timer = setTimeout(() => {
        timer = null;
        options.onIdle();
      }, options.seconds * 1000);
    }
  };
  const listen = { capture: true, passive: true };
  for (const type of INPUT_EVENTS) {
    options.target.addEventListener(type, poke, listen);
  }
  poke();
  return {
    poke,
    destroy() {
      stop();
      for (const type of INPUT_EVENTS) {
        options.target.removeEventListener(type, poke, listen);
      }
    },
  };
}
