#!/usr/bin/env node
// Drive the simplified viewer page (plugin/simple.html) in headless Chromium through a list of steps.
//
//   node tests/browser/simple-page.mjs SPEC.json
//
// SPEC = {"url": "…/viewer/simple.html?manifest=…", "viewport": {"width": 1920, "height": 1080},
//         "steps": [...], "result": "/abs/result.json", "timeoutMs": 60000,
//         "touch": true, "routes": [...], "allowConsoleErrors": ["regex", …], "expect": "ready" | "unavailable"}
//
// The page is opened with `wholeLevelMaxSide=0` and `minPixelRatio=0.75` (as render.mjs does) unless the
// URL sets them; the run waits for `body[data-state=ready]` (or `unavailable`, with "expect": "unavailable").
// Steps, in order:
//   the gestures of page-actions.mjs (touch, mouse, pen, wheel, click, select, wait), at CSS px of the viewer
//   {"type": "api", "calls": [["setLight", 0.2, 0.1], ["setActiveLayer", "ptm"], …]}  window.lanterna calls, awaited
//   {"type": "waitFor", "selector": "css"}  wait until an element matching it is in the page
//   {"type": "waitForIdleReset"}  wait until the kiosk's idle resets outnumber those of the previous read
//   {"type": "read", "out": "/abs/frame.rgba"}  wait until every tile is drawn, read the frame (RGBA, rows
//       top-down) into `out` and the state into `out + ".json"`: {width, height, state, ui, requests}
//       (`requests`: URLs since the previous read)
//   {"type": "screenshot", "path": "/abs/shot.png"}
// `result`: {ui, state (null unless ready), requests (every URL from the start), routeHits, dialogs (alert,
// confirm… the page opened), consoleErrors, pageErrors}. Exits non-zero on a page error or an unexpected
// console error.
import { readFileSync, writeFileSync } from 'node:fs';
import process from 'node:process';
import { chromium } from 'playwright-core';
import {
  CHROMIUM, CHROMIUM_ARGS, GESTURE_TYPES, installRoutes, readFrame, runGesture, watchErrors,
  withTimeout as timeoutWith,
} from './page-actions.mjs';

const STEPS = [...GESTURE_TYPES, 'api', 'waitFor', 'waitForIdleReset', 'read', 'screenshot'];

class DriveError extends Error {}

/** The viewer's state and what the page shows: every visible control, the note, the error screen. */
function describe(page) {
  return page.evaluate(() => {
    const l = window.lanterna;
    const visible = (el) => {
      const r = el.getBoundingClientRect();
      const style = getComputedStyle(el);
      return r.width > 0 && r.height > 0 && style.visibility !== 'hidden' && style.display !== 'none';
    };
    const rectOf = (el) => {
      const r = el.getBoundingClientRect();
      return [r.left, r.top, r.width, r.height];
    };
    const controls = [...document.querySelectorAll('button, select, input, textarea, [role="slider"], [role="button"], a[href]')]
      .filter(visible).map((el) => ({
        id: el.id, tag: el.tagName.toLowerCase(), text: el.textContent.trim(), pressed: el.getAttribute('aria-pressed'),
        rect: rectOf(el), fontSize: parseFloat(getComputedStyle(el).fontSize), menu: el.closest('nav')?.id ?? null,
      }));
    const dialogs = [...document.querySelectorAll('dialog, [role="dialog"], [role="alertdialog"], [role="alert"]')]
      .filter(visible).map((el) => el.outerHTML.slice(0, 200));
    const text = (id) => {
      const el = document.getElementById(id);
      return el && visible(el) ? el.textContent.trim() : null;
    };
    const state = l && document.body.dataset.state === 'ready' ? (() => {
      const center = l.viewer.viewport.getCenter(true);
      return {
        layer: l.getActiveLayer(), mode: l.getRenderMode(), params: l.getRenderParams(), light: l.getLight(),
        lens: l.getLens(), view: { center: [center.x, center.y], zoom: l.viewer.viewport.getZoom(true) },
        dragMode: l.getMode(), layers: l.getLayers().map((x) => x.id),
      };
    })() : null;
    return {
      state,
      ui: {
        bodyState: document.body.dataset.state ?? null, idleResets: Number(document.body.dataset.idleResets ?? 0),
        controls, dialogs, note: text('note'), unavailable: text('unavailable'), title: text('title'),
        kiosk: document.documentElement.classList.contains('kiosk'),
        userSelect: getComputedStyle(document.body).userSelect,
        viewport: document.querySelector('meta[name="viewport"]')?.content ?? null,
        viewer: rectOf(document.getElementById('viewer')),
        scroll: [document.documentElement.scrollWidth, document.documentElement.clientWidth],
        fullscreen: document.fullscreenElement !== null,
        contextMenuBlocked: !document.body.dispatchEvent(new MouseEvent('contextmenu', { bubbles: true, cancelable: true })),
      },
    };
  });
}

