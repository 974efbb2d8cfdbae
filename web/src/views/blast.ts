// #/blast: the blast calculator. For one charge, /v1/blast is asked at ~60 log-spaced distances
// and P_so, i_s, t_a, P_r and i_r are drawn against distance on log-log axes; the table gives every field
// at one distance, with its incident and reflected pressure-time pulses. The response tab
// (#/blast?tab=response) loads a structural element (an example or edited JSON) with that charge
// at that distance: POST /v1/response draws its displacement history, POST /v1/pi its P-I curve
// with the charge as a point on it.
import { type Blast, type BlastPulse, type BlastQuery, client, describe, type Element, type Explosive, isAbort,
         ProblemError } from "../api";
import { h, mount } from "../dom";
import { elementTemplates } from "../elements";
import { num } from "../format";
import { linePlot, logLogPlot, type PlotPoint } from "../plot";
import type { View } from "../view";

const SAMPLES = 60;
const CONCURRENCY = 6;

const CURVES: { key: keyof Blast; id: string; title: string; unit: string }[] = [
  { key: "incident_overpressure_kpa", id: "plot-pso", title: "Incident overpressure P_so", unit: "kPa" },
  { key: "incident_impulse_kpa_ms", id: "plot-is", title: "Incident impulse i_s", unit: "kPa·ms" },
  { key: "arrival_time_ms", id: "plot-ta", title: "Arrival time t_a", unit: "ms" },
  { key: "reflected_overpressure_kpa", id: "plot-pr", title: "Reflected overpressure P_r (at the angle)", unit: "kPa" },
  { key: "reflected_impulse_kpa_ms", id: "plot-ir", title: "Reflected impulse i_r (at the angle)", unit: "kPa·ms" },
];

const TABLE: { key: keyof Blast; label: string; unit: string }[] = [
  { key: "scaled_distance_m_kg13", label: "Scaled distance Z", unit: "m/kg^⅓" },
  { key: "tnt_equivalent_kg", label: "TNT equivalent W", unit: "kg" },
  { key: "incident_overpressure_kpa", label: "Incident overpressure P_so", unit: "kPa" },
  { key: "incident_impulse_kpa_ms", label: "Incident impulse i_s", unit: "kPa·ms" },
  { key: "arrival_time_ms", label: "Arrival time t_a", unit: "ms" },
  { key: "positive_duration_ms", label: "Positive duration t_o", unit: "ms" },
  { key: "reflected_overpressure_kpa", label: "Reflected overpressure P_r", unit: "kPa" },
  { key: "reflected_impulse_kpa_ms", label: "Reflected impulse i_r", unit: "kPa·ms" },
  { key: "shock_velocity_m_s", label: "Shock front velocity U", unit: "m/s" },
  { key: "dynamic_pressure_kpa", label: "Dynamic pressure q_s", unit: "kPa" },
  { key: "reflection_coefficient", label: "Reflection coefficient C_R", unit: "" },
  { key: "in_validity_range", label: "Inside the fits' validity range", unit: "" },
];

/** A positive-phase Friedlander pulse, p(t) = P (1 - t/T) exp(-b t/T), sampled from arrival. */
export const pulseSamples = (pulse: BlastPulse, arrivalMs: number, count = 120): [number, number][] =>
  Array.from({ length: count }, (_, i) => {
    const u = i / (count - 1);
    return [arrivalMs + u * pulse.duration_ms, pulse.peak_kpa * (1 - u) * Math.exp(-pulse.decay * u)];
  });

/** The incident negative phase, the cubic p(t) = -P (27/4)(t/T)(1 - t/T)^2 (docs/blast-model.md),
 *  sampled from `startMs`, where the positive phase ends. */
export const negativeSamples = (phase: Blast["negative_phase"], startMs: number, count = 60): [number, number][] =>
  Array.from({ length: count }, (_, i) => {
    const u = (i + 1) / count;
    return [startMs + u * phase.duration_ms, -phase.underpressure_kpa * 6.75 * u * (1 - u) ** 2];
  });

/** `count` distances from `lo` to `hi`, evenly spaced in log. */
export const logSpace = (lo: number, hi: number, count: number): number[] =>
  Array.from({ length: count }, (_, i) => lo * (hi / lo) ** (i / (count - 1)));

/** Runs `work` over `items`, at most `limit` at a time, keeping the order. */
async function mapLimited<T, R>(items: T[], limit: number, work: (item: T) => Promise<R>): Promise<R[]> {
  const results: R[] = new Array(items.length);
  let next = 0;
  await Promise.all(Array.from({ length: Math.min(limit, items.length) }, async () => {
    while (next < items.length) {
      const i = next++;
      results[i] = await work(items[i]!);
    }
  }));
  return results;
}

