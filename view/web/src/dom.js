// Writing to the page only what changed. A live page of 64 robots redraws about a thousand links
// twice a second; most of their attributes keep their value, and setAttribute was most of the
// page's script time even so (Chromium's profile, docs/performance.md, "Live view").

// Sets attribute `name` of `element` to `value` (removed when null or undefined) unless the
// page set that value last time. Only this function may write the attributes it is given.
export function setChanged(element, name, value) {
  const written = (element.sitlnetWritten ??= new Map());
  const text = value === null || value === undefined ? null : String(value);
  if (written.has(name) && written.get(name) === text) return;
  written.set(name, text);
  if (text === null) element.removeAttribute(name);
  else element.setAttribute(name, text);
}

// Sets `node`'s text unless it already reads so.
export function setTextChanged(node, text) {
  if (node.textContent !== text) node.textContent = text;
}
