"""A dataset folder: the atomic writer, adding layers of every type, layer plans checked before
anything is written, and the static export."""
