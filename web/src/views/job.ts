// #/jobs/ID: the job's state, long-polled (`?wait=25` with If-None-Match: the server answers as
// soon as the job changes), its stats, warnings and error, the downloads and the actions; once
// it succeeded, its panes' fracture report and the blast pulse at a chosen body.
import { type BlastQuery, client, describe, isAbort, type Job, ProblemError, type ResultSummary,
         type RunStats } from "../api";
import { download, h, mount, sleep } from "../dom";
import { dateTime, finished, num, queuedFor, ranFor, seconds } from "../format";
import { linePlot } from "../plot";
import type { View } from "../view";
import { badge, errorBox, labelChips, progressBar } from "../widgets";
import { pulseSamples } from "./blast";

// Labels of the run statistics; a field the server adds later is shown under its own name.
const STAT_LABELS: Record<string, string> = {
  steps: "Time steps", simulated_time_s: "Simulated time (s)", wall_time_s: "Wall time (s)",
  ended_early: "Ended early (all at rest)", bodies: "Bodies", bodies_anchored: "Anchored",
  bodies_never_released: "Never released (held in place throughout)",
  fragments_held_by_frame: "Glass fragments held by their frame", bodies_slept: "Slept",
  bodies_static_in_frames: "Stored once (static)", panels: "Load panels", panels_loaded: "Panels loaded",
  panels_back_facing: "Panels sheltered from every charge", panels_not_reached: "Panels not reached",
  panels_merged: "Panels merged (fragments the wave crosses within 2 cm)",
  body_steps: "Body steps", occlusion_skipped: "Occlusion skipped",
  panels_shielded: "Panels wholly shielded",
  collision_pairs: "Collision pairs (broadphase)", collision_pairs_skipped: "Collision pairs skipped",
  contact_points: "Contact points", fragments: "Glass fragments", panes_broken: "Panes broken",
  panes_not_broken: "Panes not broken (stress below strength)",
};

// Counts are exact integers (164359 body steps, not 164400); measured values keep four digits.
const statValue = (value: number): string =>
  Number.isInteger(value) ? value.toLocaleString("en-US") : num(value, 4);

function statsTable(stats: RunStats): HTMLElement {
  const entries = Object.entries(stats as unknown as Record<string, unknown>)
    .filter(([, value]) => typeof value === "number" || typeof value === "boolean");
  return h("table", { class: "kv", id: "job-stats" }, h("tbody", null, entries.map(([key, value]) =>
    h("tr", null, h("th", null, STAT_LABELS[key] ?? key.replaceAll("_", " ")),
      h("td", { class: "num" }, typeof value === "number" ? statValue(value) : value ? "yes" : "no")))));
}

// Which bodies each charge's shielding pass scaled down, and by how much (docs/occlusion.md).
function shieldingSection(result: ResultSummary): HTMLElement | null {
  const charges = result.shielding ?? [];
  if (charges.length === 0) return null;
  return h("section", { id: "job-shielding" },
    h("h2", null, "Shielding"),
    charges.map((charge) => charge.bodies.length === 0
      ? h("p", { class: "muted" }, `Charge ${charge.charge}: nothing shielded.`)
      : h("table", { class: "kv" },
          h("caption", null, `Charge ${charge.charge}: load scaled by`),
          h("tbody", null, charge.bodies.map((body) =>
            h("tr", null, h("th", null, body.name),
              h("td", { class: "num" }, body.attenuation === 0 ? "0 (wholly shielded)" : num(body.attenuation, 3))))))));
}

type PaneFracture = NonNullable<ResultSummary["fracture"]>[number];

const words = (level: string) => level.replace("_", " ");

// Where the released fragments of a pane went in the test room behind it (docs/fracture.md,
// "Hazard rating").
function glassInRoom(hazard: PaneFracture["hazard"]): string {
  if (hazard.fragments_in_room === 0) return "none";
  const parts: string[] = [];
  if (hazard.fragments_on_floor > 0)
    parts.push(`${hazard.fragments_on_floor} on the floor (furthest ${num(hazard.max_floor_distance_m, 3)} m)`);
  if (hazard.witness_impacts > 0)
    parts.push(`${hazard.witness_impacts} at the witness panel (highest ${num(hazard.max_witness_height_m, 3)} m)`);
  return `${hazard.fragments_in_room}: ${parts.join("; ")}`;
}

