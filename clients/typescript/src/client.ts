// A small typed fetch client for the Brisance HTTP API (api/openapi.yaml). The types come from
// ./schema.d.ts, which openapi-typescript generates from the spec (`npm run generate`); this file
// only adds what a generator cannot: conditional requests with ETags, long-polling, binary bodies
// and problem+json errors as a typed exception. It runs wherever `fetch` does (browsers, Node 20).
import type { components, operations } from "./schema.js";

type Schemas = components["schemas"];

export type Job = Schemas["Job"];
export type JobStatus = Schemas["JobStatus"];
export type JobList = Schemas["JobList"];
export type JobError = Schemas["JobError"];
export type RunStats = Schemas["RunStats"];
export type Queue = Schemas["Queue"];
export type Blast = Schemas["Blast"];
export type BlastPulse = Schemas["BlastPulse"];
export type Element = Schemas["Element"];
export type ResponseRequest = Schemas["ResponseRequest"];
export type ElementResponse = Schemas["ElementResponse"];
export type PiRequest = Schemas["PiRequest"];
export type PiCurve = Schemas["PiCurve"];
export type WrDiagram = Schemas["WrDiagram"];
export type Explosive = Schemas["Explosive"];
export type Explosives = Schemas["Explosives"];
export type ResultSummary = Schemas["ResultSummary"];
export type RunWarning = Schemas["RunWarning"];
export type Frames = Schemas["Frames"];
export type Meshes = Schemas["Meshes"];
export type Asset = Schemas["Asset"];
export type AssetFormat = Asset["format"];
export type Charge = Schemas["Charge"];
export type PointerError = Schemas["PointerError"];
export type ParameterError = Schemas["ParameterError"];
export type ProblemType = Schemas["ProblemType"];
export type Problem = Schemas["Problem"];
// The spec's "at least objects or generators" (an anyOf of `required`) comes out of the generator
// as extra union members `{objects: unknown}` / `{generators: unknown}`; a scene is the full shape.
export type Scene = Exclude<Schemas["Scene"], { objects: unknown } | { generators: unknown }>;
export type JobRequest = Omit<Schemas["JobRequest"], "scene"> & { scene: Scene };
export type BlastQuery = operations["getBlast"]["parameters"]["query"];
export type ListJobsQuery = NonNullable<operations["listJobs"]["parameters"]["query"]>;
export type FramesQuery = { from?: number; to?: number; bodies?: number[] };

/** A problem+json answer (RFC 9457), or a failure to reach the server (`status` 0). */
export class ProblemError extends Error {
  readonly status: number;
  readonly type: string;
  readonly title: string;
  readonly detail: string;
  /** `invalid-scene`: JSON pointers into the request body; `invalid-parameter`: parameter names. */
  readonly errors: ReadonlyArray<PointerError | ParameterError>;
  readonly requestId: string | null;
  /** Seconds, from `Retry-After` (429, 503, 409 result-not-ready while running). */
  readonly retryAfter: number | null;

  constructor(problem: Partial<Problem> & { status: number }, requestId: string | null = null,
              retryAfter: number | null = null) {
    super(`${problem.status} ${problem.title ?? "Error"}: ${problem.detail ?? ""}`.trim());
    this.name = "ProblemError";
    this.status = problem.status;
    this.type = problem.type ?? "about:blank";
    this.title = problem.title ?? "Error";
    this.detail = problem.detail ?? "";
    this.errors = problem.errors ?? [];
    this.requestId = requestId;
    this.retryAfter = retryAfter;
  }

  /** The errors that carry a JSON pointer (those of a 422 `invalid-scene`). */
  get pointerErrors(): PointerError[] {
    return this.errors.filter((e): e is PointerError => "pointer" in e);
  }

  /** `type` without the `urn:brisance:problem:` prefix, e.g. `invalid-scene`. */
  get code(): string {
    return this.type.replace(/^urn:brisance:problem:/, "");
  }
}

