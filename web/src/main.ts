// The dashboard: hash routes, each a view that renders into <main> and stops its polling when the
// route changes (its AbortSignal aborts). The 3D player is a separate chunk (three.js), loaded
// only when opened.
import "./style.css";
import { apiKey, setApiKey } from "./api";
import { h, mount } from "./dom";
import { blastView } from "./views/blast";
import { jobView } from "./views/job";
import { jobsView } from "./views/jobs";
import { newJobView } from "./views/new-job";
import { queueView } from "./views/queue";
import { settingsView } from "./views/settings";
import type { View } from "./view";


interface Route {
  pattern: RegExp;
  nav: string;
  view: () => Promise<View> | View;
}

const routes: Route[] = [
  { pattern: /^\/(queue)?$/, nav: "queue", view: () => queueView },
  { pattern: /^\/jobs$/, nav: "jobs", view: () => jobsView },
  { pattern: /^\/jobs\/([^/]+)$/, nav: "jobs", view: () => jobView },
  { pattern: /^\/jobs\/([^/]+)\/player$/, nav: "jobs",
    view: async () => (await import("./views/player")).playerView },
  { pattern: /^\/new$/, nav: "new", view: () => newJobView },
  { pattern: /^\/blast$/, nav: "blast", view: () => blastView },
  { pattern: /^\/settings$/, nav: "settings", view: () => settingsView },
];

const root = document.getElementById("view") as HTMLElement;
let current: AbortController | null = null;

async function route(): Promise<void> {
  current?.abort();
  const controller = new AbortController();
  current = controller;
  const hash = location.hash.replace(/^#/, "") || "/queue";
  const [path = "/", query = ""] = hash.split("?", 2);
  const found = routes.map((r) => ({ r, m: r.pattern.exec(path) })).find((x) => x.m);
  document.querySelectorAll<HTMLElement>("[data-nav]").forEach((a) =>
    a.classList.toggle("active", a.dataset.nav === found?.r.nav));
  if (!found?.m) {
    mount(root, h("h1", null, "Not found"), h("p", null, "No page at ", h("code", null, hash), "."));
    return;
  }
  const info = { id: decodeURIComponent(found.m[1] ?? ""), query: new URLSearchParams(query) };
  root.replaceChildren(h("p", { class: "muted" }, "Loading…"));
  try {
    const view = await found.r.view();
    if (controller.signal.aborted) return;
    root.replaceChildren();
    await view(root, info, controller.signal);
  } catch (error) {
    if (controller.signal.aborted) return;
    mount(root, h("p", { class: "error" }, `This page failed: ${String(error)}`));
  }
}

// ------------------------------------------------------------------------------ the API key

function keyState(): void {
  const slot = document.getElementById("key-state");
  if (slot) slot.textContent = apiKey() ? "API key set" : "";
}

/** Shown when any request answers 401: the key is entered once and kept in localStorage. */
function promptForKey(): void {
  const slot = document.getElementById("key-prompt-slot") as HTMLElement;
  if (slot.querySelector("#key-prompt")) return;
  const input = h("input", { id: "key-prompt-input", type: "password", autocomplete: "off",
                             placeholder: "bk_…", size: 48, "aria-label": "API key" });
  const save = (event: Event) => {
    event.preventDefault();
    if (!input.value.trim()) return;
    setApiKey(input.value);
    slot.replaceChildren();
    void route();
  };
  mount(slot, h("form", { id: "key-prompt", class: "key-prompt", onsubmit: save },
    h("strong", null, apiKey() ? "The server refused the API key." : "This server requires an API key."),
    " Enter it once; this browser keeps it (Settings changes or removes it). ",
    input, " ", h("button", { type: "submit" }, "Save key")));
  input.focus();
}

window.addEventListener("brisance:unauthorized", promptForKey);
window.addEventListener("brisance:key-changed", keyState);
window.addEventListener("hashchange", () => void route());
keyState();
void route();
