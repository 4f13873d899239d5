/**
 * A preset menu: one big button per entry of a library list, the active one marked
 * (`aria-pressed`, and the page's style). A list of buttons rather than a `<select>`: every choice
 * is in view and each is a large touch target.
 */

/** A menu and how to mark its active entry. */
export interface PresetMenu {
  /** Mark entry `index` as active (null: none). */
  setActive(index: number | null): void;
  /** The entry marked active, or null. */
  active(): number | null;
}

/**
 * Fill `list` (a `<ul>`) with a button per label; `onPick(index)` runs when one is pressed.
 */
export function createPresetMenu(list: HTMLElement, labels: readonly string[],
  onPick: (index: number) => void): PresetMenu {
  let current: number | null = null;
  const buttons = labels.map((label, index) => {
    const button = document.createElement('button');
    button.type = 'button';
    button.className = 'preset';
    button.textContent = label;
    button.dataset.index = String(index);
    button.setAttribute('aria-pressed', 'false');
    button.addEventListener('click', () => { onPick(index); });
    const item = document.createElement('li');
    item.appendChild(button);
    return { item, button };
  });
  list.replaceChildren(...buttons.map((b) => b.item));
  return {
    setActive(index) {
      current = index;
      buttons.forEach(({ button }, k) => { button.setAttribute('aria-pressed', String(k === index)); });
    },
    active: () => current,
  };
}
