import { resolve } from 'node:path';
import { defineConfig } from 'vite';

/**
 * Viewer pages build: the advanced viewer (`index.html`), the simplified, preset-driven viewer
 * (`simple.html`, docs/simple-viewer.md) and the embedding example (`embed.html`: a page's own
 * OpenSeadragon viewer given to `attachLanterna`, docs/embedding.md), sharing one chunk of the
 * plugin. `base: './'` keeps every asset path relative, so the pages work when served at `/viewer/` by `lanterna serve` and from any
 * static host.
 */
export default defineConfig({
  root: import.meta.dirname,
  base: './',
  build: {
    outDir: 'dist/viewer',
    emptyOutDir: true,
    sourcemap: true,
    chunkSizeWarningLimit: 1024,
    rollupOptions: {
      input: {
        index: resolve(import.meta.dirname, 'index.html'),
        simple: resolve(import.meta.dirname, 'simple.html'),
        embed: resolve(import.meta.dirname, 'embed.html'),
      },
      // Error classes name themselves from `new.target.name`: keep class names through minification.
      output: { keepNames: true },
    },
  },
});