// One column per breakable pane (docs/fracture.md): its load, the stress its breakage model
// gave against its strength, the crack pattern's scale and what its fragments did, beside the
// empirical glass formulas (thesis eqs. 2.45-2.46) at the same pressure.
function fractureSection(result: ResultSummary): HTMLElement | null {
  const panes = result.fracture ?? [];
  if (panes.length === 0) return null;
  const mm = (m: number) => num(m * 1e3, 3);
  const rows: [string, (p: PaneFracture) => string][] = [
    ["Broke", (p) => p.broken ? (p.forced ? "yes (forced: fracture.break = always)" : "yes") : "no"],
    ["Peak reflected pressure (kPa)", (p) => num(p.peak_pressure_pa / 1e3, 4)],
    ["Peak centre stress / strength (MPa)", (p) => `${num(p.stress_pa / 1e6, 4)} / ${num(p.strength_pa / 1e6, 4)}`],
    ["Peak centre deflection (mm)", (p) => mm(p.deflection_m) + (p.small_deflection ? "" : " (large deflection)")],
    ["Crack growth length (mm)", (p) => p.broken
      ? mm(p.growth_length_m) + (p.growth_length_given ? " (given)" : p.growth_length_clamped ? " (clamped)" : "") : "–"],
    ["Fragments (released)", (p) => p.broken ? `${p.fragment_count} (${p.released})` : "–"],
    ["Mean frontal area (cm²) / eq. 2.45", (p) => p.broken
      ? `${num(p.frontal_area_m2.mean * 1e4, 3)} / ${num(p.empirical_mean_area_m2 * 1e4, 3)}` : "–"],
    ["Mean launch speed (m/s) / eq. 2.46", (p) => p.broken
      ? `${num(p.launch_speed_m_s.mean, 3)} / ${num(p.empirical_mean_speed_m_s, 3)}` : "–"],
    ["Release time p10–p90 (ms)", (p) => p.broken && p.released > 0
      ? `${num(p.release_time_s.p10 * 1e3, 3)}–${num(p.release_time_s.p90 * 1e3, 3)}` : "–"],
    ["Hazard (GSA P100 table 8-1)", (p) =>
      `condition ${p.hazard.condition}: ${words(p.hazard.hazard_level)} hazard (${words(p.hazard.protection_level)} protection)`],
    ["Glass in the room (witness panel at 3.05 m)", (p) => p.broken ? glassInRoom(p.hazard) : "–"],
  ];
  return h("section", { id: "job-fracture" },
    h("h2", null, "Fracture"),
    h("table", { class: "kv" },
      h("thead", null, h("tr", null, h("th", null, ""), panes.map((p) => h("th", { "data-pane": p.name }, p.name)))),
      h("tbody", null, rows.map(([label, cell]) =>
        h("tr", null, h("th", null, label), panes.map((p) => h("td", { class: "num" }, cell(p))))))));
}

type Vec = [number, number, number];
interface SceneCharge { position: Vec; mass: number; explosive?: string | { tnt_factor: number };
                        burst?: "air" | "surface"; burst_model?: "hemispherical" | "factor_1_8" }

