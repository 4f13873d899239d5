/**
 * Sending a patch to the authoring API (docs/serving.md "The authoring API"): `POST …/patches` as
 * multipart (`meta` JSON + `image` PNG) and `PUT …/levels/<L>` for level texts, with the tab's bearer
 * token; `GET …/status` for the rebuild. Failures become one line from the server's `{"error"}`.
 */
import type { PatchRenderState } from '../api/viewer-api';
import { serverError, type LayerAuthoringUrls } from '../panel/authoring-url';
import { parseStatus, type BuildStatus } from './build-status';
import type { PatchFrame } from './patch-frame';

/** The render state a patch was drawn under (the one annotations carry back). */
export type DrawnState = PatchRenderState;

/** The `meta` part of an upload. */
export interface PatchMeta {
  readonly level: number;
  readonly x: number;
  readonly y: number;
  readonly w: number;
  readonly h: number;
  readonly short: string;
  readonly long: string;
  readonly motivation: 'commenting' | 'tagging';
  readonly author: string;
  readonly state: DrawnState | null;
}

/** A request the server refused: its status and one line saying why. */
export class AuthoringRequestError extends Error {
  constructor(readonly status: number, message: string) {
    super(message);
    this.name = 'AuthoringRequestError';
  }
}

const WHAT: Readonly<Record<number, string>> = {
  401: 'the token was not accepted', 403: 'the server does not allow writing (no token configured, or another origin)',
  404: 'the server has no such dataset or layer', 413: 'the patch is too large',
  503: 'the store is busy: try again in a moment',
};

/** The one-line message of a refused request (`what` says what was not done). */
export function refusalText(what: string, status: number, body: string): string {
  return `${what} (${status}): ${serverError(body) || WHAT[status] || `HTTP ${status}`}`;
}

/** The meta of a patch drawn on `frame`. */
export function patchMeta(frame: PatchFrame, texts: Omit<PatchMeta, 'level' | 'x' | 'y' | 'w' | 'h'>): PatchMeta {
  return { level: frame.level, x: frame.x, y: frame.y, w: frame.w, h: frame.h, ...texts };
}

async function send(url: string, init: RequestInit, token: string, what: string): Promise<unknown> {
  const response = await fetch(url, {
    ...init, headers: { ...(init.headers as Record<string, string> | undefined), Authorization: `Bearer ${token}` },
  });
  const body = await response.text();
  if (!response.ok) {
    throw new AuthoringRequestError(response.status, refusalText(what, response.status, body));
  }
  return JSON.parse(body) as unknown;
}

/** `POST` the patch; resolves with the new patch's id (its file stem). */
export async function postPatch(urls: LayerAuthoringUrls, token: string, meta: PatchMeta, png: Blob): Promise<string> {
  const form = new FormData();
  form.append('meta', JSON.stringify(meta));
  form.append('image', png, 'patch.png');
  const doc = await send(urls.patches, { method: 'POST', body: form }, token, 'Not uploaded');
  const patch = (doc as { patch?: { id?: unknown } }).patch;
  return typeof patch?.id === 'string' ? patch.id : '';
}

/** `PUT` the texts of level `level`. */
export async function putLevelTexts(urls: LayerAuthoringUrls, token: string, level: number, short: string,
  long: string): Promise<void> {
  await send(urls.level(level), {
    method: 'PUT', body: JSON.stringify({ short, long }), headers: { 'Content-Type': 'application/json' },
  }, token, 'Level texts not saved');
}

/** The layer's rebuild status. */
export async function readStatus(urls: LayerAuthoringUrls): Promise<BuildStatus> {
  const response = await fetch(urls.status, { headers: { Accept: 'application/json' }, cache: 'no-store' });
  const body = await response.text();
  if (!response.ok) {
    throw new AuthoringRequestError(response.status, refusalText('No status', response.status, body));
  }
  return parseStatus(JSON.parse(body));
}
