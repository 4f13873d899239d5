import { resolve } from 'node:path';
import { defineConfig } from 'vite';

/**
 * Viewer pages build: the advanced viewer (`index.html`) and the simplified, preset-driven viewer
 * (`simple.html`, docs/simple-viewer.md), sharing one chunk of the plugin. `base: './'` keeps every
 * asset path relative, so the pages work when served at `/viewer/` by `lanterna serve` and from any
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
      },
      // Error classes name themselves from `new.target.name`: keep class names through minification.
      output: { keepNames: true },
    },
  },
});
