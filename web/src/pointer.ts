// JSON pointers (RFC 6901) of 422 errors, matched to the form fields that carry them.

/** The field whose `data-pointer` is the longest prefix (by whole segments) of `pointer`. */
export function fieldFor(pointer: string, fields: Iterable<HTMLElement>): HTMLElement | null {
  let best: HTMLElement | null = null;
  let bestLength = -1;
  for (const field of fields) {
    const own = field.dataset.pointer ?? "";
    const matches = pointer === own || pointer.startsWith(own + "/");
    if (matches && own.length > bestLength) {
      best = field;
      bestLength = own.length;
    }
  }
  return best;
}
