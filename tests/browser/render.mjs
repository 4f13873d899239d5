#!/usr/bin/env node
// Render shots of the Lanterna viewer page in headless Chromium and save the read-back pixels.
//
//   node tests/browser/render.mjs SPEC.json
//
// SPEC = {"url": "…/viewer/?manifest=…", "viewport": {"width": 640, "height": 480},
//         "shots": [{"light": [lu, lv], "region": [x, y, w, h], "out": "/abs/shot.rgba",
//                    "layer": "ptm", "mode": "specular", "params": {"specExponent": 40}}],
//         "screenshot": "/abs/optional.png", "timeoutMs": 60000}
//
// For each shot: switch to `layer` (a layer id), set the render `mode`, and set the render
// parameters to the defaults overridden by `params` (each optional: when absent the current layer,
// mode and parameters stay), show or hide the annotation `overlays` (optional bool), then set the light,
// fit the image-pixel region to the viewport, apply `lens` (optional, the argument of setLens), run the
// optional synthetic input `gestures`, wait until every tile is loaded and drawn, read the frame back
// (RGBA, rows top-down) and write the raw bytes to `out` and {width, height, overlayState, lens,
// light, view: {center, zoom}, hypertext, requests} to `out + ".json"` (`hypertext`: the widget's
// short line; `requests`: the URLs the page requested during the shot). One JSON line per shot goes to stdout. Exits non-zero on a page error, a console
// error, or a step taking longer than timeoutMs (default 60 s).
//
// The page is opened with `wholeLevelMaxSide=0` (every image by its tiles, so pixel tests compare
// against the tile files) unless the URL sets that parameter itself.
// More spec keys (all optional):
//   "routes": [{"match": "regex", "status": 404} | {"match": …, "hang": true} | {"match": …, "abort": "failed"}]
//       answer matching requests with a fault instead of the server (see page-actions.mjs)
//   "allowConsoleErrors": ["regex", …]  console errors matching one of these do not fail the run
//   "expectReady": "reject"  the page is expected not to open the dataset: no shots; the error box is read
//   "result": "/abs/result.json"  {readyError, errorBox, notices, routeHits, consoleErrors, pageErrors,
//       requests: every URL the page requested, from its opening on}
//   "mobile": true  a phone-like context (hasTouch, isMobile)
//   "tileTimeoutMs": 3000  OpenSeadragon's tile time limit from then on (viewer.imageLoader.timeout)
//   "launchArgs": ["--flag", …]  extra Chromium flags
//   "minPixelRatio": 0.75  OpenSeadragon's minPixelRatio, passed to the page as ?minPixelRatio= (a
//       test-only knob: 0.75 unless given, so that a zoom of 1/2 shows exactly the next coarser level;
//       null: the page's own full detail)
// More shot keys: "home": true (go to the home view instead of fitting a region; "region" may then be
// left out), "contextLoss": true (after the frame is read: lose the WebGL context, check the
// page while lost, restore it, wait until loaded and read the frame again into `out + ".restored"`),
// "screenshot" (a PNG after the shot), "lostScreenshot" (a PNG while the context is lost), "read"
// (CSS selectors of form controls whose values go to the shot's JSON as `values`). The shot's
// JSON also holds `notices` (the notice box: visible, rect, texts, and lanterna.getNotices()),
// `routeHits` (requests caught by each route so far), `frames` (since the page opened: animation frames
// `ticks`, relit frames `rendered` (the drawer's getFrameCount) and `maxPerTick`, the most relit frames
// between two animation frames) and, with contextLoss, `noticesWhileLost`.
//
// Gesture steps: see page-actions.mjs (touch, mouse, pen, wheel, click, wait).
import { readFileSync, writeFileSync } from 'node:fs';
import process from 'node:process';
import { chromium } from 'playwright-core';
import {
  CHROMIUM, CHROMIUM_ARGS, GESTURE_TYPES, installRoutes, loseAndRestoreContext, readNotices, runGesture,
  watchErrors, withTimeout as timeoutWith,
} from './page-actions.mjs';


