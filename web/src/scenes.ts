// The example scenes (scenes/*.json), bundled at build time as the new-job form's templates.
import type { Scene } from "./api";

const files = import.meta.glob<Scene>("../../scenes/*.json", { eager: true, import: "default" });

export const templates: { name: string; scene: Scene }[] = Object.entries(files)
  .map(([path, scene]) => ({ name: path.replace(/^.*\//, "").replace(/\.json$/, ""), scene }))
  .sort((a, b) => a.name.localeCompare(b.name));
