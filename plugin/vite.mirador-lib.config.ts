import { defineConfig } from 'vite';

/**
 * The ESM entry `@lanterna/plugin/mirador` (`dist/lib/lanterna-mirador.js`, next to the main entry,
 * after it is built): Mirador, React and OpenSeadragon stay external; the page's Mirador and React are
 * used, and OpenSeadragon 6 is the plugin's own dependency.
 */
export default defineConfig({
  root: import.meta.dirname,
  build: {
    outDir: 'dist/lib',
    emptyOutDir: false,
    sourcemap: true,
    lib: {
      entry: 'src/mirador/index.ts',
      formats: ['es'],
      fileName: () => 'lanterna-mirador.js',
    },
    rollupOptions: {
      external: [/^openseadragon$/, /^twgl\.js$/, /^mirador(\/.*)?$/, /^react(\/.*)?$/, /^react-dom(\/.*)?$/],
      output: { keepNames: true },
    },
  },
});