class RenderError extends Error {}

function fail(message) {
  process.stderr.write(`render.mjs: ${message}\n`);
  process.exitCode = 1;
}

function readSpec(path) {
  if (!path) {
    throw new RenderError('usage: node tests/browser/render.mjs SPEC.json');
  }
  const spec = JSON.parse(readFileSync(path, 'utf8'));
  if (typeof spec.url !== 'string' || !Array.isArray(spec.shots)) {
    throw new RenderError(`${path}: needs "url" and "shots"`);
  }
  for (const [i, s] of spec.shots.entries()) {
    if (!Array.isArray(s.light) || s.light.length !== 2 || typeof s.out !== 'string'
      || (s.home !== true && (!Array.isArray(s.region) || s.region.length !== 4))) {
      throw new RenderError(`${path}: shot ${i} needs light [lu, lv], region [x, y, w, h] and out`);
    }
    if ((s.layer !== undefined && typeof s.layer !== 'string') || (s.mode !== undefined && typeof s.mode !== 'string')
      || (s.params !== undefined && (typeof s.params !== 'object' || s.params === null || Array.isArray(s.params)))) {
      throw new RenderError(`${path}: shot ${i}: layer and mode must be strings, params an object`);
    }
    if ((s.overlays !== undefined && typeof s.overlays !== 'boolean')
      || (s.lens !== undefined && (typeof s.lens !== 'object' || s.lens === null || Array.isArray(s.lens)))
      || (s.gestures !== undefined && !Array.isArray(s.gestures))) {
      throw new RenderError(`${path}: shot ${i}: overlays must be a boolean, lens an object, gestures a list`);
    }
    for (const g of s.gestures ?? []) {
      if (!GESTURE_TYPES.includes(g?.type)) {
        throw new RenderError(`${path}: shot ${i}: gesture type must be one of ${GESTURE_TYPES.join(', ')}, `
          + `got ${JSON.stringify(g)}`);
      }
    }
  }
  for (const r of spec.routes ?? []) {
    if (typeof r?.match !== 'string') {
      throw new RenderError(`${path}: every route needs a "match" regex, got ${JSON.stringify(r)}`);
    }
  }
  return spec;
}

/** Reject after `ms` with a clear message, unless `promise` settles first. */
/** The shared timeout, failing with a RenderError. */
const withTimeout = (promise, ms, what) => timeoutWith(promise, ms, what, RenderError);

/** Wait until every tile is loaded and drawn, then read the frame back (and the viewer's state). */
function readFrame(page) {
  return page.evaluate(async () => {
    const l = window.lanterna;
    await l.whenFullyLoaded();
    const { width, height, data } = l.readPixels();
    let binary = '';
    const chunk = 0x8000;
    for (let i = 0; i < data.length; i += chunk) {
      binary += String.fromCharCode.apply(null, data.subarray(i, i + chunk));
    }
    const center = l.viewer.viewport.getCenter(true);
    return {
      width, height, base64: btoa(binary), layer: l.getActiveLayer(), mode: l.getRenderMode(),
      overlayState: l.getOverlayState?.() ?? null, lens: l.getLens?.() ?? null, light: l.getLight(),
      view: { center: [center.x, center.y], zoom: l.viewer.viewport.getZoom(true) },
      hypertext: document.querySelector('.lanterna-hypertext-short')?.textContent ?? null,
      frames: { ...window.__lanternaFrames },
    };
  });
}

/** A frame's RGBA bytes, checked against its size. */
function frameBytes(frame, what) {
  const bytes = Buffer.from(frame.base64, 'base64');
  if (bytes.length !== frame.width * frame.height * 4) {
    throw new RenderError(`shot ${what}: got ${bytes.length} bytes for ${frame.width}×${frame.height}`);
  }
  return bytes;
}

