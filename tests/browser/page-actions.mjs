// Page actions of tests/browser/render.mjs: synthetic input, route faults, and WebGL context loss.
//
// Gesture steps (x, y in CSS px of the viewer element; `steps` intermediate moves, default 8):
//   {"type": "touch", "from": [[x, y], ...], "to": [[x, y], ...], "steps": 8}  (1 or 2 fingers, CDP)
//       "alone": n  the first finger lands and moves n steps (of its path) before the others land
//   {"type": "viewport", "size": [width, height]}  (resize the page, then let the viewer follow)
//   {"type": "mouse", "from": [x, y], "to": [x, y], "steps": 8, "button": "left"}  (press, drag, release)
//   {"type": "pen", "from": [x, y], "to": [x, y], "steps": 8, "pressure": 0.5}  (a pen drag, CDP pointerType
//       "pen"; `pressure` 0–1 while pressed, default none: the browser's 0)
//   {"type": "wheel", "at": [x, y], "deltaY": -100}
//   {"type": "click", "selector": "CSS selector"}  (a click, or a tap with touch, on an element of the page)
//   {"type": "select", "selector": "CSS selector", "value": "…"}  (choose an option of a <select>)
//   {"type": "wait", "ms": 500}
//
// Route faults (spec "routes", tried in order; the first whose `match` regex finds the URL applies):
//   {"match": "regex", "status": 404, "body": "…", "contentType": "…", "headers": {…}}  (answer that)
//   {"match": "regex", "hang": true}  (never answer)
//   {"match": "regex", "abort": "failed"}  (a network error: playwright's route.abort codes)
//   "times": n  (only the first n matching requests; later ones go to the server)
import process from 'node:process';

/** Debian's Chromium (never a downloaded browser), and the flags every driver launches it with. */
export const CHROMIUM = process.env.LANTERNA_CHROMIUM ?? '/usr/bin/chromium';
export const CHROMIUM_ARGS = [
  '--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update',
  '--disable-sync', '--no-first-run', '--disable-quic',
];

/**
 * Collect a page's errors: every page error, and every console error (all of them in
 * `consoleErrors`; those no regex of `allowed` matches also in `pageErrors`, which fail a run).
 */
export function watchErrors(page, allowed, pageErrors, consoleErrors) {
  page.on('pageerror', (err) => pageErrors.push(`page error: ${err.message}`));
  page.on('console', (msg) => {
    if (msg.type() === 'error') {
      consoleErrors.push(msg.text());
      if (!allowed.some((re) => re.test(msg.text()))) {
        pageErrors.push(`console error: ${msg.text()}`);
      }
    }
  });
}

/** `promise`, or a rejection with `new ErrorClass("timed out after … s: what")` after `ms`. */
export function withTimeout(promise, ms, what, ErrorClass = Error) {
  let timer;
  const timeout = new Promise((_, reject) => {
    timer = setTimeout(() => reject(new ErrorClass(`timed out after ${ms / 1000} s: ${what}`)), ms);
  });
  return Promise.race([promise, timeout]).finally(() => clearTimeout(timer));
}

/** Wait until every tile of the view is loaded and drawn; the frame as base64 RGBA. */
export function readFrame(page) {
  return page.evaluate(async () => {
    const l = window.lanterna;
    await l.whenFullyLoaded();
    const { width, height, data } = l.readPixels();
    let binary = '';
    for (let i = 0; i < data.length; i += 0x8000) {
      binary += String.fromCharCode.apply(null, data.subarray(i, i + 0x8000));
    }
    return { width, height, base64: btoa(binary) };
  });
}

export const GESTURE_TYPES = ['touch', 'mouse', 'pen', 'wheel', 'click', 'select', 'wait', 'viewport'];

function lerp(a, b, t) {
  return a + (b - a) * t;
}

function nextFrame(page) {
  return page.evaluate(() => new Promise((r) => { requestAnimationFrame(() => r()); }));
}

