/**
 * The plugin's module structure, read from the import statements of every `plugin/src/**` file:
 * no import circles, each folder imports only the folders below it (the table here), the pure
 * folders touch no DOM and no WebGL, and only the drawer touches OpenSeadragon's drawer internals.
 */
import { readdirSync, readFileSync, statSync } from 'node:fs';
import { dirname, join, relative, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { describe, expect, it } from 'vitest';

const SRC = resolve(dirname(fileURLToPath(import.meta.url)), '../../plugin/src');

/**
 * What each part of `src/` may import (besides itself). A part is a folder of `src/`, or a file at
 * its top (`errors`, `index`). Read top to bottom, each part is built only on parts above it.
 */
const ALLOWED: Readonly<Record<string, readonly string[]>> = {
  errors: [],
  math: [],
  iiif: ['errors', 'math'],
  render: [],
  gl: ['errors', 'render'],
  layers: ['errors', 'math', 'iiif', 'render', 'gl'],
  tiles: ['errors', 'iiif'],
  lens: ['errors', 'math', 'render'],
  presets: ['errors', 'render'],
  state: ['errors', 'render', 'lens'],
  ui: ['errors', 'math'],
  // the individual annotations: patch lists, hidden patches and the overlay's draw plan
  annotations: ['errors', 'iiif'],
  // overlay-state sanitises the hypertext with ui/sanitize-html (a pure function).
  overlay: ['errors', 'iiif', 'tiles', 'ui', 'annotations'],
  drawer: ['errors', 'math', 'iiif', 'render', 'gl', 'layers', 'tiles', 'lens'],
  api: ['errors', 'math', 'iiif', 'render', 'lens', 'overlay', 'ui', 'drawer', 'presets', 'state'],
  panel: ['errors', 'math', 'iiif', 'render', 'lens', 'overlay', 'ui', 'api', 'presets'],
  viewer: ['errors', 'math', 'iiif', 'render', 'layers', 'tiles', 'lens', 'overlay', 'ui', 'drawer', 'api', 'panel',
    'presets', 'state', 'annotations'],
  // the measurement mode reads a viewer's planes through its public API
  measure: ['errors', 'math', 'iiif', 'tiles', 'ui', 'api'],
  // The page's view tools (URL hash, snapshot button, scale bar, help, keys), on the viewer API.
  tools: ['errors', 'math', 'render', 'lens', 'state', 'api'],
  // The Annotate toolbox: the patch frame, strokes and uploads, on the viewer API and the panel's authoring URLs/token.
  annotate: ['errors', 'api', 'panel'],
  // attachLanterna: createViewer's wiring on a page's own OpenSeadragon viewer, and its example page.
  embed: ['errors', 'tiles', 'overlay', 'drawer', 'api', 'viewer'],
  index: ['errors', 'math', 'iiif', 'render', 'gl', 'layers', 'tiles', 'lens', 'ui', 'overlay', 'drawer', 'api',
    'panel', 'viewer', 'presets', 'state', 'measure', 'tools', 'annotations', 'annotate', 'embed'],
  demo: ['index'],
  simple: ['index'],
  // The Mirador 4 plugins (a separate entry, `@lanterna/plugin/mirador`): our viewer and its API in a Mirador window.
  mirador: ['errors', 'math', 'iiif', 'render', 'lens', 'ui', 'overlay', 'api', 'panel', 'viewer', 'presets', 'state',
    'annotations', 'index'],
};

/** The packages a part may import. */
const PACKAGES: Readonly<Record<string, readonly string[]>> = {
  openseadragon: ['tiles', 'lens', 'overlay', 'ui', 'drawer', 'api', 'viewer', 'measure', 'tools', 'embed'],
  'twgl.js': ['gl', 'layers', 'drawer'],
  mirador: ['mirador'],
  react: ['mirador'],
};

/** Parts that are pure: no DOM, no GL (they run, and are tested, in Node). */
const PURE = ['errors', 'math', 'iiif', 'render', 'presets', 'state', 'annotations'];
/** Pure files in folders that also hold DOM code. */
const PURE_FILES = ['annotate/patch-frame.ts', 'annotate/patch-name.ts', 'annotate/stroke-history.ts',
  'annotate/pen-width.ts', 'annotate/build-status.ts', 'embed/host-check.ts', 'embed/host-drawer.ts'];
const DOM_OR_GL = new RegExp('\\b(document|window|navigator|requestAnimationFrame|createImageBitmap|OffscreenCanvas'
  + '|HTML\\w*Element|WebGL\\w*)\\b');

/** OpenSeadragon drawer internals: only `drawer/` may use them. */
const OSD_INTERNALS = new RegExp('\\b(DrawerBase|internalCacheCreate|internalCacheFree|getDataToDraw'
  + '|_createDrawingElement|setInternalCacheNeedsRefresh|destroyInternalCache)\\b');

/** Source text without comments (string and template literals are kept as they are). */
function stripComments(source: string): string {
  return source.replace(/('(?:\\.|[^'\\\n])*'|"(?:\\.|[^"\\\n])*"|`(?:\\.|[^`\\])*`)|\/\*[\s\S]*?\*\/|\/\/[^\n]*/g,
    (whole, literal: string | undefined) => literal ?? (whole.startsWith('/*') ? whole.replace(/[^\n]/g, ' ') : ''));
}

