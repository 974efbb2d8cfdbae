// Pieces several pages share: status badges, progress bars, the jobs table, error boxes.
import { describe, type Job, type JobStatus } from "./api";
import { h } from "./dom";
import { ago, queuedFor, ranFor, seconds, shortId } from "./format";

export const STATUSES: JobStatus[] = ["queued", "running", "succeeded", "failed", "cancelled"];

export const badge = (status: JobStatus): HTMLElement =>
  h("span", { class: `badge status-${status}`, "data-status": status }, status);

/** A progress bar; `data-status` and `aria-valuenow` (0..1) say where the job is. */
export function progressBar(job: Job, large = false): HTMLElement {
  const percent = Math.round(job.progress * 100);
  return h("div", {
    class: `progress status-${job.status}${large ? " large" : ""}`,
    role: "progressbar",
    "aria-valuemin": 0, "aria-valuemax": 1, "aria-valuenow": job.progress,
    "aria-label": `progress of ${job.id}`,
    "data-status": job.status,
    "data-job": job.id,
  },
  h("div", { class: "fill", style: `width: ${percent}%` }),
  h("span", { class: "label" }, job.status === "succeeded" ? "done" : `${percent}%`));
}

/** A job's labels as `key=value` chips; each links to the list of jobs with that label. */
export function labelChips(labels: Record<string, string> | undefined): HTMLElement {
  const entries = Object.entries(labels ?? {});
  if (entries.length === 0) return h("span", { class: "muted" }, "–");
  return h("span", { class: "labels" }, entries.map(([key, value]) => {
    const selector = `${key}=${value}`;
    return h("a", { class: "label-chip", href: `#/jobs?label=${encodeURIComponent(selector)}`,
                    title: `jobs labelled ${selector}` }, selector);
  }));
}

export function jobsTable(jobs: Job[]): HTMLElement {
  if (jobs.length === 0) return h("p", { class: "muted empty" }, "No jobs.");
  return h("table", { class: "jobs" },
    h("thead", null, h("tr", null,
      h("th", null, "Job"), h("th", null, "Name"), h("th", null, "Labels"), h("th", null, "Status"), h("th", { class: "wide" }, "Progress"),
      h("th", null, "Priority"), h("th", null, "Submitted"), h("th", null, "Queued"),
      h("th", null, "Run time"), h("th", null, "Attempts"))),
    h("tbody", null, jobs.map((job) =>
      h("tr", { "data-job": job.id },
        h("td", null, h("a", { href: `#/jobs/${job.id}`, title: job.id }, h("code", null, shortId(job.id)))),
        h("td", { class: "job-name" }, job.name),
        h("td", null, labelChips(job.labels)),
        h("td", null, badge(job.status), job.cancel_requested && job.status === "running" ? " stopping" : ""),
        h("td", null, progressBar(job)),
        h("td", { class: "num" }, job.priority),
        h("td", { title: job.created_at }, ago(job.created_at)),
        h("td", { class: "num" }, seconds(queuedFor(job))),
        h("td", { class: "num" }, seconds(ranFor(job))),
        h("td", { class: "num" }, job.attempts)))));
}

export const errorBox = (error: unknown): HTMLElement =>
  h("p", { class: "error", role: "alert" }, describe(error));