/** What a conditional GET answered: a fresh value with its tag, or `304 Not Modified`. */
export type Conditional<T> =
  | { modified: true; value: T; etag: string | null }
  | { modified: false; etag: string };

export interface ClientOptions {
  /** Origin (and optional prefix) of the server; "" (the default) means the page's own origin. */
  baseUrl?: string;
  /** The API key, or a function asked before every request (so a key entered later is used). */
  apiKey?: string | null | (() => string | null | undefined);
  /** A fetch implementation; the global one by default. */
  fetch?: typeof fetch;
}

export interface RequestOptions {
  signal?: AbortSignal;
}

export interface ConditionalOptions extends RequestOptions {
  /** The `ETag` of the copy the caller has; a match answers `{modified: false}`. */
  etag?: string | null;
}

type Query = Record<string, string | number | boolean | number[] | undefined | null>;

export class BrisanceClient {
  private readonly baseUrl: string;
  private readonly keySource: ClientOptions["apiKey"];
  private readonly fetchImpl: typeof fetch;

  constructor(options: ClientOptions = {}) {
    this.baseUrl = (options.baseUrl ?? "").replace(/\/+$/, "");
    this.keySource = options.apiKey;
    // Bound so that a browser's fetch is not called with the client as `this`.
    this.fetchImpl = options.fetch ?? ((input, init) => globalThis.fetch(input, init));
  }

  // ---------------------------------------------------------------------------------- jobs

  /** `POST /v1/jobs`: validates and queues a job (202), or returns the job of an idempotent retry. */
  async submitJob(request: JobRequest,
                  options: RequestOptions & { idempotencyKey?: string } = {}): Promise<Job> {
    const headers: Record<string, string> = { "Content-Type": "application/json" };
    if (options.idempotencyKey !== undefined) headers["Idempotency-Key"] = options.idempotencyKey;
    const response = await this.send("POST", this.url("/v1/jobs"), {
      headers, body: JSON.stringify(request), signal: options.signal,
    });
    return (await response.json()) as Job;
  }

  // -------------------------------------------------------------------------------- assets

  /**
   * `POST /v1/assets`: uploads a mesh file (GLB, glTF with embedded buffers, or OBJ; metres) for
   * scenes to name as `{type: "asset", asset: id, node}`. Answers the stored asset, new (201) or
   * the same file uploaded before (200); an open or non-manifold mesh is a ProblemError 422.
   */
  async uploadAsset(file: ArrayBuffer | Blob, format: AssetFormat,
                    options: RequestOptions = {}): Promise<Asset> {
    const response = await this.send("POST", this.url("/v1/assets", { format }), {
      headers: { "Content-Type": ASSET_MEDIA_TYPES[format] }, body: file, signal: options.signal,
    });
    return (await response.json()) as Asset;
  }

  /** `GET /v1/assets/{id}`: an uploaded asset's format, size and nodes. */
  async getAsset(id: string, options: RequestOptions = {}): Promise<Asset> {
    return this.getJson<Asset>(`/v1/assets/${encodeURIComponent(id)}`, {}, options);
  }

  /**
   * `GET /v1/jobs/{id}`. With `etag`, an unchanged job answers `{modified: false}` and costs no
   * body; with `wait` (seconds, at most 30) the server holds the request until the job differs
   * from `etag` (or from its state on arrival) - a long-poll.
   */
  async getJob(id: string, options: ConditionalOptions & { wait?: number } = {}): Promise<Conditional<Job>> {
    return this.conditional<Job>(`/v1/jobs/${encodeURIComponent(id)}`, { wait: options.wait }, options);
  }

  /** `GET /v1/jobs`: one page, newest first; pass `next_cursor` as `cursor` for the next. */
  async listJobs(query: ListJobsQuery = {}, options: ConditionalOptions = {}): Promise<Conditional<JobList>> {
    return this.conditional<JobList>("/v1/jobs", query, options);
  }