/** Wait for the page's error box; returns it and, if the viewer was made, how `ready` rejected. */
async function readOpenError(page) {
  await page.waitForFunction(() => {
    const box = document.getElementById('error');
    return box !== null && !box.hidden;
  });
  return page.evaluate(async () => {
    const box = document.getElementById('error');
    const readyError = window.lanterna
      ? await window.lanterna.ready.then(() => null, (e) => ({ name: e?.name, message: e?.message }))
      : null;
    const text = (sel) => box.querySelector(sel)?.textContent ?? null;
    const r = box.getBoundingClientRect();
    return {
      readyError,
      errorBox: {
        visible: !box.hidden && r.width > 0 && r.height > 0, text: box.textContent,
        title: text('h2'), problem: text('.problem'), url: text('.url code'), hint: text('.hint'),
        rect: [r.left, r.top, r.width, r.height], scrollWidth: box.scrollWidth, clientWidth: box.clientWidth,
      },
    };
  });
}

async function main() {
  const spec = readSpec(process.argv[2]);
  const timeoutMs = spec.timeoutMs ?? 60000;
  const viewport = { width: spec.viewport?.width ?? 640, height: spec.viewport?.height ?? 480 };
  const browser = await chromium.launch({
    executablePath: CHROMIUM, args: [...CHROMIUM_ARGS, ...(spec.launchArgs ?? [])], headless: true,
  });
  const pageErrors = [];
  const consoleErrors = [];
  const allowed = (spec.allowConsoleErrors ?? []).map((p) => new RegExp(p));
  let failure = null;
  try {
    const uses = (type) => spec.shots.some((s) => (s.gestures ?? []).some((g) => g.type === type));
    const touch = uses('touch') || spec.mobile === true;
    const context = await browser.newContext({
      viewport, deviceScaleFactor: 1, ...(touch ? { hasTouch: true } : {}), ...(spec.mobile ? { isMobile: true } : {}),
    });
    const page = await context.newPage();
    const cdp = touch || uses('pen') ? await context.newCDPSession(page) : null;
    const routeHits = await installRoutes(page, spec.routes ?? []);
    let requests = [];
    const allRequests = [];
    page.on('request', (req) => { requests.push(req.url()); allRequests.push(req.url()); });
    watchErrors(page, allowed, pageErrors, consoleErrors);
    const check = () => {
      if (pageErrors.length > 0) {
        throw new RenderError(pageErrors.join('\n'));
      }
    };
    const writeResult = async (extra) => {
      if (spec.result) {
        writeFileSync(spec.result, JSON.stringify({
          ...extra, notices: await readNotices(page), routeHits, consoleErrors, pageErrors, requests: allRequests,
        }));
      }
    };
    // Count animation frames and the drawer's relit frames between them, from the page's start.
    await page.addInitScript(() => {
      const counts = { ticks: 0, rendered: 0, maxPerTick: 0 };
      window.__lanternaFrames = counts;
      const tick = () => {
        const rendered = window.lanterna?.viewer?.drawer?.getFrameCount?.() ?? 0;
        counts.maxPerTick = Math.max(counts.maxPerTick, rendered - counts.rendered);
        counts.rendered = rendered;
        counts.ticks++;
        requestAnimationFrame(tick);
      };
      requestAnimationFrame(tick);
    });
    const minPixelRatio = spec.minPixelRatio === undefined ? 0.75 : spec.minPixelRatio;
    const extra = [];
    if (minPixelRatio !== null) {
      extra.push(`minPixelRatio=${minPixelRatio}`);
    }
    if (!new URL(spec.url).searchParams.has('wholeLevelMaxSide')) {
      extra.push('wholeLevelMaxSide=0');
    }
    const url = extra.length === 0 ? spec.url : `${spec.url}${spec.url.includes('?') ? '&' : '?'}${extra.join('&')}`;
    await withTimeout(page.goto(url, { waitUntil: 'load' }), timeoutMs, `loading ${url}`);
    if (spec.expectReady === 'reject') {
      const opened = await withTimeout(readOpenError(page), timeoutMs, 'waiting for the error message');
      // Give late errors (unhandled rejections, errors in handlers) a moment to show up.
      await page.waitForTimeout(300);
      if (spec.screenshot) {
        await page.screenshot({ path: spec.screenshot });
      }
      await writeResult(opened);
      check();
      return;
    }
    await withTimeout(page.waitForFunction(() => window.lanterna !== undefined), timeoutMs,
      'waiting for window.lanterna');
    await withTimeout(page.evaluate(() => window.lanterna.ready), timeoutMs, 'waiting for lanterna.ready');
    if (spec.tileTimeoutMs !== undefined) {
      await page.evaluate((ms) => { window.lanterna.viewer.imageLoader.timeout = ms; }, spec.tileTimeoutMs);
    }
    check();
    for (const shot of spec.shots) {
      requests = [];
      await withTimeout(page.evaluate(async ({ light, region, home, layer, mode, params, overlays, lens }) => {
        const l = window.lanterna;
        if (layer !== undefined) {
          await l.setActiveLayer(layer);
        }
        if (mode !== undefined) {
          l.setRenderMode(mode);
        }
        if (params !== undefined) {
          l.resetRenderParams();
          l.setRenderParams(params);
        }
        if (overlays !== undefined) {
          l.setOverlaysVisible(overlays);
        }
        l.setLight(light[0], light[1]);
        if (home === true) {
          l.viewer.viewport.goHome(true);
        } else {
          l.showImageRegion(region[0], region[1], region[2], region[3]);
        }
        if (lens !== undefined) {
          await l.setLens(lens);
        }
      }, shot), timeoutMs, `shot setup ${JSON.stringify(shot)}`);
      check();
      if (shot.gestures?.length) {
        await withTimeout(page.evaluate(() => window.lanterna.whenFullyLoaded()), timeoutMs, 'loading before gestures');
        const box = await page.evaluate(() => {
          const r = window.lanterna.viewer.element.getBoundingClientRect();
          return { x: r.left, y: r.top };
        });
        for (const g of shot.gestures) {
          await withTimeout(runGesture(page, cdp, box, g, touch), timeoutMs, `gesture ${JSON.stringify(g)}`);
        }
        check();
      }
      const result = await withTimeout(readFrame(page), timeoutMs, `shot ${JSON.stringify(shot)}`);
      check();
      const extra = {};
      if (shot.contextLoss) {
        extra.noticesWhileLost = await withTimeout(loseAndRestoreContext(page, shot.lostScreenshot), timeoutMs,
          'losing and restoring the WebGL context');
        const restored = await withTimeout(readFrame(page), timeoutMs, 'the frame after the restoration');
        check();
        writeFileSync(`${shot.out}.restored`, frameBytes(restored, shot.out));
      }
      writeFileSync(shot.out, frameBytes(result, shot.out));
      const notices = await readNotices(page);
      const values = await page.evaluate((selectors) => Object.fromEntries(selectors.map((sel) => [
        sel, document.querySelector(sel)?.value ?? null])), shot.read ?? []);
      if (shot.screenshot) {
        await withTimeout(page.screenshot({ path: shot.screenshot }), timeoutMs, 'screenshot');
      }
      writeFileSync(`${shot.out}.json`, JSON.stringify({
        width: result.width, height: result.height, overlayState: result.overlayState, lens: result.lens,
        light: result.light, view: result.view, hypertext: result.hypertext, requests, notices,
        routeHits: [...routeHits], values, frames: result.frames, ...extra,
      }));
      process.stdout.write(`${JSON.stringify({
        out: shot.out, width: result.width, height: result.height, light: shot.light, region: shot.region,
        layer: result.layer, mode: result.mode,
      })}\n`);
    }
    if (spec.screenshot) {
      await withTimeout(page.screenshot({ path: spec.screenshot }), timeoutMs, 'screenshot');
    }
    await writeResult({});
    check();
  } catch (error) {
    failure = error;
  } finally {
    await browser.close();
  }
  if (failure) {
    throw failure;
  }
}

main().catch((error) => {
  fail(error instanceof RenderError ? error.message : (error?.stack ?? String(error)));
});
