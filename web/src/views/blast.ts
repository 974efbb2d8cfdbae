// #/blast: the blast calculator. For one charge, /v1/blast is asked at ~60 log-spaced distances
// and P_so, i_s and t_a are drawn against distance on log-log axes; the table gives every field
// at one distance.
import { type Blast, type BlastQuery, client, describe, type Explosive, isAbort } from "../api";
import { h, mount } from "../dom";
import { num } from "../format";
import { logLogPlot, type PlotPoint } from "../plot";
import type { View } from "../view";

const SAMPLES = 60;
const CONCURRENCY = 6;

const CURVES: { key: keyof Blast; id: string; title: string; unit: string }[] = [
  { key: "incident_overpressure_kpa", id: "plot-pso", title: "Incident overpressure P_so", unit: "kPa" },
  { key: "incident_impulse_kpa_ms", id: "plot-is", title: "Incident impulse i_s", unit: "kPa·ms" },
  { key: "arrival_time_ms", id: "plot-ta", title: "Arrival time t_a", unit: "ms" },
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
  const message = h("p", { id: "blast-message", role: "status", class: "muted" });
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
    form, message, plots, h("h2", null, "At one distance"), table);

  let running: AbortController | null = null;

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
  await compute();
};
