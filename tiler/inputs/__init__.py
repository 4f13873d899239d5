"""Input images and their metadata: 8-bit images, normal/colour/depth maps and spectral bands,
multi-light image stacks read in row bands, camera RAW, light-position (.lp) files."""
