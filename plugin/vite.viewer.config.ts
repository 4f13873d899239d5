import { defineConfig } from 'vite';

/**
 * Viewer page build. `base: './'` keeps every asset path relative, so the page works when served
 * at `/viewer/` by `lanterna serve` and from any static host.
 */
export default defineConfig({
  root: import.meta.dirname,
  base: './',
  build: {
    outDir: 'dist/viewer',
    emptyOutDir: true,
    sourcemap: true,
    chunkSizeWarningLimit: 1024,
    // Error classes name themselves from `new.target.name`: keep class names through minification.
    rollupOptions: { output: { keepNames: true } },
  },
});