  /** `POST /v1/jobs/{id}/cancel`: a queued job is cancelled at once, a running one asked to stop. */
  async cancelJob(id: string, options: RequestOptions = {}): Promise<Job> {
    const response = await this.send("POST", this.url(`/v1/jobs/${encodeURIComponent(id)}/cancel`), options);
    return (await response.json()) as Job;
  }

  /** `DELETE /v1/jobs/{id}`: the job and its result. */
  async deleteJob(id: string, options: RequestOptions = {}): Promise<void> {
    await this.send("DELETE", this.url(`/v1/jobs/${encodeURIComponent(id)}`), options);
  }

  /** `GET /v1/jobs/{id}/scene`: the scene as submitted. */
  async getScene(id: string, options: RequestOptions = {}): Promise<Scene> {
    return this.getJson<Scene>(`/v1/jobs/${encodeURIComponent(id)}/scene`, {}, options);
  }

  // ------------------------------------------------------------------------------- results

  /** `GET /v1/jobs/{id}/result`: bodies, frame times, final state, stats and warnings. */
  async getResult(id: string, options: RequestOptions = {}): Promise<ResultSummary> {
    return this.getJson<ResultSummary>(`/v1/jobs/${encodeURIComponent(id)}/result`, {}, options);
  }

  /** `GET /v1/jobs/{id}/frames` as JSON: poses of frames `[from, to)`. */
  async getFrames(id: string, query: FramesQuery = {}, options: RequestOptions = {}): Promise<Frames> {
    return this.getJson<Frames>(`/v1/jobs/${encodeURIComponent(id)}/frames`, query, options);
  }

  /** `GET /v1/jobs/{id}/meshes`: every body's mesh in its own frame. */
  async getMeshes(id: string, options: ConditionalOptions = {}): Promise<Conditional<Meshes>> {
    return this.conditional<Meshes>(`/v1/jobs/${encodeURIComponent(id)}/meshes`, {}, options);
  }

  /** `GET /v1/jobs/{id}/result.glb`: the animated glTF binary. */
  async getGlb(id: string, options: RequestOptions = {}): Promise<ArrayBuffer> {
    const response = await this.send("GET", this.url(`/v1/jobs/${encodeURIComponent(id)}/result.glb`), {
      headers: { Accept: "model/gltf-binary" }, signal: options.signal,
    });
    return response.arrayBuffer();
  }

  // ------------------------------------------------------------------------ queue and blast

  /** `GET /v1/queue`: counts by state, workers, the oldest queued job, throughput. */
  async getQueue(options: ConditionalOptions = {}): Promise<Conditional<Queue>> {
    return this.conditional<Queue>("/v1/queue", {}, options);
  }

  /** `GET /v1/blast`: Kingery-Bulmash blast parameters at one distance. */
  async blast(query: BlastQuery, options: RequestOptions = {}): Promise<Blast> {
    return this.getJson<Blast>("/v1/blast", query, options);
  }

  /**
   * `POST /v1/response`: the SDOF response of an element to a charge or a pulse
   * (docs/response.md); a bad field is a 422 `invalid-input` with its pointer.
   */
  async response(request: ResponseRequest, options: RequestOptions = {}): Promise<ElementResponse> {
    return this.postJson<ElementResponse>("/v1/response", request, options);
  }

  /** `POST /v1/pi`: the pressure-impulse curve of an element for one damage limit. */
  async pressureImpulse(request: PiRequest, options: RequestOptions = {}): Promise<PiCurve> {
    return this.postJson<PiCurve>("/v1/pi", { ...request, diagram: "pi" }, options);
  }

  /** `POST /v1/pi` with `"diagram": "wr"`: the charge weight-stand-off diagram of the limit. */
  async chargeStandOff(
    request: Omit<PiRequest, "diagram">,
    options: RequestOptions = {},
  ): Promise<WrDiagram> {
    return this.postJson<WrDiagram>("/v1/pi", { ...request, diagram: "wr" }, options);
  }

  /** `GET /v1/explosives`: the explosives a charge may name. */
  async explosives(options: ConditionalOptions = {}): Promise<Conditional<Explosives>> {
    return this.conditional<Explosives>("/v1/explosives", {}, options);
  }

