/**
 * The viewer's individual annotations: per layer, its patches (`PatchAnnotation`s read from its
 * annotation page) and which of them are hidden. Pure state: no DOM, no OpenSeadragon.
 */
import { applicationOrder, type PatchAnnotation } from '../iiif/annotation-page';

const NONE: ReadonlySet<string> = new Set();

/** Patches and hidden ids, per layer. */
export class AnnotationSet {
  #patches = new Map<string, readonly PatchAnnotation[]>();
  readonly #hidden = new Map<string, Set<string>>();

  /**
   * Replace every layer's patches (e.g. after a rebuild). A hidden patch that is still there stays
   * hidden; the ids of patches that are gone are forgotten.
   */
  replace(patches: readonly PatchAnnotation[]): void {
    const byLayer = new Map<string, PatchAnnotation[]>();
    for (const p of patches) {
      const list = byLayer.get(p.layer) ?? [];
      list.push(p);
      byLayer.set(p.layer, list);
    }
    this.#patches = new Map([...byLayer].map(([layer, list]) => [layer, list.sort(applicationOrder)]));
    for (const [layer, hidden] of this.#hidden) {
      const ids = new Set((this.#patches.get(layer) ?? []).map((p) => p.id));
      for (const id of hidden) {
        if (!ids.has(id)) {
          hidden.delete(id);
        }
      }
    }
  }

  /** A layer's patches, in application order. */
  list(layer: string): readonly PatchAnnotation[] {
    return this.#patches.get(layer) ?? [];
  }

  /** The patch with this id: of `preferred` layer if it has one, else of the first layer that does. */
  find(id: string, preferred: string): PatchAnnotation | undefined {
    const own = this.list(preferred).find((p) => p.id === id);
    if (own) {
      return own;
    }
    for (const list of this.#patches.values()) {
      const found = list.find((p) => p.id === id);
      if (found) {
        return found;
      }
    }
    return undefined;
  }

  /** Hide or show a patch; true when that changed anything. */
  setHidden(patch: PatchAnnotation, hidden: boolean): boolean {
    let set = this.#hidden.get(patch.layer);
    if (!set) {
      set = new Set();
      this.#hidden.set(patch.layer, set);
    }
    if (set.has(patch.id) === hidden) {
      return false;
    }
    if (hidden) {
      set.add(patch.id);
    } else {
      set.delete(patch.id);
    }
    return true;
  }

  /** The ids of a layer's hidden patches. */
  hidden(layer: string): ReadonlySet<string> {
    return this.#hidden.get(layer) ?? NONE;
  }
}