/** The module specifiers a file imports or re-exports (static, side-effect and dynamic imports). */
function importSpecifiers(source: string): string[] {
  const code = stripComments(source);
  const out: string[] = [];
  for (const re of [/\bfrom\s*'([^']+)'/g, /^\s*import\s*'([^']+)'/gm, /\bimport\(\s*'([^']+)'\s*\)/g]) {
    for (const m of code.matchAll(re)) {
      out.push(m[1] ?? '');
    }
  }
  return out;
}

/** The file-level cycles of a graph: strongly connected components of two or more files, or a self-import. */
function findCycles(graph: ReadonlyMap<string, readonly string[]>): string[][] {
  let index = 0;
  const indices = new Map<string, number>();
  const low = new Map<string, number>();
  const stack: string[] = [];
  const onStack = new Set<string>();
  const cycles: string[][] = [];
  const visit = (v: string): void => {
    indices.set(v, index);
    low.set(v, index);
    index++;
    stack.push(v);
    onStack.add(v);
    for (const w of graph.get(v) ?? []) {
      if (!indices.has(w)) {
        visit(w);
        low.set(v, Math.min(low.get(v) ?? 0, low.get(w) ?? 0));
      } else if (onStack.has(w)) {
        low.set(v, Math.min(low.get(v) ?? 0, indices.get(w) ?? 0));
      }
    }
    if (low.get(v) === indices.get(v)) {
      const component: string[] = [];
      let w: string | undefined;
      do {
        w = stack.pop();
        if (w !== undefined) {
          onStack.delete(w);
          component.push(w);
        }
      } while (w !== undefined && w !== v);
      if (component.length > 1 || (graph.get(v) ?? []).includes(v)) {
        cycles.push(component.sort());
      }
    }
  };
  for (const v of graph.keys()) {
    if (!indices.has(v)) {
      visit(v);
    }
  }
  return cycles;
}

/** The part of `src/` a file belongs to: its top folder, or its name for a file at the top. */
function partOf(file: string): string {
  const [head = '', ...rest] = file.split('/');
  return rest.length > 0 ? head : head.replace(/\.ts$/, '');
}

/** Imports of one part by another that the table does not allow, as `from -> to (file)`. */
function tierViolations(graph: ReadonlyMap<string, readonly string[]>,
  allowed: Readonly<Record<string, readonly string[]>>): string[] {
  const out: string[] = [];
  for (const [file, targets] of graph) {
    const from = partOf(file);
    for (const target of targets) {
      const to = partOf(target);
      if (to !== from && !(allowed[from] ?? []).includes(to)) {
        out.push(`${from} -> ${to} (${file} imports ${target})`);
      }
    }
  }
  return out;
}

function sourceFiles(dir: string): string[] {
  return readdirSync(dir).flatMap((name) => {
    const path = join(dir, name);
    return statSync(path).isDirectory() ? sourceFiles(path) : name.endsWith('.ts') ? [path] : [];
  });
}

/** Every source file (relative to `src/`), its text, local imports (files) and package imports. */
function readTree(): { sources: Map<string, string>; graph: Map<string, string[]>; packages: Map<string, string[]> } {
  const sources = new Map<string, string>();
  const graph = new Map<string, string[]>();
  const packages = new Map<string, string[]>();
  for (const path of sourceFiles(SRC)) {
    const file = relative(SRC, path).split('\\').join('/');
    const text = readFileSync(path, 'utf8');
    sources.set(file, text);
    const local: string[] = [];
    const external: string[] = [];
    for (const spec of importSpecifiers(text)) {
      if (!spec.startsWith('.')) {
        external.push(spec);
        continue;
      }
      const base = resolve(dirname(path), spec);
      const target = [`${base}.ts`, join(base, 'index.ts'), base].find((p) => {
        try {
          return statSync(p).isFile();
        } catch {
          return false;
        }
      });
      local.push(target ? relative(SRC, target).split('\\').join('/') : `UNRESOLVED:${spec}`);
    }
    graph.set(file, local);
    packages.set(file, external);
  }
  return { sources, graph, packages };
}