  // ------------------------------------------------------------------------------ plumbing

  /** The URL of a path with a query (arrays comma-joined, empty values left out). */
  url(path: string, query: Query = {}): string {
    const parts: string[] = [];
    for (const [name, value] of Object.entries(query)) {
      if (value === undefined || value === null) continue;
      const text = Array.isArray(value) ? value.join(",") : String(value);
      parts.push(`${encodeURIComponent(name)}=${encodeURIComponent(text)}`);
    }
    return `${this.baseUrl}${path}${parts.length ? `?${parts.join("&")}` : ""}`;
  }

  private async getJson<T>(path: string, query: Query, options: RequestOptions): Promise<T> {
    const response = await this.send("GET", this.url(path, query), options);
    return (await response.json()) as T;
  }

  private async postJson<T>(path: string, body: unknown, options: RequestOptions): Promise<T> {
    const response = await this.send("POST", this.url(path), {
      headers: { "Content-Type": "application/json" }, body: JSON.stringify(body), signal: options.signal,
    });
    return (await response.json()) as T;
  }

  private async conditional<T>(path: string, query: Query,
                               options: ConditionalOptions): Promise<Conditional<T>> {
    const headers: Record<string, string> = {};
    if (options.etag) headers["If-None-Match"] = options.etag;
    const response = await this.send("GET", this.url(path, query), { headers, signal: options.signal });
    const etag = response.headers.get("ETag");
    if (response.status === 304) return { modified: false, etag: etag ?? options.etag ?? "" };
    return { modified: true, value: (await response.json()) as T, etag };
  }

  /** Sends one request; any status but 2xx and 304 is thrown as a ProblemError. */
  private async send(method: string, url: string,
                     init: { headers?: Record<string, string>; body?: string | ArrayBuffer | Blob;
                             signal?: AbortSignal | undefined }):
      Promise<Response> {
    const headers: Record<string, string> = { Accept: "application/json", ...init.headers };
    const key = typeof this.keySource === "function" ? this.keySource() : this.keySource;
    if (key) headers["Authorization"] = `Bearer ${key}`;
    let response: Response;
    try {
      response = await this.fetchImpl(url, {
        method,
        headers,
        // The caller keeps the tags: the HTTP cache must neither answer for the server nor
        // turn a 304 into a 200.
        cache: "no-store",
        ...(init.body !== undefined ? { body: init.body } : {}),
        ...(init.signal ? { signal: init.signal } : {}),
      });
    } catch (error) {
      if (error instanceof Error && error.name === "AbortError") throw error;
      throw new ProblemError({ status: 0, title: "Network error",
                               detail: error instanceof Error ? error.message : String(error) });
    }
    if (response.ok || response.status === 304) return response;
    throw await problemFrom(response);
  }
}

const ASSET_MEDIA_TYPES: Record<AssetFormat, string> = {
  glb: "model/gltf-binary",
  gltf: "model/gltf+json",
  obj: "model/obj",
};

/** Reads a failed response as a ProblemError (problem+json when it is one). */
export async function problemFrom(response: Response): Promise<ProblemError> {
  const requestId = response.headers.get("X-Request-Id");
  const retryHeader = response.headers.get("Retry-After");
  const retryAfter = retryHeader !== null && /^\d+$/.test(retryHeader) ? Number(retryHeader) : null;
  let problem: Partial<Problem> & { status: number } = { status: response.status,
                                                         title: response.statusText || "HTTP error" };
  const text = await response.text().catch(() => "");
  if ((response.headers.get("Content-Type") ?? "").includes("json") && text) {
    try {
      problem = { ...(JSON.parse(text) as Partial<Problem>), status: response.status };
    } catch {
      problem.detail = text.slice(0, 500);
    }
  } else if (text) {
    problem.detail = text.slice(0, 500);
  }
  return new ProblemError(problem, requestId, retryAfter);
}