export const blastView: View = async (root, route, signal) => {
  let explosives: Explosive[] = [];
  try {
    const answer = await client.explosives({ signal });
    if (answer.modified) explosives = answer.value.explosives;
  } catch { /* typed in instead */ }
  if (signal.aborted) return;

  const q = route.query;
  const input = (id: string, label: string, value: string, attrs: Record<string, string | number> = {}) =>
    h("label", { class: "field" }, label, " ", h("input", { id, name: id, inputmode: "decimal", size: 7, value, ...attrs }));
  const explosive = explosives.length
    ? h("select", { id: "explosive", name: "explosive" }, explosives.map((e) =>
        h("option", { value: e.name, selected: e.name === (q.get("explosive") ?? "TNT") }, `${e.name} (×${e.tnt_factor})`)))
    : h("input", { id: "explosive", name: "explosive", value: q.get("explosive") ?? "TNT" });
  const burst = h("select", { id: "burst", name: "burst" },
    ["air", "surface"].map((b) => h("option", { value: b, selected: b === (q.get("burst") ?? "air") }, b)));
  const plots = h("div", { class: "plots", id: "blast-plots" });
  const table = h("div", { id: "blast-table" });
  const pulses = h("div", { class: "plots", id: "pulse-plots" });
  const message = h("p", { id: "blast-message", role: "status", class: "muted" });

  // The response tab.
  const startName = elementTemplates[0]?.name ?? "";
  const elementJson = h("textarea", { id: "element-json", class: "element-json", spellcheck: "false",
                                      "aria-label": "Element JSON" });
  elementJson.value = JSON.stringify(elementTemplates[0]?.element ?? {}, null, 2);
  const elementPick = h("select", { id: "element-example", name: "element-example",
                                    onchange: () => {
                                      const t = elementTemplates.find((e) => e.name === elementPick.value);
                                      if (t) elementJson.value = JSON.stringify(t.element, null, 2);
                                    } },
    elementTemplates.map((e) => h("option", { value: e.name, selected: e.name === startName }, e.name)));
  const responseMessage = h("p", { id: "response-message", role: "status", class: "muted" });
  const responseSummary = h("div", { id: "response-summary" });
  const responsePlots = h("div", { class: "plots", id: "response-plots" });
  const responseForm = h("form", { id: "response-form", class: "toolbar wrap",
                                   onsubmit: (e: Event) => { e.preventDefault(); void respond(); } },
    h("label", { class: "field" }, "Element ", elementPick),
    input("pi-ductility", "P–I limit: ductility μ", q.get("ductility") ?? "3"),
    input("pi-rotation", "or rotation θ (°)", q.get("rotation_deg") ?? ""),
    h("button", { type: "submit", class: "primary", id: "compute-response" }, "Compute response"));
  const blastSection = h("section", { id: "tab-panel-blast" },
    plots, h("h2", null, "At one distance"), table, pulses);
  const responseSection = h("section", { id: "tab-panel-response", hidden: true },
    h("p", { class: "muted small" }, "The element (lumped-mass SDOF model, docs/response.md) loaded by the reflected ",
      "pulse of the charge above at the table's distance and angle. Edit the JSON or pick an example."),
    responseForm, elementJson, responseMessage, responseSummary, responsePlots);
  const tabButton = (id: string, label: string, panel: HTMLElement) =>
    h("button", { type: "button", id, role: "tab", "aria-selected": "false", onclick: () => select(id, panel) }, label);
  const tabs = h("div", { class: "tabs", role: "tablist" },
    tabButton("tab-blast", "Blast wave", blastSection), tabButton("tab-response", "Element response", responseSection));
  let responded = false;
  function select(id: string, panel: HTMLElement): void {
    for (const button of tabs.querySelectorAll("button")) button.setAttribute("aria-selected", String(button.id === id));
    blastSection.hidden = panel !== blastSection;
    responseSection.hidden = panel !== responseSection;
    if (panel === responseSection && !responded) void respond();
  }
  const form = h("form", { id: "blast-form", class: "toolbar wrap", onsubmit: (e: Event) => { e.preventDefault(); void compute(); } },
    input("charge", "Charge (kg)", q.get("charge_kg") ?? "100"),
    h("label", { class: "field" }, "Explosive ", explosive),
    h("label", { class: "field" }, "Burst ", burst),
    input("angle", "Angle of incidence (°)", q.get("angle_deg") ?? "0"),
    input("rmin", "Distances from (m)", q.get("from") ?? "1"),
    input("rmax", "to (m)", q.get("to") ?? "200"),
    input("distance", "Table at (m)", q.get("distance_m") ?? "15"),
    h("button", { type: "submit", class: "primary", id: "compute" }, "Compute"));
  mount(root, h("h1", null, "Blast calculator"),
    h("p", { class: "muted small" }, "Kingery–Bulmash fits (free-air spherical or hemispherical surface burst). ",
      "Dashed: outside the fits' validity range."),
    form, message, tabs, blastSection, responseSection);

  let running: AbortController | null = null;
  let current: { query: BlastQuery; blast: Blast } | null = null;

  async function compute(): Promise<void> {
    running?.abort();
    const controller = new AbortController();
    running = controller;
    signal.addEventListener("abort", () => controller.abort(), { once: true });
    const value = (id: string) => Number((root.querySelector<HTMLInputElement>(`#${id}`)?.value ?? "").trim());
    const [charge, angle, rmin, rmax, distance] = ["charge", "angle", "rmin", "rmax", "distance"].map(value) as
      [number, number, number, number, number];
    if (!(rmin > 0 && rmax > rmin)) {
      message.className = "error";
      message.textContent = "The distances must satisfy 0 < from < to.";
      return;
    }
    const base: Omit<BlastQuery, "distance_m"> = { charge_kg: charge, explosive: explosive.value, burst: burst.value as "air" | "surface", angle_deg: angle };
    message.className = "muted";
    message.textContent = `Asking /v1/blast at ${SAMPLES} distances…`;
    try {
      const distances = logSpace(rmin, rmax, SAMPLES);
      const single = client.blast({ ...base, distance_m: distance }, { signal: controller.signal });
      const curve = await mapLimited(distances, CONCURRENCY, async (r) =>
        ({ r, blast: await client.blast({ ...base, distance_m: r }, { signal: controller.signal }) }));
      const one = await single;
      if (controller.signal.aborted) return;
      mount(plots, CURVES.map((c) => logLogPlot({
        id: c.id, title: c.title, xLabel: "distance (m)", yLabel: c.unit, marker: distance,
        points: curve.map(({ r, blast }): PlotPoint => ({ x: r, y: blast[c.key] as number, valid: blast.in_validity_range })),
      })));
      mount(table, h("table", { class: "kv", id: "blast-values" }, h("tbody", null, TABLE.map((row) => {
        const v = one[row.key];
        return h("tr", { "data-field": row.key }, h("th", null, row.label),
          h("td", { class: "num" }, typeof v === "number" ? num(v, 4) : v ? "yes" : "no"), h("td", { class: "unit" }, row.unit));
      }))));
      mount(pulses, linePlot({
        id: "plot-pulse", title: `Pressure–time pulse at ${num(distance)} m`, xLabel: "time since detonation (ms)",
        yLabel: "overpressure (kPa)",
        series: [
          { name: "incident (with its negative phase)", cls: "incident",
            points: [...pulseSamples(one.incident_pulse, one.arrival_time_ms),
                     ...negativeSamples(one.negative_phase, one.arrival_time_ms + one.incident_pulse.duration_ms)] },
          { name: `reflected (${num(angle)}°, positive phase)`, cls: "reflected", points: pulseSamples(one.reflected_pulse, one.arrival_time_ms) },
        ],
      }));
      current = { query: { ...base, distance_m: distance }, blast: one };
      if (!responseSection.hidden) void respond();
      message.textContent = `${charge} kg ${explosive.value}, ${burst.value} burst, at ${distance} m: ` +
        `P_so ${num(one.incident_overpressure_kpa)} kPa.`;
      history.replaceState(null, "", `#/blast?charge_kg=${charge}&explosive=${encodeURIComponent(explosive.value)}` +
        `&burst=${burst.value}&angle_deg=${angle}&from=${rmin}&to=${rmax}&distance_m=${distance}`);
    } catch (error) {
      if (isAbort(error)) return;
      message.className = "error";
      message.textContent = describe(error);
    }
  }
  let responding: AbortController | null = null;

  async function respond(): Promise<void> {
    if (!current) return;
    responded = true;
    responding?.abort();
    const controller = new AbortController();
    responding = controller;
    signal.addEventListener("abort", () => controller.abort(), { once: true });
    let element: Element;
    try {
      element = JSON.parse(elementJson.value) as Element;
    } catch (error) {
      responseMessage.className = "error";
      responseMessage.textContent = `The element is not valid JSON: ${error instanceof Error ? error.message : String(error)}`;
      return;
    }
    const { query, blast } = current;
    const ductility = Number(root.querySelector<HTMLInputElement>("#pi-ductility")?.value.trim() || "NaN");
    const rotationText = root.querySelector<HTMLInputElement>("#pi-rotation")?.value.trim() ?? "";
    const limit = rotationText ? { rotation_deg: Number(rotationText) } : { ductility };
    responseMessage.className = "muted";
    responseMessage.textContent = "Asking /v1/response and /v1/pi…";
    try {
      const charge = { charge_kg: query.charge_kg, distance_m: query.distance_m, explosive: query.explosive,
                       burst: query.burst, angle_deg: query.angle_deg };
      const [response, pi] = await Promise.all([
        client.response({ element, charge }, { signal: controller.signal }),
        client.pressureImpulse({ element, ...limit }, { signal: controller.signal }),
      ]);
      if (controller.signal.aborted) return;
      const rows: [string, string, string][] = [
        ["Peak displacement", num(response.peak_displacement_m * 1e3, 4), "mm"],
        ["Time to peak", num(response.time_to_peak_ms, 4), "ms"],
        ["Ductility μ", response.ductility === null ? "–" : num(response.ductility, 3), ""],
        ["Support rotation θ", response.support_rotation_deg === null ? "–" : num(response.support_rotation_deg, 3), "°"],
        ["Damage", response.damage ?? "(no limits in the element)", response.limits ?? ""],
        ["Natural period T", num(response.natural_period_ms, 4), "ms"],
      ];
      mount(responseSummary, h("table", { class: "kv", id: "response-values" }, h("tbody", null, rows.map(([label, value, unit]) =>
        h("tr", { "data-field": label }, h("th", null, label), h("td", { class: "num" }, value), h("td", { class: "unit" }, unit))))));
      const history = response.history;
      mount(responsePlots,
        linePlot({ id: "plot-displacement", title: "Displacement history", xLabel: "time since detonation (ms)",
                   yLabel: "displacement (mm)",
                   series: [{ name: "midspan", cls: "displacement",
                              points: (history?.time_ms ?? []).map((t, i): [number, number] => [t, (history?.displacement_m[i] ?? 0) * 1e3]) }] }),
        logLogPlot({ id: "plot-pi", title: `P–I curve, limit ${num(pi.displacement_limit_m * 1e3)} mm`, xLabel: "impulse (kPa·ms)",
                     yLabel: "kPa", xUnit: "kPa·ms",
                     points: pi.points.map((p): PlotPoint => ({ x: p.impulse_kpa_ms, y: p.peak_pressure_kpa, valid: true })),
                     hlines: [{ y: pi.quasi_static_asymptote_kpa, id: "pi-quasi-static" }],
                     vlines: [{ x: pi.impulsive_asymptote_kpa_ms, id: "pi-impulsive" }],
                     dots: [{ x: blast.reflected_impulse_kpa_ms, y: blast.reflected_overpressure_kpa, id: "pi-charge",
                              label: `${num(query.charge_kg)} kg at ${num(query.distance_m)} m` }] }));
      responseMessage.textContent = `Peak ${num(response.peak_displacement_m * 1e3)} mm; ` +
        `the charge is ${above(pi.points, blast) ? "above" : "below"} the P–I curve.`;
    } catch (error) {
      if (isAbort(error)) return;
      responseMessage.className = "error";
      responseMessage.textContent = error instanceof ProblemError && error.pointerErrors.length
        ? error.pointerErrors.map((e) => `${e.pointer}: ${e.detail}`).join("; ")
        : describe(error);
    }
  }

  await compute();
  select(q.get("tab") === "response" ? "tab-response" : "tab-blast",
         q.get("tab") === "response" ? responseSection : blastSection);
};

/** Whether the charge's (impulse, pressure) lies beyond the curve: above it at its impulse. */
function above(points: { impulse_kpa_ms: number; peak_pressure_kpa: number }[], blast: Blast): boolean {
  const i = blast.reflected_impulse_kpa_ms, p = blast.reflected_overpressure_kpa;
  const sorted = [...points].sort((a, b) => a.impulse_kpa_ms - b.impulse_kpa_ms);
  if (!sorted.length || i < sorted[0]!.impulse_kpa_ms) return false;
  for (let k = 1; k < sorted.length; k++) {
    const a = sorted[k - 1]!, b = sorted[k]!;
    if (i <= b.impulse_kpa_ms) {
      const u = Math.log(i / a.impulse_kpa_ms) / Math.log(b.impulse_kpa_ms / a.impulse_kpa_ms);
      return p > a.peak_pressure_kpa * (b.peak_pressure_kpa / a.peak_pressure_kpa) ** u;
    }
  }
  return p > sorted.at(-1)!.peak_pressure_kpa;
}
