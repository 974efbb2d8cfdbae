// #/queue: jobs by state, workers, throughput and the oldest queued job, plus the newest jobs.
// Both are polled every 2 s with If-None-Match, so an idle queue costs a 304 per poll.
import { client, type JobList, type Queue } from "../api";
import { h, mount } from "../dom";
import { ago, seconds } from "../format";
import { poll, type PollStats } from "../poll";
import type { View } from "../view";
import { errorBox, jobsTable, STATUSES } from "../widgets";

function queueCards(queue: Queue): HTMLElement {
  const { busy, idle, total } = queue.workers;
  return h("div", { class: "queue" },
    h("section", { class: "cards" }, STATUSES.map((status) =>
      h("a", { class: `card status-${status}`, href: `#/jobs?status=${status}`, "data-count": status },
        h("span", { class: "count" }, queue.counts[status]), h("span", { class: "what" }, status)))),
    h("section", { class: "cards" },
      h("div", { class: "card", "data-workers": "" },
        h("span", { class: "count" }, `${busy} / ${total}`), h("span", { class: "what" }, "workers busy"),
        h("div", { class: "meter", title: `${busy} busy, ${idle} idle` },
          h("div", { class: "fill", style: `width: ${total ? (100 * busy) / total : 0}%` })),
        h("span", { class: "muted" }, `${idle} idle`)),
      h("div", { class: "card", "data-throughput": "" },
        h("span", { class: "count" }, queue.throughput_per_min), h("span", { class: "what" }, "finished / min")),
      h("div", { class: "card", "data-oldest": "" },
        h("span", { class: "count" }, queue.oldest_queued ? seconds(queue.oldest_queued.age_s) : "–"),
        h("span", { class: "what" }, "oldest queued job"),
        queue.oldest_queued ? h("span", { class: "muted" }, `since ${ago(queue.oldest_queued.created_at)}`) : null)));
}

const pollLine = (stats: PollStats): string =>
  `${stats.requests} polls, ${stats.notModified} answered 304 Not Modified` +
  (stats.lastChange ? `; last change ${stats.lastChange.toLocaleTimeString()}` : "");

export const queueView: View = (root, _route, signal) => {
  const overview = h("div", { id: "queue-overview" }, h("p", { class: "muted" }, "Loading…"));
  const recent = h("div", { id: "recent-jobs" });
  const status = h("p", { class: "muted small", id: "poll-stats" });
  mount(root, h("h1", null, "Queue"), overview, status,
        h("h2", null, "Newest jobs ", h("a", { class: "small", href: "#/jobs" }, "all jobs →")), recent);

  void poll<Queue>({
    fetch: (etag, s) => client.getQueue({ etag, signal: s }),
    onValue: (queue) => mount(overview, queueCards(queue)),
    onError: (error) => mount(overview, errorBox(error)),
    onPoll: (stats) => {
      status.textContent = pollLine(stats);
      status.dataset.notModified = String(stats.notModified);
    },
    intervalMs: 2000,
    signal,
  });
  void poll<JobList>({
    fetch: (etag, s) => client.listJobs({ limit: 8 }, { etag, signal: s }),
    onValue: (list) => mount(recent, jobsTable(list.jobs)),
    onError: (error) => mount(recent, errorBox(error)),
    intervalMs: 2000,
    signal,
  });
};