// The free-field pulse a charge sends to a body (GET /v1/blast at the distance from the charge
// to the body's origin; head-on reflection, so an upper bound for faces struck at an angle),
// with the load scale the shielding pass gave that body for that charge.
function pulseSection(result: ResultSummary, charges: SceneCharge[], signal: AbortSignal): HTMLElement | null {
  if (charges.length === 0 || result.bodies.length === 0) return null;
  const moving = result.bodies.filter((b) => b.animated);
  const bodies = (moving.length > 0 ? moving : result.bodies).slice(0, 2000);
  const bodySelect = h("select", { id: "pulse-body", name: "pulse-body" },
    bodies.map((b) => h("option", { value: String(b.index) }, b.name)));
  const chargeSelect = h("select", { id: "pulse-charge", name: "pulse-charge" },
    charges.map((c, i) => h("option", { value: String(i) }, `Charge ${i}: ${num(c.mass)} kg`)));
  const out = h("div", { id: "pulse-out" });
  const message = h("p", { class: "muted", role: "status" });
  let running: AbortController | null = null;
  async function show(): Promise<void> {
    running?.abort();
    const controller = new AbortController();
    running = controller;
    signal.addEventListener("abort", () => controller.abort(), { once: true });
    const body = result.bodies[Number(bodySelect.value)]!;
    const ci = Number(chargeSelect.value);
    const charge = charges[ci]!;
    const distance = Math.hypot(...body.position.map((x, k) => x - charge.position[k]!));
    const query: BlastQuery = { charge_kg: charge.mass, distance_m: Math.max(distance, 1e-3), burst: charge.burst ?? "air",
                                surface_model: charge.burst_model ?? "hemispherical" };
    if (typeof charge.explosive === "object") query.tnt_factor = charge.explosive.tnt_factor;
    else if (charge.explosive) query.explosive = charge.explosive;
    const shielded = result.shielding?.find((s) => s.charge === ci)?.bodies.find((b) => b.body === body.index);
    message.textContent = "Asking /v1/blast…";
    try {
      const blast = await client.blast(query, { signal: controller.signal });
      if (controller.signal.aborted) return;
      message.textContent = `${body.name}: ${num(distance, 4)} m from charge ${ci} (Z ${num(blast.scaled_distance_m_kg13, 3)} m/kg^⅓)` +
        (blast.in_validity_range ? "" : " — outside the fits' range") +
        (shielded ? `; the shielding pass scaled its load by ${num(shielded.attenuation, 3)}.` : "; not shielded from it.");
      mount(out,
        h("table", { class: "kv", id: "pulse-values" }, h("tbody", null,
          ([["Arrival (ms)", blast.arrival_time_ms], ["Positive duration (ms)", blast.positive_duration_ms],
            ["Incident P_so (kPa)", blast.incident_overpressure_kpa], ["Incident i_s (kPa·ms)", blast.incident_impulse_kpa_ms],
            ["Reflected P_r, head-on (kPa)", blast.reflected_overpressure_kpa],
            ["Reflected i_r, head-on (kPa·ms)", blast.reflected_impulse_kpa_ms]] as [string, number][])
            .map(([k, v]) => h("tr", null, h("th", null, k), h("td", { class: "num" }, num(v, 4)))))),
        linePlot({ id: "plot-body-pulse", title: `Pulse at ${body.name}`, xLabel: "time since detonation (ms)",
                   yLabel: "overpressure (kPa)",
                   series: [{ name: "incident", cls: "incident", points: pulseSamples(blast.incident_pulse, blast.arrival_time_ms) },
                            { name: "reflected (head-on)", cls: "reflected",
                              points: pulseSamples(blast.reflected_pulse, blast.arrival_time_ms) }] }));
    } catch (error) {
      if (!isAbort(error)) { message.textContent = ""; mount(out, errorBox(error)); }
    }
  }
  bodySelect.addEventListener("change", () => void show());
  chargeSelect.addEventListener("change", () => void show());
  void show();
  return h("section", { id: "job-pulse" },
    h("h2", null, "Blast pulse at a body"),
    h("p", { class: "muted" }, "Free-field Kingery–Bulmash pulse at the distance from the charge to the body's origin, " +
      "reflected head-on (faces struck at an angle see less; shielding is not in the curve)."),
    h("div", { class: "fields" }, h("label", { class: "field" }, "Body ", bodySelect),
      charges.length > 1 ? h("label", { class: "field" }, "Charge ", chargeSelect) : null),
    message, out);
}

function infoTable(job: Job): HTMLElement {
  const rows: [string, string | number | HTMLElement][] = [
    ["Name", job.name || "–"],
    ["Labels", labelChips(job.labels)],
    ["Submitted", dateTime(job.created_at)],
    ["Started", dateTime(job.started_at)],
    ["Finished", dateTime(job.finished_at)],
    ["Queued for", seconds(queuedFor(job))],
    ["Run time", seconds(ranFor(job))],
    ["Priority", job.priority],
    ["Attempts", job.attempts],
  ];
  if (job.callback) {
    const last = job.callback.deliveries.at(-1);
    rows.push(["Callback", h("span", { id: "job-callback", "data-state": job.callback.state },
      h("code", null, job.callback.url), ` ${job.callback.state}`,
      last ? ` (attempt ${last.attempt}: ${last.status ?? last.error ?? "no answer"})` : "")]);
  }
  return h("table", { class: "kv" }, h("tbody", null, rows.map(([k, v]) => h("tr", null, h("th", null, k), h("td", null, v)))));
}

