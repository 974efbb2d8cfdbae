// #/settings: the API key, kept in this browser's localStorage and sent as
// `Authorization: Bearer KEY` with every API request (never with the page's own files).
import { apiKey, client, describe, setApiKey } from "../api";
import { h, mount } from "../dom";
import type { View } from "../view";

export const settingsView: View = (root) => {
  const input = h("input", { id: "api-key", name: "api-key", type: "password", autocomplete: "off", size: 52,
                             placeholder: "bk_… (empty: no key)", value: apiKey() ?? "" });
  const message = h("p", { id: "settings-message", role: "status" });
  const test = async () => {
    message.className = "muted";
    message.textContent = "Asking /v1/queue…";
    try {
      const queue = await client.getQueue();
      message.className = "ok";
      message.textContent = `The server accepts this key (${queue.modified ? queue.value.workers.total : "?"} workers).`;
    } catch (error) {
      message.className = "error";
      message.textContent = describe(error);
    }
  };
  mount(root, h("h1", null, "Settings"),
    h("form", { class: "settings", onsubmit: (e: Event) => {
      e.preventDefault();
      setApiKey(input.value.trim() || null);
      document.getElementById("key-prompt-slot")?.replaceChildren();
      void test();
    } },
      h("h2", null, "API key"),
      h("p", { class: "muted small" }, "Needed when the server runs with --api-keys (make one with ",
        h("code", null, "brisance api-key --name NAME --scope read|write"), "). A read key can watch jobs; ",
        "submitting, cancelling and deleting need a write key. The key stays in this browser."),
      h("div", { class: "toolbar" }, input,
        h("button", { type: "button", onclick: () => { input.type = input.type === "password" ? "text" : "password"; } }, "Show"),
        h("button", { type: "submit", class: "primary", id: "save-key" }, "Save"),
        h("button", { type: "button", id: "clear-key", onclick: () => { setApiKey(null); input.value = ""; void test(); } }, "Remove")),
      message));
};
