#!/usr/bin/env node
// CTest contract.lint: lints api/openapi.yaml with Redocly (rules: redocly.yaml beside this file,
// targeted ignores with their reasons: .redocly.lint-ignore.yaml) and fails on any error OR
// warning - `redocly lint` itself exits 0 when there are only warnings. Exits 2 when Redocly is not
// installed (`npm ci --prefix tests/contract`).
//
//   node lint.mjs [SPEC]          (default ../../api/openapi.yaml)
import { spawnSync } from "node:child_process";
import fs from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";

const here = path.dirname(fileURLToPath(import.meta.url));
const spec = path.resolve(process.argv[2] ?? path.join(here, "..", "..", "api", "openapi.yaml"));
const cli = path.join(here, "node_modules", "@redocly", "cli", "bin", "cli.js");
if (!fs.existsSync(cli)) {
  console.error("contract.lint cannot run: @redocly/cli is not installed. " +
                "Run `npm ci --prefix tests/contract` from the repository root.");
  process.exit(2);
}

const run = spawnSync(process.execPath,
                      [cli, "lint", "--config", path.join(here, "redocly.yaml"), "--format=json",
                       path.relative(here, spec)],
                      { cwd: here, encoding: "utf8", maxBuffer: 64 << 20,
                        env: { ...process.env, REDOCLY_TELEMETRY: "off", REDOCLY_SUPPRESS_UPDATE_NOTICE: "true" } });
let report;
try {
  report = JSON.parse(run.stdout);
} catch {
  console.error(`contract.lint: redocly lint printed no JSON report (exit ${run.status}):\n${run.stdout}\n${run.stderr}`);
  process.exit(1);
}
const { errors, warnings, ignored } = report.totals;
for (const problem of report.problems) {
  const where = (problem.location ?? []).map((l) => l.pointer).join(", ");
  console.log(`${problem.severity} [${problem.ruleId}] ${where}: ${problem.message}`);
}
console.log(`redocly ${report.version} lint ${path.relative(process.cwd(), spec)}: ` +
            `${errors} error(s), ${warnings} warning(s), ${ignored} ignored (see .redocly.lint-ignore.yaml)`);
if (errors + warnings > 0 || run.status !== 0) {
  console.log(`contract.lint: the spec must lint with no error and no warning (redocly exit ${run.status})`);
  console.log("0 passed, 1 failed");
  process.exit(1);
}
console.log("1 passed, 0 failed");
