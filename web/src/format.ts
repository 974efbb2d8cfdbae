// How numbers, times and durations read on the dashboard.
import type { Job } from "./api";

export function seconds(s: number | null | undefined): string {
  if (s === null || s === undefined || !Number.isFinite(s)) return "–";
  if (s < 1) return `${Math.round(s * 1000)} ms`;
  if (s < 60) return `${s.toFixed(s < 10 ? 2 : 1)} s`;
  const m = Math.floor(s / 60);
  if (m < 60) return `${m} min ${Math.round(s - 60 * m)} s`;
  return `${Math.floor(m / 60)} h ${m % 60} min`;
}

const ms = (t: string | null): number | null => (t ? Date.parse(t) : null);

/** Seconds between two timestamps; `to` null means now. */
export function between(from: string | null, to: string | null): number | null {
  const a = ms(from);
  if (a === null) return null;
  return ((ms(to) ?? Date.now()) - a) / 1000;
}

/** Time spent queued (until started, or until now/finished if it never started). */
export function queuedFor(job: Job): number | null {
  return between(job.created_at, job.started_at ?? job.finished_at);
}

/** Run time: started to finished, or to now while running. */
export function ranFor(job: Job): number | null {
  if (!job.started_at) return null;
  return between(job.started_at, job.status === "running" ? null : job.finished_at);
}

export function ago(t: string | null): string {
  const s = between(t, null);
  return s === null ? "–" : `${seconds(Math.max(0, s))} ago`;
}

export function dateTime(t: string | null): string {
  return t ? new Date(t).toLocaleString() : "–";
}

/** Three significant digits, switching to exponents outside 1e-3..1e6. */
export function num(x: number, digits = 3): string {
  if (!Number.isFinite(x)) return String(x);
  const a = Math.abs(x);
  if (a !== 0 && (a < 1e-3 || a >= 1e6)) return x.toExponential(digits - 1);
  return Number(x.toPrecision(digits)).toString();
}

export const shortId = (id: string): string => id.slice(0, 9) + "…";

export const finished = (job: Job): boolean =>
  job.status === "succeeded" || job.status === "failed" || job.status === "cancelled";
