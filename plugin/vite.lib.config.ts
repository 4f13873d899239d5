import { defineConfig } from 'vite';

/** Library build: ESM bundle of the plugin; openseadragon and twgl.js stay external peers. */
export default defineConfig({
  root: import.meta.dirname,
  build: {
    outDir: 'dist/lib',
    emptyOutDir: true,
    sourcemap: true,
    lib: {
      entry: 'src/index.ts',
      formats: ['es'],
      fileName: () => 'lanterna.js',
    },
    rollupOptions: {
      external: ['openseadragon', 'twgl.js'],
      // Error classes name themselves from `new.target.name`: keep class names through minification.
      output: { keepNames: true },
    },
  },
});
