// What every page is: it renders into `root` and stops its requests when `signal` aborts (the
// route changed).
export interface RouteInfo {
  /** The job id of #/jobs/ID and #/jobs/ID/player; "" elsewhere. */
  id: string;
  /** The query after `?` in the hash (#/jobs?status=failed). */
  query: URLSearchParams;
}

export type View = (root: HTMLElement, route: RouteInfo, signal: AbortSignal) => void | Promise<void>;
