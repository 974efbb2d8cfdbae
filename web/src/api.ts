// The dashboard's one API client (clients/typescript) and its API key. The key lives in
// localStorage and is read before every request, so a key entered once serves every page and
// every later visit. A 401 from any request raises the key prompt (main.ts).
import { BrisanceClient, ProblemError } from "../../clients/typescript/src/client";

export * from "../../clients/typescript/src/client";

const KEY_STORAGE = "brisance.apiKey";

export function apiKey(): string | null {
  try {
    return localStorage.getItem(KEY_STORAGE);
  } catch {
    return null;  // storage disabled: the dashboard still works against a server without keys
  }
}

export function setApiKey(key: string | null): void {
  if (key) localStorage.setItem(KEY_STORAGE, key.trim());
  else localStorage.removeItem(KEY_STORAGE);
  window.dispatchEvent(new CustomEvent("brisance:key-changed"));
}

export const client = new BrisanceClient({
  apiKey: apiKey,
  fetch: async (input, init) => {
    const response = await fetch(input, init);
    if (response.status === 401) window.dispatchEvent(new CustomEvent("brisance:unauthorized"));
    return response;
  },
});

export const isAbort = (error: unknown): boolean =>
  error instanceof DOMException && error.name === "AbortError";

/** One line for people: what went wrong and what to do. */
export function describe(error: unknown): string {
  if (error instanceof ProblemError) {
    if (error.status === 0) return `Cannot reach the server: ${error.detail}`;
    if (error.status === 401) return "This server requires an API key: enter one above or in Settings.";
    if (error.status === 403) return "Your API key may only read: this needs a key with the write scope.";
    const id = error.requestId ? ` (request ${error.requestId})` : "";
    return `${error.status} ${error.title}: ${error.detail}${id}`;
  }
  return error instanceof Error ? error.message : String(error);
}
