// Plots drawn as SVG. logLogPlot: decade grid lines, labelled decades, the curve as one path
// (points outside the fits' validity range dashed), a marker at one chosen x, and optionally
// reference lines (asymptotes) and labelled dots. linePlot: linear axes with "nice" ticks and
// several named series (pressure-time pulses, displacement histories).
import { s } from "./dom";
import { num } from "./format";

export interface PlotPoint { x: number; y: number; valid: boolean }

export interface PlotSpec {
  id: string;
  title: string;
  xLabel: string;
  yLabel: string;
  points: PlotPoint[];
  marker?: number;
  /** Unit of x in the points' tooltips (default "m"). */
  xUnit?: string;
  /** Horizontal (y) and vertical (x) reference lines, drawn dashed. */
  hlines?: { y: number; id: string }[];
  vlines?: { x: number; id: string }[];
  /** Labelled dots, kept inside the axes' range. */
  dots?: { x: number; y: number; id: string; label: string }[];
}

const W = 380, H = 280;
const M = { left: 58, right: 14, top: 28, bottom: 42 };

const decades = (lo: number, hi: number): number[] => {
  const out: number[] = [];
  for (let e = Math.floor(Math.log10(lo)); e <= Math.ceil(Math.log10(hi)); e++) out.push(e);
  return out;
};

export function logLogPlot(spec: PlotSpec): SVGSVGElement {
  const points = spec.points.filter((p) => p.x > 0 && p.y > 0 && Number.isFinite(p.y));
  const dots = (spec.dots ?? []).filter((d) => d.x > 0 && d.y > 0 && Number.isFinite(d.x) && Number.isFinite(d.y));
  const xs = [...points.map((p) => p.x), ...dots.map((d) => d.x), ...(spec.vlines ?? []).map((l) => l.x)];
  const ys = [...points.map((p) => p.y), ...dots.map((d) => d.y), ...(spec.hlines ?? []).map((l) => l.y)];
  const [x0, x1] = [Math.min(...xs), Math.max(...xs)];
  let [y0, y1] = [Math.min(...ys), Math.max(...ys)];
  if (!(y1 > y0)) { y0 /= 2; y1 *= 2; }
  const lx0 = Math.log10(x0), lx1 = Math.log10(x1);
  const ly0 = Math.log10(y0) - 0.05 * (Math.log10(y1) - Math.log10(y0));
  const ly1 = Math.log10(y1) + 0.05 * (Math.log10(y1) - Math.log10(y0));
  const px = (x: number) => M.left + ((Math.log10(x) - lx0) / (lx1 - lx0 || 1)) * (W - M.left - M.right);
  const py = (y: number) => H - M.bottom - ((Math.log10(y) - ly0) / (ly1 - ly0 || 1)) * (H - M.top - M.bottom);

  const grid: SVGElement[] = [];
  for (const e of decades(x0, x1)) {
    for (let k = 1; k < 10; k++) {
      const x = k * 10 ** e;
      if (x < x0 * 0.999 || x > x1 * 1.001) continue;
      grid.push(s("line", { class: k === 1 ? "grid major" : "grid", x1: px(x), x2: px(x), y1: M.top, y2: H - M.bottom }));
      if (k === 1) grid.push(s("text", { class: "tick", x: px(x), y: H - M.bottom + 14, "text-anchor": "middle" }, num(x)));
    }
  }
  for (const e of decades(10 ** ly0, 10 ** ly1)) {
    for (let k = 1; k < 10; k++) {
      const y = k * 10 ** e;
      if (Math.log10(y) < ly0 || Math.log10(y) > ly1) continue;
      grid.push(s("line", { class: k === 1 ? "grid major" : "grid", x1: M.left, x2: W - M.right, y1: py(y), y2: py(y) }));
      if (k === 1) grid.push(s("text", { class: "tick", x: M.left - 5, y: py(y) + 4, "text-anchor": "end" }, num(y)));
    }
  }

  // Valid and out-of-range stretches as two paths; a segment is valid when both ends are.
  let valid = "", invalid = "";
  for (let i = 1; i < points.length; i++) {
    const a = points[i - 1]!, b = points[i]!;
    const seg = `M${px(a.x).toFixed(1)},${py(a.y).toFixed(1)}L${px(b.x).toFixed(1)},${py(b.y).toFixed(1)}`;
    if (a.valid && b.valid) valid += seg; else invalid += seg;
  }

  const marker = spec.marker !== undefined && spec.marker >= x0 && spec.marker <= x1 ? spec.marker : undefined;
  return s("svg", { class: "plot", id: spec.id, viewBox: `0 0 ${W} ${H}`, width: W, height: H, role: "img",
                    "aria-label": `${spec.title}, log-log`, "data-points": points.length },
    s("text", { class: "title", x: M.left, y: 18 }, spec.title),
    grid,
    s("rect", { class: "frame", x: M.left, y: M.top, width: W - M.left - M.right, height: H - M.top - M.bottom }),
    s("path", { class: "curve", d: valid, "data-points": points.filter((p) => p.valid).length }),
    invalid ? s("path", { class: "curve out-of-range", d: invalid }) : null,
    points.map((p) => s("circle", { class: p.valid ? "point" : "point out-of-range", cx: px(p.x), cy: py(p.y), r: 1.8 },
      s("title", null, `${num(p.x)} ${spec.xUnit ?? "m"}: ${num(p.y)} ${spec.yLabel}`))),
    (spec.hlines ?? []).map((l) => s("line", { class: "reference", id: l.id, x1: M.left, x2: W - M.right, y1: py(l.y), y2: py(l.y) })),
    (spec.vlines ?? []).map((l) => s("line", { class: "reference", id: l.id, x1: px(l.x), x2: px(l.x), y1: M.top, y2: H - M.bottom })),
    dots.map((d) => s("g", { class: "dot", id: d.id },
      s("circle", { cx: px(d.x), cy: py(d.y), r: 4.5 }),
      s("text", { x: px(d.x) + 7, y: py(d.y) - 6 }, d.label),
      s("title", null, `${d.label}: ${num(d.x)} ${spec.xUnit ?? "m"}, ${num(d.y)} ${spec.yLabel}`))),
    marker !== undefined ? s("line", { class: "marker", x1: px(marker), x2: px(marker), y1: M.top, y2: H - M.bottom }) : null,
    s("text", { class: "axis-label", x: (M.left + W - M.right) / 2, y: H - 8, "text-anchor": "middle" }, spec.xLabel),
    s("text", { class: "axis-label", x: 14, y: (M.top + H - M.bottom) / 2, "text-anchor": "middle",
                transform: `rotate(-90 14 ${(M.top + H - M.bottom) / 2})` }, spec.yLabel));
}

