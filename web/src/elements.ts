// The example structural elements (scenes/elements/*.json, docs/response.md), bundled at build
// time as the response tab's templates.
import type { Element } from "./api";

const files = import.meta.glob<Element>("../../scenes/elements/*.json", { eager: true, import: "default" });

export const elementTemplates: { name: string; element: Element }[] = Object.entries(files)
  .map(([path, element]) => ({ name: path.replace(/^.*\//, "").replace(/\.json$/, ""), element }))
  .sort((a, b) => a.name.localeCompare(b.name));