export const jobView: View = (root, route, signal) => {
  const id = route.id;
  const header = h("div", { class: "job-header" });
  const body = h("div", { id: "job-body" }, h("p", { class: "muted" }, "Loading…"));
  const actionMessage = h("p", { class: "muted", id: "action-message", role: "status" });
  const warnings = h("div", { id: "job-warnings" });
  mount(root, h("p", null, h("a", { href: "#/jobs" }, "← Jobs")), header, actionMessage, body, warnings);

  let resultLoaded = false;

  async function act(what: string, run: () => Promise<unknown>): Promise<void> {
    actionMessage.textContent = `${what}…`;
    try {
      await run();
      actionMessage.textContent = `${what}: done.`;
    } catch (error) {
      actionMessage.textContent = `${what} failed: ${describe(error)}`;
    }
  }

  function actions(job: Job): HTMLElement {
    const ok = job.status === "succeeded";
    return h("div", { class: "actions" },
      ok ? h("a", { class: "button primary", href: `#/jobs/${id}/player`, id: "open-player" }, "Open 3D player") : null,
      ok ? h("button", { type: "button", id: "download-glb", onclick: () => act("Downloading result.glb", async () =>
        download(await client.getGlb(id, { signal }), `${id}.glb`, "model/gltf-binary")) }, "Download .glb") : null,
      ok ? h("button", { type: "button", id: "download-frames", onclick: () => act("Downloading frames", async () =>
        download(JSON.stringify(await client.getFrames(id, {}, { signal })), `${id}-frames.json`, "application/json")) },
        "Download frames (JSON)") : null,
      ok ? h("button", { type: "button", onclick: () => act("Downloading result summary", async () =>
        download(JSON.stringify(await client.getResult(id, { signal }), null, 2), `${id}-result.json`, "application/json")) },
        "Download result (JSON)") : null,
      h("button", { type: "button", onclick: () => act("Downloading scene", async () =>
        download(JSON.stringify(await client.getScene(id, { signal }), null, 2), `${id}-scene.json`, "application/json")) },
        "Download scene"),
      !finished(job) ? h("button", { type: "button", id: "cancel-job", onclick: () => act("Cancelling", () => client.cancelJob(id)) },
        job.cancel_requested ? "Stopping…" : "Cancel") : null,
      h("button", { type: "button", class: "danger", id: "delete-job", onclick: () => {
        if (!confirm(`Delete job ${id} and its result?`)) return;
        void act("Deleting", async () => { await client.deleteJob(id); location.hash = "#/jobs"; });
      } }, "Delete"));
  }

  function render(job: Job): void {
    mount(header, h("h1", null, job.name ? `${job.name} ` : "Job ", h("code", null, job.id), " ", badge(job.status)),
          progressBar(job, true), actions(job));
    mount(body,
      h("div", { class: "columns" },
        h("section", null, h("h2", null, "State"), infoTable(job)),
        job.stats ? h("section", null, h("h2", null, "Run statistics"), statsTable(job.stats)) : null),
      job.error ? h("section", { class: "error-box", id: "job-error" },
        h("h2", null, "Error ", h("code", null, job.error.type)), h("pre", null, job.error.message)) : null);
    if (job.status === "succeeded" && !resultLoaded) {
      resultLoaded = true;
      void loadResult();
    }
  }

  async function loadResult(): Promise<void> {
    try {
      const result: ResultSummary = await client.getResult(id, { signal });
      let charges: SceneCharge[] = [];
      try {
        const scene = await client.getScene(id, { signal }) as { charges?: SceneCharge[] };
        charges = scene.charges ?? [];
      } catch (error) {
        if (isAbort(error)) return;  // without the scene, no pulse section
      }
      mount(warnings,
        h("h2", null, "Warnings"),
        result.warnings.length === 0 ? h("p", { class: "muted" }, "None.") :
          h("ul", { class: "warnings" }, result.warnings.map((w) =>
            h("li", null, h("code", null, w.code), ` ×${w.count}: ${w.message}`))),
        h("h2", null, "Result"),
        h("p", null, `${result.bodies.length} bodies, ${result.animated.length} moving; ` +
                     `${result.frame_count} frames over ${num(result.duration, 4)} s.`),
        fractureSection(result),
        shieldingSection(result),
        pulseSection(result, charges, signal));
    } catch (error) {
      if (!isAbort(error)) mount(warnings, errorBox(error));
    }
  }

  // The long-poll: ask for the job with the tag we have and `wait=25`; the server answers when
  // it changes (200) or after 25 s (304). Stops once the job has finished.
  void (async () => {
    let etag: string | null = null;
    let failures = 0;
    while (!signal.aborted) {
      try {
        const answer = await client.getJob(id, { etag, wait: etag ? 25 : 0, signal });
        failures = 0;
        if (answer.modified) {
          etag = answer.etag;
          render(answer.value);
          if (finished(answer.value)) return;
        }
      } catch (error) {
        if (isAbort(error) || signal.aborted) return;
        if (error instanceof ProblemError && error.status === 404) {
          mount(header, h("h1", null, "Job ", h("code", null, id)));
          mount(body, h("p", { class: "error" }, "No such job: it was never made, was deleted, or was pruned."));
          return;
        }
        failures++;
        mount(actionMessage, errorBox(error));
        await sleep(Math.min(30_000, 1000 * 2 ** failures), signal);
      }
    }
  })();
};