export interface Series { name: string; cls: string; points: [number, number][] }

export interface LineSpec {
  id: string;
  title: string;
  xLabel: string;
  yLabel: string;
  series: Series[];
}

/** Ticks at 1, 2 or 5 x 10^k covering [lo, hi], about `count` of them. */
export function niceTicks(lo: number, hi: number, count = 6): number[] {
  const span = hi - lo || Math.abs(hi) || 1;
  const raw = span / count;
  const power = 10 ** Math.floor(Math.log10(raw));
  const step = [1, 2, 5, 10].map((k) => k * power).find((k) => k >= raw) ?? 10 * power;
  const out: number[] = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) out.push(Math.abs(v) < step * 1e-9 ? 0 : v);
  return out;
}

export function linePlot(spec: LineSpec): SVGSVGElement {
  const all = spec.series.flatMap((series) => series.points).filter(([x, y]) => Number.isFinite(x) && Number.isFinite(y));
  const xs = all.map(([x]) => x), ys = all.map(([, y]) => y);
  const x0 = Math.min(...xs), x1 = Math.max(...xs);
  let y0 = Math.min(0, ...ys), y1 = Math.max(...ys);
  if (!(y1 > y0)) y1 = y0 + 1;
  const pad = 0.05 * (y1 - y0);
  y0 -= y0 < 0 ? pad : 0;
  y1 += pad;
  const px = (x: number) => M.left + ((x - x0) / (x1 - x0 || 1)) * (W - M.left - M.right);
  const py = (y: number) => H - M.bottom - ((y - y0) / (y1 - y0 || 1)) * (H - M.top - M.bottom);
  const grid: SVGElement[] = [];
  for (const x of niceTicks(x0, x1)) {
    grid.push(s("line", { class: "grid major", x1: px(x), x2: px(x), y1: M.top, y2: H - M.bottom }));
    grid.push(s("text", { class: "tick", x: px(x), y: H - M.bottom + 14, "text-anchor": "middle" }, num(x)));
  }
  for (const y of niceTicks(y0, y1, 5)) {
    grid.push(s("line", { class: y === 0 ? "grid zero" : "grid major", x1: M.left, x2: W - M.right, y1: py(y), y2: py(y) }));
    grid.push(s("text", { class: "tick", x: M.left - 5, y: py(y) + 4, "text-anchor": "end" }, num(y)));
  }
  const path = (points: [number, number][]) =>
    points.map(([x, y], i) => `${i ? "L" : "M"}${px(x).toFixed(1)},${py(y).toFixed(1)}`).join("");
  return s("svg", { class: "plot", id: spec.id, viewBox: `0 0 ${W} ${H}`, width: W, height: H, role: "img",
                    "aria-label": spec.title, "data-series": spec.series.length },
    s("text", { class: "title", x: M.left, y: 18 }, spec.title),
    grid,
    s("rect", { class: "frame", x: M.left, y: M.top, width: W - M.left - M.right, height: H - M.top - M.bottom }),
    spec.series.map((series) => s("path", { class: `series ${series.cls}`, d: path(series.points),
                                           "data-name": series.name, "data-points": series.points.length })),
    spec.series.map((series, i) => s("text", { class: `legend ${series.cls}`, x: W - M.right - 6, y: M.top + 14 + 14 * i,
                                               "text-anchor": "end" }, series.name)),
    s("text", { class: "axis-label", x: (M.left + W - M.right) / 2, y: H - 8, "text-anchor": "middle" }, spec.xLabel),
    s("text", { class: "axis-label", x: 14, y: (M.top + H - M.bottom) / 2, "text-anchor": "middle",
                transform: `rotate(-90 14 ${(M.top + H - M.bottom) / 2})` }, spec.yLabel));
}