/** Run one synthetic input step; (x, y) are CSS px of the viewer element at `origin`. */
export async function runGesture(page, cdp, origin, g, touch) {
  const steps = g.steps ?? 8;
  const at = ([x, y]) => ({ x: origin.x + x, y: origin.y + y });
  if (g.type === 'touch') {
    const to = g.to ?? g.from;
    const points = (t) => g.from.map((p, id) => {
      const q = to[id] ?? p;
      return { ...at([lerp(p[0], q[0], t), lerp(p[1], q[1], t)]), id };
    });
    const alone = g.alone ?? 0;
    await cdp.send('Input.dispatchTouchEvent', { type: 'touchStart', touchPoints: points(0).slice(0, alone > 0 ? 1 : undefined) });
    for (let k = 1; k <= alone; k++) {
      const first = points(k / steps).slice(0, 1);
      await cdp.send('Input.dispatchTouchEvent', { type: 'touchMove', touchPoints: first });
      await nextFrame(page);
    }
    if (alone > 0) {
      const landing = points(alone / steps).map((p, id) => (id === 0 ? p : { ...points(0)[id] }));
      await cdp.send('Input.dispatchTouchEvent', { type: 'touchStart', touchPoints: landing });
      await nextFrame(page);
    }
    for (let k = alone + 1; k <= steps; k++) {
      await cdp.send('Input.dispatchTouchEvent', { type: 'touchMove', touchPoints: points(k / steps) });
      await nextFrame(page);
    }
    await cdp.send('Input.dispatchTouchEvent', { type: 'touchEnd', touchPoints: [] });
  } else if (g.type === 'pen') {
    const from = at(g.from);
    const to = at(g.to ?? g.from);
    const pen = (type, p, buttons) => cdp.send('Input.dispatchMouseEvent', {
      type, x: p.x, y: p.y, button: 'left', buttons, clickCount: 1, pointerType: 'pen',
      ...(g.pressure !== undefined && buttons ? { force: g.pressure } : {}),
    });
    await pen('mousePressed', from, 1);
    for (let k = 1; k <= steps; k++) {
      await pen('mouseMoved', { x: lerp(from.x, to.x, k / steps), y: lerp(from.y, to.y, k / steps) }, 1);
      await nextFrame(page);
    }
    await pen('mouseReleased', to, 0);
  } else if (g.type === 'mouse') {
    const from = at(g.from);
    const to = at(g.to ?? g.from);
    await page.mouse.move(from.x, from.y);
    await page.mouse.down({ button: g.button ?? 'left' });
    for (let k = 1; k <= steps; k++) {
      await page.mouse.move(lerp(from.x, to.x, k / steps), lerp(from.y, to.y, k / steps));
      await nextFrame(page);
    }
    await page.mouse.up({ button: g.button ?? 'left' });
  } else if (g.type === 'click') {
    await (touch ? page.tap(g.selector) : page.click(g.selector));
  } else if (g.type === 'select') {
    await page.selectOption(g.selector, g.value);
  } else if (g.type === 'wait') {
    await page.waitForTimeout(g.ms ?? 100);
  } else if (g.type === 'viewport') {
    const [width, height] = g.size;
    await page.setViewportSize({ width, height });
    // OpenSeadragon notices the new container size at its next frame.
    for (let k = 0; k < 4; k++) {
      await nextFrame(page);
    }
  } else {
    const p = at(g.at);
    await page.mouse.move(p.x, p.y);
    await page.mouse.wheel(0, g.deltaY ?? -100);
  }
  await nextFrame(page);
}

/** Install the spec's route faults; returns the number of requests each one caught. */
export async function installRoutes(page, routes) {
  const hits = routes.map(() => 0);
  if (routes.length === 0) {
    return hits;
  }
  const patterns = routes.map((r) => new RegExp(r.match));
  await page.route(() => true, async (route) => {
    const url = route.request().url();
    const i = routes.findIndex((r, k) => patterns[k].test(url) && (r.times === undefined || hits[k] < r.times));
    if (i < 0) {
      await route.fallback();
      return;
    }
    hits[i]++;
    const r = routes[i];
    if (r.hang) {
      return; // never answered
    }
    if (r.abort !== undefined) {
      await route.abort(r.abort);
      return;
    }
    await route.fulfill({
      status: r.status ?? 200, body: r.body ?? '', contentType: r.contentType, headers: r.headers,
    });
  });
  return hits;
}

/** The notice box as the reader sees it, and the viewer's notices. */
export function readNotices(page) {
  return page.evaluate(() => {
    const box = document.querySelector('.lanterna-notices');
    const r = box?.getBoundingClientRect();
    const visible = box !== null && !box.hidden && r.height > 0;
    return {
      visible,
      rect: r ? [r.left, r.top, r.width, r.height] : null,
      texts: box ? [...box.querySelectorAll('.lanterna-notice')].map((n) => n.textContent) : [],
      list: window.lanterna?.getNotices?.() ?? [],
    };
  });
}

/**
 * Lose the viewer's WebGL context, check the page while it is lost (drawing and reading back must not
 * throw), then restore it. Returns the notices seen while lost.
 */
export async function loseAndRestoreContext(page, screenshot) {
  await page.evaluate(async () => {
    const gl = window.lanterna.viewer.drawer.canvas.getContext('webgl2');
    window.__lanternaLoseContext = gl.getExtension('WEBGL_lose_context');
    window.__lanternaLoseContext.loseContext();
    while (!gl.isContextLost()) {
      await new Promise((r) => { requestAnimationFrame(() => r()); });
    }
  });
  await page.waitForFunction(() => window.lanterna.getNotices().some((n) => n.kind === 'context-lost'));
  await page.evaluate(async () => {
    const l = window.lanterna;
    l.viewer.forceRedraw();
    l.readPixels();
    await new Promise((r) => { requestAnimationFrame(() => r()); });
  });
  const whileLost = await readNotices(page);
  if (screenshot) {
    await page.screenshot({ path: screenshot });
  }
  await page.evaluate(() => { window.__lanternaLoseContext.restoreContext(); });
  await page.waitForFunction(() => !window.lanterna.getNotices().some((n) => n.kind === 'context-lost'));
  return whileLost;
}
