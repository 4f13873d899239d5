/** Small DOM helpers shared by the viewer's panels. */

/** A `<label>` holding a caption and its control. */
export function labelled(text: string, control: HTMLElement): HTMLLabelElement {
  const label = document.createElement('label');
  const span = document.createElement('span');
  span.textContent = text;
  label.append(span, control);
  return label;
}
