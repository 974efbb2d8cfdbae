// A log-log line plot drawn as SVG: decade grid lines, labelled decades, the curve as one path
// (points outside the fits' validity range dashed), a marker at one chosen x.
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
  const xs = points.map((p) => p.x), ys = points.map((p) => p.y);
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
      s("title", null, `${num(p.x)} m: ${num(p.y)} ${spec.yLabel}`))),
    marker !== undefined ? s("line", { class: "marker", x1: px(marker), x2: px(marker), y1: M.top, y2: H - M.bottom }) : null,
    s("text", { class: "axis-label", x: (M.left + W - M.right) / 2, y: H - 8, "text-anchor": "middle" }, spec.xLabel),
    s("text", { class: "axis-label", x: 14, y: (M.top + H - M.bottom) / 2, "text-anchor": "middle",
                transform: `rotate(-90 14 ${(M.top + H - M.bottom) / 2})` }, spec.yLabel));
}