describe('the checks themselves', () => {
  it('finds import circles, and only circles', () => {
    const graph = new Map([['a.ts', ['b.ts']], ['b.ts', ['c.ts']], ['c.ts', ['a.ts']], ['d.ts', ['a.ts', 'd.ts']],
      ['e.ts', ['a.ts']]]);
    expect(findCycles(graph)).toEqual([['a.ts', 'b.ts', 'c.ts'], ['d.ts']]);
    expect(findCycles(new Map([['a.ts', ['b.ts']], ['b.ts', []]]))).toEqual([]);
  });

  it('reports an import the tier table does not allow', () => {
    const graph = new Map([['ui/widget.ts', ['drawer/relight-drawer.ts', 'math/light.ts', 'ui/other.ts']]]);
    expect(tierViolations(graph, ALLOWED)).toEqual(['ui -> drawer (ui/widget.ts imports drawer/relight-drawer.ts)']);
    expect(tierViolations(new Map([['errors.ts', ['index.ts']]]), ALLOWED)).toHaveLength(1);
  });

  it('reads imports and re-exports, but not comments', () => {
    const source = `import { a } from './a';\nimport type {\n  B,\n} from "../b";\nexport { c } from './c';\n`
      + `import './side-effect';\n// import { x } from './commented';\n/* import { y } from './y'; */\n`
      + `const z = await import('./dynamic');\nconst url = 'http://host/path';\n`;
    expect(importSpecifiers(source.replace('"../b"', "'../b'")))
      .toEqual(['./a', '../b', './c', './side-effect', './dynamic']);
    expect(DOM_OR_GL.test(stripComments('// the document is parsed\nconst n = 1;'))).toBe(false);
    expect(DOM_OR_GL.test(stripComments('const c = document.createElement("canvas");'))).toBe(true);
  });
});

describe('plugin/src structure', () => {
  const { sources, graph, packages } = readTree();

  it('resolves every local import to a file', () => {
    expect(sources.size).toBeGreaterThan(50);
    const unresolved = [...graph].flatMap(([file, targets]) => targets.filter((t) => t.startsWith('UNRESOLVED:'))
      .map((t) => `${file}: ${t}`));
    expect(unresolved).toEqual([]);
  });

  it('has no import circles', () => {
    expect(findCycles(graph)).toEqual([]);
  });

  it('imports only downward, as the tier table says', () => {
    const unknown = [...new Set([...graph.keys()].map(partOf))].filter((p) => !(p in ALLOWED));
    expect(unknown).toEqual([]);
    expect(tierViolations(graph, ALLOWED)).toEqual([]);
  });

  it('uses each package only where the table allows it', () => {
    const bad = [...packages].flatMap(([file, specs]) => specs
      .filter((spec) => !(PACKAGES[spec] ?? []).includes(partOf(file)))
      .map((spec) => `${file} imports ${spec}`));
    expect(bad).toEqual([]);
  });

  it('keeps the pure folders free of the DOM and WebGL', () => {
    expect(PURE_FILES.filter((f) => !sources.has(f))).toEqual([]);
    const bad = [...sources].filter(([file]) => PURE.includes(partOf(file)) || PURE_FILES.includes(file))
      .filter(([, text]) => DOM_OR_GL.test(stripComments(text)))
      .map(([file, text]) => `${file}: ${DOM_OR_GL.exec(stripComments(text))?.[0]}`);
    expect(bad).toEqual([]);
  });

  it('leaves OpenSeadragon drawer internals to the drawer', () => {
    const users = [...sources].filter(([, text]) => OSD_INTERNALS.test(stripComments(text))).map(([file]) => file);
    expect(users.length).toBeGreaterThan(0);
    expect(users.filter((file) => partOf(file) !== 'drawer')).toEqual([]);
  });
});

/** Lines per `.ts` file, by folder, of `plugin/src/` and of these tests. */
function linesByFolder(): Map<string, number[]> {
  const folders = new Map<string, number[]>();
  for (const root of [SRC, resolve(SRC, '../../tests/plugin')]) {
    for (const path of sourceFiles(root)) {
      const folder = relative(resolve(SRC, '../..'), dirname(path));
      const lines = readFileSync(path, 'utf8').split('\n').length - 1;
      folders.set(folder, [...(folders.get(folder) ?? []), lines]);
    }
  }
  return folders;
}

function median(values: readonly number[]): number {
  const sorted = [...values].sort((a, b) => a - b);
  const mid = sorted.length >> 1;
  return sorted.length % 2 ? (sorted[mid] ?? 0) : ((sorted[mid - 1] ?? 0) + (sorted[mid] ?? 0)) / 2;
}

describe('file sizes (one concept per file)', () => {
  const folders = linesByFolder();

  it('reads the source and test folders', () => {
    expect(folders.size).toBeGreaterThan(15);
    expect(median([3, 1, 2])).toBe(2);
    expect(median([4, 1, 2, 3])).toBe(2.5);
  });

  it('keeps every file within 450 lines and every folder\'s median within 200', () => {
    const tooLong = [...folders].flatMap(([folder, sizes]) => sizes.filter((n) => n > 450).map((n) => `${folder}: ${n}`));
    expect(tooLong).toEqual([]);
    const heavy = [...folders].filter(([, sizes]) => median(sizes) > 200).map(([folder, sizes]) => `${folder}: ${median(sizes)}`);
    expect(heavy).toEqual([]);
  });
});
