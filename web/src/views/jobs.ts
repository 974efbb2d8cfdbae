// #/jobs[?status=S&label=L&name=N]: one page of jobs at a time, newest first, filtered by status,
// label selectors and name; the page on screen is polled with If-None-Match (a 304 while it is
// unchanged).
import { client, type JobList, type JobStatus } from "../api";
import { h, mount } from "../dom";
import { poll } from "../poll";
import type { View } from "../view";
import { errorBox, jobsTable, STATUSES } from "../widgets";

const PAGE_SIZE = 20;

export const jobsView: View = (root, route, signal) => {
  const statusParam = route.query.get("status");
  const status = STATUSES.find((s) => s === statusParam) as JobStatus | undefined;
  const label = route.query.get("label") ?? "";
  const name = route.query.get("name") ?? "";
  // The filters live in the address, so a filtered list can be bookmarked and shared.
  const go = (changes: Record<string, string>): void => {
    const query = new URLSearchParams({ ...(status ? { status } : {}), label, name, ...changes });
    for (const [key, value] of [...query.entries()]) if (!value) query.delete(key);
    const text = query.toString();
    location.hash = text ? `#/jobs?${text}` : "#/jobs";
  };
  // Cursors of the pages before this one, so "Previous" can go back (the API pages forwards).
  const cursors: number[] = [];
  let cursor = 0;
  let nextCursor: string | null = null;
  let pageSignal: AbortController | null = null;

  const filter = h("select", { id: "status-filter", "aria-label": "Filter by status",
                               onchange: (e: Event) => go({ status: (e.target as HTMLSelectElement).value }) },
    h("option", { value: "" }, "all statuses"),
     STATUSES.map((s) => h("option", { value: s, selected: s === status }, s)));
  const table = h("div", { id: "jobs-table" }, h("p", { class: "muted" }, "Loading…"));
  const prev = h("button", { type: "button", id: "prev-page", disabled: true,
                             onclick: () => { cursor = cursors.pop() ?? 0; load(); } }, "← Newer");
  const next = h("button", { type: "button", id: "next-page", disabled: true,
                             onclick: () => {
    if (nextCursor === null) return;
    cursors.push(cursor);
    cursor = Number(nextCursor);
    load();
  } }, "Older →");
  const pageLabel = h("span", { class: "muted", id: "page-label" });

  const labelInput = h("input", { id: "label-filter", type: "search", value: label, size: 18,
                                  placeholder: "shot=sq010,artist", "aria-label": "Filter by labels" });
  const nameInput = h("input", { id: "name-filter", type: "search", value: name, size: 14,
                                 placeholder: "part of a name", "aria-label": "Filter by name" });
  const filters = h("form", { class: "filters", id: "job-filters", onsubmit: (e: Event) => {
    e.preventDefault();
    go({ label: labelInput.value.trim(), name: nameInput.value.trim() });
  } }, h("label", null, "Labels ", labelInput), h("label", null, "Name ", nameInput),
     h("button", { type: "submit" }, "Filter"),
     label || name ? h("button", { type: "button", id: "clear-filters", onclick: () => go({ label: "", name: "" }) },
                       "Clear") : null);

  mount(root, h("h1", null, "Jobs"),
        h("div", { class: "toolbar" }, h("label", null, "Status ", filter), filters, h("span", { class: "grow" }),
          pageLabel, prev, next),
        table);

  function load(): void {
    pageSignal?.abort();
    const controller = new AbortController();
    pageSignal = controller;
    signal.addEventListener("abort", () => controller.abort(), { once: true });
    pageLabel.textContent = `page ${cursors.length + 1}`;
    prev.disabled = cursors.length === 0;
    void poll<JobList>({
      fetch: (etag, s) => client.listJobs({ limit: PAGE_SIZE, cursor, ...(status ? { status } : {}),
                                            ...(label ? { label } : {}), ...(name ? { name } : {}) },
                                          { etag, signal: s }),
      onValue: (list) => {
        nextCursor = list.next_cursor;
        next.disabled = nextCursor === null;
        mount(table, jobsTable(list.jobs));
      },
      onError: (error) => mount(table, errorBox(error)),
      intervalMs: 2000,
      signal: controller.signal,
    });
  }
  load();
};
