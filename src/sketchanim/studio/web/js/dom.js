// @ts-check
/** Building the panels' elements. */

/**
 * An element with attributes and text.
 * @template {keyof HTMLElementTagNameMap} K
 * @param {K} tag
 * @param {Record<string, string>} [attrs]
 * @param {string} [text]
 * @returns {HTMLElementTagNameMap[K]}
 */
export function el(tag, attrs = {}, text = '') {
  const node = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) node.setAttribute(k, v);
  if (text) node.textContent = text;
  return node;
}

/**
 * A labelled select.
 * @param {string} label
 * @param {[string, string][]} options value, text
 * @param {string} value
 * @param {(value: string) => void} onChange
 * @param {string} testid
 * @returns {{wrap: HTMLLabelElement, select: HTMLSelectElement}}
 */
export function choice(label, options, value, onChange, testid) {
  const wrap = el('label', { class: 'field' }, label);
  const select = el('select', { 'data-testid': testid });
  for (const [v, text] of options) select.append(el('option', { value: v }, text));
  select.value = value;
  select.addEventListener('change', () => onChange(select.value));
  wrap.append(select);
  return { wrap, select };
}
