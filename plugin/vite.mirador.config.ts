import { copyFileSync, mkdirSync } from 'node:fs';
import { resolve } from 'node:path';
import { defineConfig, type Plugin } from 'vite';

const here = import.meta.dirname;

/**
 * After the bundle is written: the Mirador page (`mirador.html`) and a copy of the bundle go into the
 * viewer build (`dist/viewer`, which the wheel carries and `lanterna serve` serves at `/viewer/`), so
 * that `/viewer/mirador.html?manifest=…` works. Run after `build:viewer`, which empties that folder.
 */
function miradorPage(): Plugin {
  return {
    name: 'lanterna-mirador-page',
    writeBundle() {
      const viewer = resolve(here, 'dist/viewer');
      mkdirSync(resolve(viewer, 'mirador'), { recursive: true });
      copyFileSync(resolve(here, 'dist/mirador/lanterna-mirador.js'), resolve(viewer, 'mirador/lanterna-mirador.js'));
      copyFileSync(resolve(here, 'mirador.html'), resolve(viewer, 'mirador.html'));
    },
  };
}

/**
 * The ready Mirador bundle (docs/mirador.md): Mirador 4, React, the Lanterna plugins and
 * OpenSeadragon 6 in one classic script, `dist/mirador/lanterna-mirador.js`, that defines
 * `window.Mirador` (Mirador's exports plus `lanternaPlugins`). Mirador keeps its own OpenSeadragon
 * (5) for the canvases Lanterna does not relight.
 */
export default defineConfig({
  root: here,
  define: { 'process.env.NODE_ENV': JSON.stringify('production') },
  plugins: [miradorPage()],
  build: {
    outDir: 'dist/mirador',
    emptyOutDir: true,
    sourcemap: false,
    minify: true,
    chunkSizeWarningLimit: 4096,
    lib: {
      entry: 'src/mirador/bundle.ts',
      formats: ['iife'],
      name: 'LanternaMiradorBundle',
      fileName: () => 'lanterna-mirador.js',
    },
    rollupOptions: {
      // MUI's "use client" directives mean nothing in a bundle: not worth a warning each.
      onwarn(warning, warn) {
        if (warning.code !== 'MODULE_LEVEL_DIRECTIVE') {
          warn(warning);
        }
      },
      // Error classes name themselves from `new.target.name`: keep class names through minification.
      output: { keepNames: true },
    },
  },
});