/** The shared timeout, failing with a DriveError. */
const withTimeout = (promise, ms, what) => timeoutWith(promise, ms, what, DriveError);

async function main() {
  const path = process.argv[2];
  if (!path) {
    throw new DriveError('usage: node tests/browser/simple-page.mjs SPEC.json');
  }
  const spec = JSON.parse(readFileSync(path, 'utf8'));
  for (const step of spec.steps ?? []) {
    if (!STEPS.includes(step?.type)) {
      throw new DriveError(`${path}: step type must be one of ${STEPS.join(', ')}, got ${JSON.stringify(step)}`);
    }
  }
  const timeoutMs = spec.timeoutMs ?? 60000;
  const browser = await chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_ARGS, headless: true });
  const pageErrors = [];
  const consoleErrors = [];
  const dialogs = [];
  const allowed = (spec.allowConsoleErrors ?? []).map((p) => new RegExp(p));
  try {
    const touch = spec.touch === true;
    const context = await browser.newContext({
      viewport: { width: spec.viewport?.width ?? 1280, height: spec.viewport?.height ?? 720 }, deviceScaleFactor: 1,
      ...(touch ? { hasTouch: true, isMobile: spec.mobile === true } : {}),
    });
    const page = await context.newPage();
    const cdp = await context.newCDPSession(page);
    const routeHits = await installRoutes(page, spec.routes ?? []);
    const all = [];
    let since = [];
    let idleResets = 0;
    page.on('request', (req) => { all.push(req.url()); since.push(req.url()); });
    page.on('dialog', (d) => { dialogs.push(`${d.type()}: ${d.message()}`); void d.dismiss(); });
    watchErrors(page, allowed, pageErrors, consoleErrors);
    const check = () => {
      if (pageErrors.length > 0) {
        throw new DriveError(pageErrors.join('\n'));
      }
    };
    const url = new URL(spec.url);
    if (!url.searchParams.has('wholeLevelMaxSide')) {
      url.searchParams.set('wholeLevelMaxSide', '0');
    }
    if (!url.searchParams.has('minPixelRatio')) {
      url.searchParams.set('minPixelRatio', '0.75');
    }
    await withTimeout(page.goto(url.href, { waitUntil: 'load' }), timeoutMs, `loading ${url.href}`);
    const expect = spec.expect ?? 'ready';
    await withTimeout(page.waitForSelector(`body[data-state="${expect}"]`, { state: 'attached', timeout: 0 }),
      timeoutMs, `waiting for the page to be ${expect}`);
    check();
    for (const step of spec.steps ?? []) {
      const what = JSON.stringify(step);
      if (GESTURE_TYPES.includes(step.type)) {
        const box = await page.evaluate(() => {
          const r = document.getElementById('viewer').getBoundingClientRect();
          return { x: r.left, y: r.top };
        });
        await withTimeout(runGesture(page, cdp, box, step, touch), timeoutMs, what);
      } else if (step.type === 'api') {
        await withTimeout(page.evaluate(async (calls) => {
          for (const [name, ...args] of calls) {
            await window.lanterna[name](...args);
          }
        }, step.calls), timeoutMs, what);
      } else if (step.type === 'waitFor') {
        await withTimeout(page.waitForSelector(step.selector, { state: 'attached', timeout: 0 }), timeoutMs, what);
      } else if (step.type === 'waitForIdleReset') {
        await withTimeout(page.waitForFunction((n) => Number(document.body.dataset.idleResets ?? 0) > n, idleResets,
          { timeout: 0 }), timeoutMs, what);
      } else if (step.type === 'read') {
        const frame = await withTimeout(readFrame(page), timeoutMs, what);
        const bytes = Buffer.from(frame.base64, 'base64');
        const seen = await describe(page);
        idleResets = seen.ui.idleResets;
        writeFileSync(step.out, bytes);
        writeFileSync(`${step.out}.json`, JSON.stringify({
          width: frame.width, height: frame.height, ...seen, requests: since,
        }));
        since = [];
      } else {
        await withTimeout(page.screenshot({ path: step.path }), timeoutMs, what);
      }
      check();
    }
    if (spec.result) {
      writeFileSync(spec.result, JSON.stringify({
        ...(await describe(page)), requests: all, routeHits, dialogs, consoleErrors, pageErrors,
      }));
    }
    check();
  } finally {
    await browser.close();
  }
}

main().catch((error) => {
  process.stderr.write(`simple-page.mjs: ${error instanceof DriveError ? error.message : (error?.stack ?? String(error))}\n`);
  process.exitCode = 1;
});
