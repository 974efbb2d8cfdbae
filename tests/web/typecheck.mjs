#!/usr/bin/env node
// CTest web.typecheck: the TypeScript client's generated types are those of api/openapi.yaml
// today (openapi-typescript --check), and tsc (strict) accepts clients/typescript and web/.
// Exits 0 when all pass, 1 on any failure, 2 when it cannot run (packages not installed).
//
//   node typecheck.mjs [REPOSITORY_ROOT]      (npm ci in clients/typescript and in web first)
import { spawnSync } from "node:child_process";
import fs from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";

const root = path.resolve(process.argv[2] ?? path.join(path.dirname(fileURLToPath(import.meta.url)), "../.."));
const clientDir = path.join(root, "clients", "typescript");
const webDir = path.join(root, "web");
const bin = (dir, file) => path.join(dir, "node_modules", ...file.split("/"));

const tools = [bin(clientDir, "openapi-typescript/bin/cli.js"), bin(clientDir, "typescript/bin/tsc"),
               bin(webDir, "typescript/bin/tsc")];
const missing = tools.filter((tool) => !fs.existsSync(tool));
if (missing.length) {
  console.error(`web.typecheck cannot run: missing ${missing.join(", ")}\n` +
                "Install the packages: `npm ci --prefix clients/typescript && npm ci --prefix web` " +
                "from the repository root (make web does).");
  process.exit(2);
}

// The generator's flags live in clients/typescript/package.json ("generate"); the check reuses them.
const generate = JSON.parse(fs.readFileSync(path.join(clientDir, "package.json"), "utf8")).scripts.generate;
const generateArgs = generate.split(/\s+/).slice(1);

const steps = [
  { name: "clients/typescript: src/schema.d.ts matches api/openapi.yaml", cwd: clientDir,
    args: [tools[0], ...generateArgs, "--check"],
    hint: "regenerate it: npm run generate --prefix clients/typescript" },
  { name: "clients/typescript: tsc --noEmit (strict)", cwd: clientDir, args: [tools[1], "--noEmit", "-p", "."] },
  { name: "web: tsc --noEmit (strict)", cwd: webDir, args: [tools[2], "--noEmit", "-p", "."] },
];

let passed = 0, failed = 0;
for (const step of steps) {
  const t0 = Date.now();
  const run = spawnSync(process.execPath, step.args, { cwd: step.cwd, encoding: "utf8" });
  const output = `${run.stdout ?? ""}${run.stderr ?? ""}`.trim();
  if (run.status === 0) {
    passed++;
    console.log(`PASS ${step.name} (${((Date.now() - t0) / 1000).toFixed(1)} s)`);
  } else {
    failed++;
    console.log(`FAIL ${step.name}${step.hint ? ` - ${step.hint}` : ""}\n${output}`);
  }
}
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
