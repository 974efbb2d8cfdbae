// Polling with ETags: every request after the first sends If-None-Match, so while nothing changes
// the server answers 304 with no body and the page does no work. Polls pause while the tab is
// hidden and stop when the view's signal aborts.
import { type Conditional, isAbort } from "./api";
import { sleep } from "./dom";

export interface PollStats {
  requests: number;
  notModified: number;
  lastChange: Date | null;
}

export interface PollOptions<T> {
  fetch: (etag: string | null, signal: AbortSignal) => Promise<Conditional<T>>;
  onValue: (value: T) => void;
  onError: (error: unknown) => void;
  onPoll?: (stats: PollStats) => void;
  intervalMs: number;
  signal: AbortSignal;
}

export async function poll<T>(options: PollOptions<T>): Promise<void> {
  const stats: PollStats = { requests: 0, notModified: 0, lastChange: null };
  let etag: string | null = null;
  let failures = 0;
  while (!options.signal.aborted) {
    if (document.hidden) {
      await sleep(500, options.signal);
      continue;
    }
    try {
      const answer = await options.fetch(etag, options.signal);
      stats.requests++;
      failures = 0;
      if (answer.modified) {
        etag = answer.etag;
        stats.lastChange = new Date();
        options.onValue(answer.value);
      } else {
        stats.notModified++;
      }
      options.onPoll?.(stats);
    } catch (error) {
      if (isAbort(error) || options.signal.aborted) return;
      failures++;
      options.onError(error);
    }
    // Back off while the server fails, up to 30 s.
    await sleep(failures ? Math.min(30_000, options.intervalMs * 2 ** failures) : options.intervalMs,
                options.signal);
  }
}
