/**
 * Mirador ships no types: its module is declared untyped here, and `mirador-parts.ts` types the
 * few exports we use.
 */
declare module 'mirador';
